//! Trim curves approximated by quadratic Bézier pieces under separate tolerances in u and v.
//!
//! The seed's thesis interpolates each trim curve's samples with a quadratic B-spline and
//! removes knots under error control (Lyche–Mørken) with separate ε_u, ε_v; here a greedy fit
//! gives the same guarantee more directly: from each piece's start, the longest run of samples
//! that one quadratic (ends on the run's ends, control point by least squares after a few
//! reparametrisations) holds within the tolerance ellipse at every sample and at the curve's
//! point between every two samples. A quadratic's pieces join with C⁰ continuity at least,
//! which is all the trim test needs.
//!
//! The samples lie on the curve; the polyline between them does not (it cuts each bend by up
//! to the sampling's deflection). So the point between two samples is the curve's, estimated
//! by the cubic through the four samples about it at their chord-length parameters (the
//! quadratic through three at a run's ends) — within ~ε²/R of the curve where the chords'
//! sag is ε — not the chord's middle, which held the pieces to the polyline: on the corpus
//! that took 30 % more pieces for the same tolerance (BENCHMARKS.md, trim trees). Where the
//! two three-sample estimates about a gap disagree by more than a quarter of the tolerance
//! (a kink the samples straddle, or samples too sparse for the curve), the chord's middle
//! stands in: the polyline is then all that is known of the curve.

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
    let mids = curve_midpoints(points, tol);
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
            match fit_run(&points[start..=end], &mids[start..end], tol) {
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
                match fit_run(&points[start..=mid], &mids[start..mid], tol) {
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

/// The curve's point between each two consecutive samples of `points` (one fewer than
/// them), estimated from the samples about it (see the module's comment).
fn curve_midpoints(points: &[Uv], tol: UvTolerance) -> Vec<Uv> {
    let n = points.len();
    // Chord-length parameters in the tolerance metric.
    let mut t = Vec::with_capacity(n);
    let mut total = 0.0;
    for (k, p) in points.iter().enumerate() {
        if k > 0 {
            total += tol.scaled(*p - points[k - 1]);
        }
        t.push(total);
    }
    let chord = |k: usize| 0.5 * (points[k] + points[k + 1]);
    let through = |range: std::ops::Range<usize>, k: usize| {
        lagrange(&points[range.clone()], &t[range], 0.5 * (t[k] + t[k + 1]))
    };
    if n < 4 {
        // Too few samples to tell a bend from a kink: the polyline is all that is known.
        return (0..n.saturating_sub(1)).map(chord).collect();
    }
    // Inner gaps: the cubic through the four samples about it, where the two quadratics
    // through three of them agree.
    let mut mids: Vec<Uv> = (0..n - 1)
        .map(|k| {
            if k == 0 || k == n - 2 {
                return chord(k);
            }
            let (left, right) = (through(k - 1..k + 2, k), through(k..k + 3, k));
            if tol.scaled(left - right) <= 0.25 {
                through(k - 1..k + 3, k)
            } else {
                chord(k)
            }
        })
        .collect();
    // End gaps: the quadratic through the three end samples, where it bows from the chord
    // no more than the next gap's estimate does (by half again, and a quarter tolerance):
    // the curve bends alike over neighbouring gaps, a kink at the end does not.
    for (k, next, range) in [(0, 1, 0..3), (n - 2, n - 3, n - 3..n)] {
        let estimate = through(range, k);
        let bow_next = tol.scaled(mids[next] - chord(next));
        if tol.scaled(estimate - chord(k)) <= 1.5 * bow_next + 0.25 {
            mids[k] = estimate;
        }
    }
    mids
}

/// The polynomial through `points` at parameters `t` (Lagrange's form), at `at`.
fn lagrange(points: &[Uv], t: &[f64], at: f64) -> Uv {
    let mut sum = Uv::ZERO;
    for (i, p) in points.iter().enumerate() {
        let mut w = 1.0;
        for (j, &tj) in t.iter().enumerate() {
            if i != j {
                w *= (at - tj) / (t[i] - tj);
            }
        }
        sum += w * *p;
    }
    sum
}

/// One quadratic through `run`'s ends within `tol` of all of it — every sample and the
/// curve's point `mids[k]` between samples `k` and `k + 1` — if the fit finds one.
fn fit_run(run: &[Uv], mids: &[Uv], tol: UvTolerance) -> Option<QuadPiece> {
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
    within(&piece, run, mids, &t, tol).then_some(piece)
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

/// Whether the piece holds every sample of `run` (at its parameter) and the curve's point
/// between two samples (`mids`, at the mean parameter) within `tol`: the distances measured
/// to points of the piece, so at least the distances to the piece itself.
fn within(piece: &QuadPiece, run: &[Uv], mids: &[Uv], t: &[f64], tol: UvTolerance) -> bool {
    let at_samples = run
        .iter()
        .zip(t)
        .all(|(p, &t)| tol.scaled(piece.eval(t) - *p) <= 1.0);
    at_samples
        && mids
            .iter()
            .zip(t.windows(2))
            .all(|(mid, t)| tol.scaled(piece.eval(0.5 * (t[0] + t[1])) - *mid) <= 1.0)
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
