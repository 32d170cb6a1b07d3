//! Trim curves approximated by quadratic Bézier pieces under separate tolerances in u and v.
//!
//! The seed's thesis interpolates each trim curve's samples with a quadratic B-spline and
//! removes knots under error control (Lyche–Mørken) with separate ε_u, ε_v; here a greedy fit
//! gives the same guarantee more directly: from each piece's start, the longest run of samples
//! that one quadratic (ends on the run's ends, control point by least squares after a few
//! reparametrisations) holds within the tolerance ellipse at every sample and at every
//! midpoint between samples. A quadratic's pieces join with C⁰ continuity at least, which is
//! all the trim test needs.

use crate::Uv;
use crate::quad::QuadPiece;

/// How far a fitted piece may stray from the samples: `u` along u, `v` along v (a point is
/// within tolerance where `(du / u)² + (dv / v)² ≤ 1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTolerance {
    /// Along u, parameter units.
    pub u: f64,
    /// Along v, parameter units.
    pub v: f64,
}

impl UvTolerance {
    /// The parameter tolerances that keep a trim within `eps` in model units on a surface
    /// whose partial derivatives reach at most `speed_u = max |∂S/∂u|` and
    /// `speed_v = max |∂S/∂v|` over the face: `eps / speed` on each axis (a step `du` moves
    /// the surface point by at most `speed_u · du`), the speeds floored so that a degenerate
    /// axis (a pole's) gets a finite tolerance.
    pub fn from_speeds(eps: f64, speed_u: f64, speed_v: f64) -> UvTolerance {
        let floor = eps * 1e-6;
        UvTolerance {
            u: eps / speed_u.max(floor),
            v: eps / speed_v.max(floor),
        }
    }

    /// `d` measured in tolerances: ≤ 1 within the tolerance ellipse.
    pub fn scaled(&self, d: Uv) -> f64 {
        Uv::new(d.x / self.u, d.y / self.v).length()
    }
}

/// Reparametrisations (each sample projected onto the piece by Newton steps, then the control
/// point fitted again) per candidate run.
const REFITS: usize = 3;

/// Quadratic pieces through `points` (one smooth trim curve's samples, in order), each within
/// `tol` of every sample it spans and of the midpoints between them; consecutive pieces share
/// their ends exactly, the first starts at the first point and the last ends at the last.
/// Fewer than two points give no piece.
pub fn fit_points(points: &[Uv], tol: UvTolerance) -> Vec<QuadPiece> {
    let mut pieces = Vec::new();
    let last = points.len().saturating_sub(1);
    let mut start = 0;
    while start < last {
        // The longest run that fits: doubling, then bisecting between what fits and what
        // does not. Two samples always fit (the straight piece between them).
        let mut good = (start + 1, QuadPiece::line(points[start], points[start + 1]));
        let mut step = 2;
        let mut bad = None;
        while good.0 < last {
            let end = (start + step).min(last);
            match fit_run(&points[start..=end], tol) {
                Some(piece) => {
                    good = (end, piece);
                    step *= 2;
                }
                None => {
                    bad = Some(end);
                    break;
                }
            }
        }
        if let Some(mut bad) = bad {
            while bad - good.0 > 1 {
                let mid = good.0 + (bad - good.0) / 2;
                match fit_run(&points[start..=mid], tol) {
                    Some(piece) => good = (mid, piece),
                    None => bad = mid,
                }
            }
        }
        pieces.push(good.1);
        start = good.0;
    }
    pieces
}

/// One quadratic through `run`'s ends within `tol` of all of it, if the fit finds one.
fn fit_run(run: &[Uv], tol: UvTolerance) -> Option<QuadPiece> {
    let (first, last) = (run[0], run[run.len() - 1]);
    if run.len() == 2 {
        return Some(QuadPiece::line(first, last));
    }
    // Chord-length parameters, in the tolerance metric (the axis that matters counts).
    let mut t: Vec<f64> = Vec::with_capacity(run.len());
    let mut total = 0.0;
    t.push(0.0);
    for pair in run.windows(2) {
        total += tol.scaled(pair[1] - pair[0]);
        t.push(total);
    }
    if total <= 0.0 {
        return Some(QuadPiece::line(first, last));
    }
    for x in &mut t {
        *x /= total;
    }
    let mut piece = QuadPiece::line(first, last);
    for round in 0..=REFITS {
        piece.p[1] = control_point(run, &t, first, last)?;
        if round < REFITS {
            for (k, p) in run.iter().enumerate().skip(1).take(run.len() - 2) {
                t[k] = project(&piece, *p, t[k], tol);
            }
        }
    }
    within(&piece, run, &t, tol).then_some(piece)
}

/// The least-squares control point of a quadratic from `first` to `last` through `run` at
/// parameters `t` (each axis on its own, so the metric's scale does not matter).
fn control_point(run: &[Uv], t: &[f64], first: Uv, last: Uv) -> Option<Uv> {
    let mut numerator = Uv::ZERO;
    let mut denominator = 0.0;
    for (p, &t) in run.iter().zip(t) {
        let s = 1.0 - t;
        let b1 = 2.0 * s * t;
        numerator += b1 * (*p - s * s * first - t * t * last);
        denominator += b1 * b1;
    }
    (denominator > 0.0).then(|| numerator / denominator)
}

/// `t0` moved by a few Newton steps towards the parameter of the piece's point nearest `p`
/// (in the tolerance metric), kept in [0, 1].
fn project(piece: &QuadPiece, p: Uv, t0: f64, tol: UvTolerance) -> f64 {
    let w = Uv::new(1.0 / (tol.u * tol.u), 1.0 / (tol.v * tol.v));
    let second = 2.0 * (piece.p[0] - 2.0 * piece.p[1] + piece.p[2]);
    let mut t = t0;
    for _ in 0..3 {
        let d = piece.eval(t) - p;
        let d1 = piece.derivative(t);
        let g = (d * d1 * w).element_sum();
        let h = (d1 * d1 * w).element_sum() + (d * second * w).element_sum();
        if h <= 0.0 {
            break;
        }
        t = (t - g / h).clamp(0.0, 1.0);
    }
    t
}

/// Whether the piece holds every sample of `run` (at its parameter) and every midpoint
/// between two samples (at the mean parameter) within `tol`: the distances measured to points
/// of the piece, so at least the distances to the piece itself.
fn within(piece: &QuadPiece, run: &[Uv], t: &[f64], tol: UvTolerance) -> bool {
    let at_samples = run
        .iter()
        .zip(t)
        .all(|(p, &t)| tol.scaled(piece.eval(t) - *p) <= 1.0);
    at_samples
        && run.windows(2).zip(t.windows(2)).all(|(p, t)| {
            let mid = 0.5 * (p[0] + p[1]);
            tol.scaled(piece.eval(0.5 * (t[0] + t[1])) - mid) <= 1.0
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Collinear samples give one straight piece; a corner splits the fit.
    #[test]
    fn a_line_is_one_piece_and_a_corner_two() {
        let tol = UvTolerance { u: 1e-3, v: 1e-3 };
        let line: Vec<Uv> = (0..50).map(|k| Uv::new(f64::from(k), 0.5)).collect();
        let pieces = fit_points(&line, tol);
        assert_eq!(pieces.len(), 1);
        let corner: Vec<Uv> = (0..20)
            .map(|k| Uv::new(f64::from(k), 0.0))
            .chain((1..20).map(|k| Uv::new(19.0, f64::from(k))))
            .collect();
        assert_eq!(fit_points(&corner, tol).len(), 2);
    }

    /// The tolerance per axis: a tighter v needs more pieces for the same curve.
    #[test]
    fn a_tighter_axis_needs_more_pieces() {
        let arc: Vec<Uv> = (0..=400)
            .map(|k| {
                let a = f64::from(k) / 400.0 * std::f64::consts::PI;
                Uv::new(a.cos(), a.sin())
            })
            .collect();
        let loose = fit_points(&arc, UvTolerance { u: 1e-3, v: 1e-3 }).len();
        let tight_v = fit_points(&arc, UvTolerance { u: 1e-3, v: 1e-5 }).len();
        assert!(tight_v > loose, "{tight_v} pieces against {loose}");
    }
}
