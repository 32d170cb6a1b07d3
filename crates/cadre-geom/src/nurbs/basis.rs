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
const STACK_DEGREE: usize = 8;
const STACK_OUT: usize = 4 * (STACK_DEGREE + 1);

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
                span, t, degree, order, knots, &mut ndu, &mut a, &mut lr, &mut out,
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
                span, t, degree, order, knots, &mut ndu, &mut a, &mut lr, &mut out,
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
/// `a` two rows of `p+1`, `lr` left then right, `out` `(order+1)` rows of `p+1`.
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
    out.iter_mut().for_each(|x| *x = 0.0);
    for j in 0..=p {
        out[j] = ndu[j * w + p];
    }
    let kmax = order.min(p);
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, w);
        a.iter_mut().for_each(|x| *x = 0.0);
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
            out[k * w + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=kmax {
        for x in &mut out[k * w..(k + 1) * w] {
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
    fn binomials() {
        assert_eq!(binomial(3, 0), 1.0);
        assert_eq!(binomial(3, 1), 3.0);
        assert_eq!(binomial(4, 2), 6.0);
        assert_eq!(binomial(2, 3), 0.0);
    }
}
