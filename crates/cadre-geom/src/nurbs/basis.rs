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
    let p = degree;
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences (never zero on a non-empty span).
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = vec![vec![0.0; p + 1]; order + 1];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let kmax = order.min(p);
    let mut a = [vec![0.0; p + 1], vec![0.0; p + 1]];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0].iter_mut().for_each(|x| *x = 0.0);
        a[0][0] = 1.0;
        for k in 1..=kmax {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rku = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rku];
                d = a[s2][0] * ndu[rku][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(kmax + 1).skip(1) {
        for x in row.iter_mut() {
            *x *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
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
    fn binomials() {
        assert_eq!(binomial(3, 0), 1.0);
        assert_eq!(binomial(3, 1), 3.0);
        assert_eq!(binomial(4, 2), 6.0);
        assert_eq!(binomial(2, 3), 0.0);
    }
}
