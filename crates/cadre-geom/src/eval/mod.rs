//! Evaluation of curves and surfaces: points, derivatives, normals, domains and periods.

pub mod curve;
pub mod surface;

/// `(a1, b1)` for an interval given as the two trimming values of a possibly periodic
/// parameter: when `period` is set and `b < a` the interval wraps, ending at the first value
/// `≡ b (mod period)` after `a` (ISO 10303-42's reading of trimmed periodic entities);
/// otherwise the values are just ordered.
pub(crate) fn wrapped_range(a: f64, b: f64, period: Option<f64>) -> (f64, f64) {
    match period {
        Some(p) if b < a && p > 0.0 => {
            let mut e = a + (b - a).rem_euclid(p);
            if e <= a {
                e += p;
            }
            (a, e)
        }
        _ => (a.min(b), a.max(b)),
    }
}
