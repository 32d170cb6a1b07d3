//! Point inversion: the parameters of the point of a curve or surface closest to a given
//! point.
//!
//! Analytic entities use closed forms. The others minimise the squared distance by Newton's
//! method (exact Hessian when it is positive definite, Gauss–Newton otherwise, with a
//! backtracking line search and clamping to the domain), started from the best points of a
//! coarse sampling and from the caller's hint.
//!
//! Periodic parameters are returned in the domain's first period, or, when a hint is given,
//! shifted by whole periods to be nearest the hint, so a caller walking along an edge gets
//! continuous parameters across a seam.

mod curve;
mod newton;
mod surface;
mod valley;

/// Shifts a periodic parameter `t` by whole periods: nearest to `hint` when given, else into
/// `[start, start + period)`.
pub(crate) fn wrap(t: f64, period: Option<f64>, start: f64, hint: Option<f64>) -> f64 {
    let Some(p) = period.filter(|p| *p > 0.0 && t.is_finite()) else {
        return t;
    };
    match hint.filter(|h| h.is_finite()) {
        Some(h) => t + ((h - t) / p).round() * p,
        None => {
            let s = if start.is_finite() { start } else { 0.0 };
            let w = s + (t - s).rem_euclid(p);
            // rem_euclid may round up to exactly one period.
            if w >= s + p { s } else { w }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::wrap;
    use std::f64::consts::TAU;

    #[test]
    fn wrapping() {
        assert_eq!(wrap(-1.0, Some(TAU), 0.0, None), TAU - 1.0);
        assert!((wrap(0.1, Some(TAU), 0.0, Some(6.2)) - (0.1 + TAU)).abs() < 1e-15);
        assert_eq!(wrap(5.0, None, 0.0, Some(100.0)), 5.0);
        assert_eq!(wrap(-1e-18, Some(TAU), 0.0, None), 0.0);
    }
}
