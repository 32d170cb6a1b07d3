//! B-spline basis functions and derivatives (Piegl & Tiller, *The NURBS Book*, A2.1 & A2.3).

/// The knot span `i` (`knots[i] < knots[i+1]`, `degree ≤ i < n`) whose polynomial piece is
/// used at `t`, for a spline with `n` control points.
///
/// Parameters outside the domain use the first or last non-empty span, so evaluation there
/// extends the end pieces polynomially: Newton iterations that step slightly outside stay
/// smooth. Requires `knots[degree] < knots[n]` (checked by the constructors).
pub fn find_span(knots: &[f64], n: usize, degree: usize, t: f64) -> usize {
    let first_nonempty = || {
        (degree..n)
            .find(|&i| knots[i] < knots[i + 1])
            .unwrap_or(degree)
    };
    // NaN goes to the first span too, so evaluation returns NaN rather than panicking.
    if t.is_nan() || t <= knots[degree] {
        return first_nonempty();
    }
    if t >= knots[n] {
        return (degree..n)
            .rev()
            .find(|&i| knots[i] < knots[i + 1])
            .unwrap_or(n - 1);
    }
    // Largest i with knots[i] ≤ t; since knots[degree] < t < knots[n] it lies in
    // [degree, n-1] and knots[i+1] > t, so the span is not empty.
    let i = knots[..n].partition_point(|&k| k <= t) - 1;
    i.clamp(degree, n - 1)
}

/// Non-zero basis functions and their derivatives at `t` on `span`: `ders[k][j]` is the
/// `k`-th derivative of `N_{span−degree+j}`. Derivatives above the degree are zero.
pub fn ders_basis_funs(
    span: usize,
    t: f64,
    degree: usize,
    order: usize,
    knots: &[f64],
) -> Vec<Vec<f64>> {
    let b = BasisDers::new(span, t, degree, order, knots);
    (0..=order).map(|k| b.row(k).to_vec()).collect()
}

/// Largest degree evaluated with stack-only scratch space (no allocation); higher degrees
/// fall back to the heap.
pub const STACK_DEGREE: usize = 8;
const STACK_OUT: usize = 4 * (STACK_DEGREE + 1);

/// The `degree + 1` basis functions non-zero on `span`, at `t`, into `out[..=degree]`
/// (*The NURBS Book* A2.2); `None` above [`STACK_DEGREE`].
///
/// Point evaluation needs only these: running the derivative algorithm A2.3 for them, with
/// its `(p+1)²` table zero-filled on every call, was the largest item of `cadre info`'s
/// profile on a 24 MB assembly (basis core 36 %, memset 13.5 %). The arithmetic is the
/// same as A2.3's order-0 row, so the values agree bit for bit.
pub fn basis_funs(
    span: usize,
    t: f64,
    degree: usize,
    knots: &[f64],
) -> Option<[f64; STACK_DEGREE + 1]> {
    // One instance per degree: with the degree known at compile time the triangle is fully
    // unrolled and kept in registers (bench `curve_eval_poly_x1000`: 69.5 µs with the
    // degree-generic loop, 58.0 µs like this; the rest is division latency).
    match degree {
        1 => Some(basis_funs_d::<1>(span, t, knots)),
        2 => Some(basis_funs_d::<2>(span, t, knots)),
        3 => Some(basis_funs_d::<3>(span, t, knots)),
        4 => Some(basis_funs_d::<4>(span, t, knots)),
        5 => Some(basis_funs_d::<5>(span, t, knots)),
        6 => Some(basis_funs_d::<6>(span, t, knots)),
        7 => Some(basis_funs_d::<7>(span, t, knots)),
        8 => Some(basis_funs_d::<8>(span, t, knots)),
        _ => None,
    }
}

/// [`basis_funs`] for degree `D` (≤ [`STACK_DEGREE`]), in the same operation order.
#[inline(always)]
fn basis_funs_d<const D: usize>(span: usize, t: f64, knots: &[f64]) -> [f64; STACK_DEGREE + 1] {
    let mut n = [0.0; STACK_DEGREE + 1];
    let mut left = [0.0; STACK_DEGREE + 1];
    let mut right = [0.0; STACK_DEGREE + 1];
    // One bounds check for all the knots read below.
    let k = &knots[span + 1 - D..=span + D];
    n[0] = 1.0;
    for j in 1..=D {
        left[j] = t - k[D - j];
        right[j] = k[D - 1 + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = n[r] / (right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

/// Rows `0..=order` (`order ≤ 3`) of basis derivatives, as [`ders_basis_funs`], for
/// `degree < W`: row `k` is `result[k][..=degree]`, rows above `order` are zero.
///
/// The scratch tables are sized by `W` rather than by [`STACK_DEGREE`], so for the common
/// cubic case (`W = 4`) nothing larger than 16 values is initialised per call instead of
/// the ~150 that made `memset` 13.5 % of the `cadre info` profile.
///
/// # Panics
///
/// If `degree ≥ W` or `order > 3`.
pub fn ders_rows<const W: usize>(
    span: usize,
    t: f64,
    degree: usize,
    order: usize,
    knots: &[f64],
) -> [[f64; W]; 4] {
    assert!(degree < W && order <= 3);
    let w = degree + 1;
    let mut ndu = [[0.0; W]; W];
    let mut a = [[0.0; W]; 2];
    let mut lr = [[0.0; W]; 2];
    let mut out = [[0.0; W]; 4];
    basis_core(
        span,
        t,
        degree,
        order,
        knots,
        &mut ndu.as_flattened_mut()[..w * w],
        &mut a.as_flattened_mut()[..2 * w],
        &mut lr.as_flattened_mut()[..2 * w],
        out.as_flattened_mut(),
        W,
    );
    out
}

/// Basis function derivatives as computed by [`ders_basis_funs`], stored flat, and on the
/// stack for the usual degrees and orders (evaluation is the inner loop of bounds and
/// inversion, where allocation dominated).
pub struct BasisDers {
    width: usize,
    buf: Buf,
}

// The large variant is the point: it keeps the common case off the heap.
#[allow(clippy::large_enum_variant)]
enum Buf {
    Stack([f64; STACK_OUT]),
    Heap(Vec<f64>),
}

impl BasisDers {
    /// Evaluates the derivatives up to `order` of the `degree + 1` basis functions that are
    /// non-zero on `span`, at `t`.
    pub fn new(span: usize, t: f64, degree: usize, order: usize, knots: &[f64]) -> Self {
        let width = degree + 1;
        if degree <= STACK_DEGREE && (order + 1) * width <= STACK_OUT {
            let mut ndu = [0.0; (STACK_DEGREE + 1) * (STACK_DEGREE + 1)];
            let mut a = [0.0; 2 * (STACK_DEGREE + 1)];
            let mut lr = [0.0; 2 * (STACK_DEGREE + 1)];
            let mut out = [0.0; STACK_OUT];
            basis_core(
                span,
                t,
                degree,
                order,
                knots,
                &mut ndu[..width * width],
                &mut a[..2 * width],
                &mut lr[..2 * width],
                &mut out[..(order + 1) * width],
                width,
            );
            BasisDers {
                width,
                buf: Buf::Stack(out),
            }
        } else {
            let mut ndu = vec![0.0; width * width];
            let mut a = vec![0.0; 2 * width];
            let mut lr = vec![0.0; 2 * width];
            let mut out = vec![0.0; (order + 1) * width];
            basis_core(
                span, t, degree, order, knots, &mut ndu, &mut a, &mut lr, &mut out, width,
            );
            BasisDers {
                width,
                buf: Buf::Heap(out),
            }
        }
    }

    /// The `k`-th derivatives of the non-zero basis functions.
    pub fn row(&self, k: usize) -> &[f64] {
        let data: &[f64] = match &self.buf {
            Buf::Stack(a) => a,
            Buf::Heap(v) => v,
        };
        &data[k * self.width..(k + 1) * self.width]
    }
}

/// *The NURBS Book* A2.3 on flat scratch buffers: `ndu` is `(p+1)²` (row `j` at `j·(p+1)`),
/// `a` two rows of `p+1`, `lr` left then right, `out` rows of `p+1` values `stride` apart
/// (rows `0..=order` are written; the rest of `out` is left alone).
#[allow(clippy::too_many_arguments)]
fn basis_core(
    span: usize,
    t: f64,
    p: usize,
    order: usize,
    knots: &[f64],
    ndu: &mut [f64],
    a: &mut [f64],
    lr: &mut [f64],
    out: &mut [f64],
    stride: usize,
) {
    let w = p + 1;
    let (left, right) = lr.split_at_mut(w);
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences (never zero on a non-empty span).
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + j - 1] / ndu[j * w + r];
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
    for j in 0..=p {
        out[j] = ndu[j * w + p];
    }
    let kmax = order.min(p);
    // Derivative rows above the degree vanish.
    for k in (kmax + 1)..=order {
        out[k * stride..k * stride + w].fill(0.0);
    }
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, w);
        a.fill(0.0);
        a[0] = 1.0;
        for k in 1..=kmax {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rku = rk as usize;
                a[s2] = a[s1] / ndu[(pk + 1) * w + rku];
                d = a[s2] * ndu[rku * w + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2 + j] = (a[s1 + j] - a[s1 + j - 1]) / ndu[(pk + 1) * w + idx];
                d += a[s2 + j] * ndu[idx * w + pk];
            }
            if r <= pk {
                a[s2 + k] = -a[s1 + k - 1] / ndu[(pk + 1) * w + r];
                d += a[s2 + k] * ndu[r * w + pk];
            }
            out[k * stride + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=kmax {
        for x in &mut out[k * stride..k * stride + w] {
            *x *= factor;
        }
        factor *= (p - k) as f64;
    }
}

/// Binomial coefficient `C(n, k)` as `f64` (small arguments only: derivative orders).
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_zero_derivative_sum() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.3, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0];
        let n = knots.len() - 4;
        for i in 0..=50 {
            let t = i as f64 / 50.0;
            let span = find_span(&knots, n, 3, t);
            assert!(knots[span] < knots[span + 1]);
            let d = ders_basis_funs(span, t, 3, 4, &knots);
            let s0: f64 = d[0].iter().sum();
            assert!((s0 - 1.0).abs() < 1e-14);
            for row in &d[1..] {
                assert!(row.iter().sum::<f64>().abs() < 1e-9);
            }
            assert!(d[4].iter().all(|&x| x == 0.0));
        }
    }

    #[test]
    fn span_at_ends_and_outside() {
        let knots = [0.0, 0.0, 1.0, 1.0, 1.0];
        // Degree 1, 3 points: span 2 is empty (knots[2] == knots[3]).
        assert_eq!(find_span(&knots, 3, 1, 1.0), 1);
        assert_eq!(find_span(&knots, 3, 1, 5.0), 1);
        assert_eq!(find_span(&knots, 3, 1, -5.0), 1);
        assert_eq!(find_span(&knots, 3, 1, f64::NAN), 1);
    }

    #[test]
    fn heap_path_matches_stack_path() {
        // Degree 10 exceeds the stack buffers; compare with the degree-10 Bernstein basis.
        let knots: Vec<f64> = [vec![0.0; 11], vec![1.0; 11]].concat();
        let t = 0.3;
        let d = ders_basis_funs(10, t, 10, 1, &knots);
        for (j, &b) in d[0].iter().enumerate() {
            let expected = binomial(10, j) * t.powi(j as i32) * (1.0 - t).powi(10 - j as i32);
            assert!((b - expected).abs() < 1e-14);
        }
        assert!(d[1].iter().sum::<f64>().abs() < 1e-12);
    }

    #[test]
    fn fast_paths_match_general_algorithm() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.3, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0];
        let n = knots.len() - 4;
        for i in 0..=40 {
            let t = -0.1 + 1.2 * i as f64 / 40.0;
            let span = find_span(&knots, n, 3, t);
            let general = ders_basis_funs(span, t, 3, 3, &knots);
            let n0 = basis_funs(span, t, 3, &knots).unwrap();
            assert_eq!(&n0[..4], &general[0][..]);
            let r4 = ders_rows::<4>(span, t, 3, 3, &knots);
            let r9 = ders_rows::<9>(span, t, 3, 2, &knots);
            for k in 0..=3 {
                assert_eq!(&r4[k][..4], &general[k][..]);
                if k <= 2 {
                    assert_eq!(&r9[k][..4], &general[k][..]);
                }
            }
        }
        assert!(basis_funs(10, 0.5, STACK_DEGREE + 1, &[0.0; 22]).is_none());
    }

    #[test]
    fn binomials() {
        assert_eq!(binomial(3, 0), 1.0);
        assert_eq!(binomial(3, 1), 3.0);
        assert_eq!(binomial(4, 2), 6.0);
        assert_eq!(binomial(2, 3), 0.0);
    }
}
