//! Tight axis-aligned bounding boxes of curve arcs and surface patches.
//!
//! Analytic entities get exact boxes from the closed-form extrema of each coordinate; the
//! others get the box of samples plus every coordinate extremum located by root-finding on
//! the derivative (sign changes between samples, refined by safeguarded Newton). The
//! sampled boxes are therefore made of true curve/surface points: never larger than the
//! exact box, and smaller only by an extremum hidden between two samples that cancel out,
//! which the per-knot-span sampling makes negligible.

mod curve;
mod surface;

use std::f64::consts::{FRAC_PI_4, PI, TAU};

/// Parameters in `[t0, t1]` where `a cos t + b sin t` is extreme (`t* = atan2(b, a)` and
/// `t* + π`, shifted by whole periods). For ranges of a period or more both are returned,
/// possibly outside the range: the function is periodic, so their values are attained.
pub(crate) fn sinusoid_critical(a: f64, b: f64, t0: f64, t1: f64, out: &mut Vec<f64>) {
    if (a == 0.0 && b == 0.0) || !(t0.is_finite() && t1.is_finite()) {
        return;
    }
    let ts = b.atan2(a);
    if t1 - t0 >= TAU {
        out.extend([ts, ts + PI]);
        return;
    }
    let kmin = ((t0 - ts) / PI).ceil() as i64;
    let kmax = ((t1 - ts) / PI).floor() as i64;
    for k in kmin..=kmax {
        out.push(ts + k as f64 * PI);
    }
}

/// Adds the multiples of π/4 strictly inside `(t0, t1)` to `out`, so that samplers never
/// take a step longer than an eighth of a turn on angular parameters.
pub(crate) fn angular_breaks(t0: f64, t1: f64, out: &mut Vec<f64>) {
    if !(t0.is_finite() && t1.is_finite()) || t1 - t0 > 64.0 * TAU {
        return;
    }
    let mut k = (t0 / FRAC_PI_4).floor() + 1.0;
    while k * FRAC_PI_4 < t1 {
        out.push(k * FRAC_PI_4);
        k += 1.0;
    }
}

/// Sorted sample parameters over `[t0, t1]`: the range ends, the `breaks` and `per_piece`
/// evenly spaced samples in each piece; at most about `max_total` in all (falling back to
/// uniform sampling when there are too many breaks).
pub(crate) fn sample_params(
    t0: f64,
    t1: f64,
    breaks: &[f64],
    per_piece: usize,
    max_total: usize,
) -> Vec<f64> {
    let pieces = sample_pieces(t0, t1, breaks, per_piece, max_total);
    let mut out: Vec<f64> = Vec::with_capacity(pieces.iter().map(Vec::len).sum());
    for piece in pieces {
        // Consecutive pieces share their end sample.
        let skip = usize::from(out.last().is_some_and(|l| Some(l) == piece.first()));
        out.extend_from_slice(&piece[skip..]);
    }
    out
}

/// The samples of [`sample_params`] grouped by smooth piece (between consecutive breaks),
/// each piece including both its ends; a single uniform piece when there are too many
/// breaks.
pub(crate) fn sample_pieces(
    t0: f64,
    t1: f64,
    breaks: &[f64],
    per_piece: usize,
    max_total: usize,
) -> Vec<Vec<f64>> {
    let mut knots: Vec<f64> = Vec::with_capacity(breaks.len() + 2);
    knots.push(t0);
    knots.extend(breaks.iter().copied().filter(|&b| b > t0 && b < t1));
    knots.push(t1);
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    let pieces = knots.len() - 1;
    if pieces == 0 {
        return vec![knots];
    }
    let max_total = max_total.max(1);
    if pieces > max_total {
        return vec![
            (0..=max_total)
                .map(|i| t0 + (t1 - t0) * i as f64 / max_total as f64)
                .collect(),
        ];
    }
    let n = (max_total / pieces).clamp(1, per_piece.max(1));
    knots
        .windows(2)
        .map(|w| {
            (0..=n)
                .map(|j| {
                    if j == n {
                        w[1]
                    } else {
                        w[0] + (w[1] - w[0]) * j as f64 / n as f64
                    }
                })
                .collect()
        })
        .collect()
}

/// A root of `g` in `[a, b]` given `g(a)·g(b) < 0`: Newton steps (`g` returns value and
/// derivative) kept inside a shrinking bracket, bisection when Newton leaves it.
pub(crate) fn bracketed_root<G: Fn(f64) -> (f64, f64)>(
    g: G,
    mut a: f64,
    mut b: f64,
    ga: f64,
) -> f64 {
    let sa = ga.signum();
    let mut t = 0.5 * (a + b);
    for _ in 0..64 {
        let (gt, dg) = g(t);
        if gt == 0.0 || !gt.is_finite() {
            return t;
        }
        if gt.signum() == sa {
            a = t;
        } else {
            b = t;
        }
        let newton = t - gt / dg;
        let next = if newton.is_finite() && newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        let done = (next - t).abs() <= 1e-15 * (1.0 + t.abs()) || b - a <= 1e-15 * (1.0 + t.abs());
        t = next;
        if done {
            break;
        }
    }
    t
}

/// A maximiser of `f` on `[a, b]` by golden-section search (exact for unimodal `f`; for
/// others some local maximum, still a point of the curve, never outside the interval).
pub(crate) fn golden_max<F: Fn(f64) -> f64>(f: F, a: f64, b: f64) -> f64 {
    golden(f, a, b, 80)
}

/// A minimiser of `f` on `[a, b]` by at most `iterations` golden-section steps.
pub(crate) fn golden_min<F: Fn(f64) -> f64>(f: F, a: f64, b: f64, iterations: usize) -> f64 {
    golden(|t| -f(t), a, b, iterations)
}

fn golden<F: Fn(f64) -> f64>(f: F, mut a: f64, mut b: f64, iterations: usize) -> f64 {
    const R: f64 = 0.618_033_988_749_895;
    let mut c = b - R * (b - a);
    let mut d = a + R * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..iterations {
        if b - a <= 1e-14 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - R * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + R * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinusoid_critical_points() {
        let mut v = Vec::new();
        sinusoid_critical(1.0, 0.0, -0.1, 0.1, &mut v);
        assert_eq!(v, vec![0.0]);
        v.clear();
        sinusoid_critical(0.0, 1.0, 0.0, 10.0, &mut v);
        assert_eq!(v.len(), 2);
        v.clear();
        sinusoid_critical(0.0, 1.0, 0.0, 1.0, &mut v);
        assert!(v.is_empty());
    }

    #[test]
    fn root_of_cubic() {
        let r = bracketed_root(|t| (t * t * t - 2.0, 3.0 * t * t), 0.0, 2.0, -2.0);
        assert!((r - 2f64.cbrt()).abs() < 1e-14);
    }

    #[test]
    fn golden_section() {
        let t = golden_max(|t| -(t - 0.3) * (t - 0.3), -1.0, 2.0);
        assert!((t - 0.3).abs() < 1e-7);
    }

    #[test]
    fn samples_cover_range() {
        let s = sample_params(0.0, 1.0, &[0.5], 4, 100);
        assert_eq!(s.len(), 9);
        assert_eq!(s[0], 0.0);
        assert_eq!(*s.last().unwrap(), 1.0);
        let s = sample_params(
            0.0,
            1.0,
            &(1..1000).map(|i| i as f64 / 1000.0).collect::<Vec<_>>(),
            4,
            100,
        );
        assert_eq!(s.len(), 101);
    }
}
