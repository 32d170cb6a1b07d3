//! Projection of a point onto a curve.

use super::newton::{Bounds, curve_newton};
use super::wrap;
use crate::Accuracy;
use crate::bounds::{golden_min, sample_pieces};
use crate::curve::Curve;
use crate::eval::curve::segment_map;
use crate::point::GeomPoint;

/// Samples used to seed Newton on a bounded curve, per smooth piece and in all.
const SEED_PER_PIECE: usize = 4;
const SEED_MAX: usize = 256;
/// Newton runs at most (from the closest local minima of the sampled distance).
const MAX_STARTS: usize = 12;
/// Window searched around the natural seed on unbounded curves (parabola, hyperbola).
const UNBOUNDED_WINDOW: f64 = 4.0;

impl<P: GeomPoint> Curve<P> {
    /// The parameter of the point of the curve closest to `p`.
    ///
    /// Lines, circles and polylines are solved in closed form; other curves by Newton's
    /// method on the squared distance from the best of a set of samples (and from `hint`),
    /// within `acc.max_iterations` and to `acc.distance`. Bounded curves (B-splines,
    /// polylines, trimmed and composite curves) return parameters in their domain. On a
    /// periodic curve the result is shifted by whole periods to be nearest `hint` when
    /// given, else into the domain `[0, 2π)`. Where every parameter is equally close (the
    /// centre of a circle) `hint` (or the domain start) is returned. `None` for non-finite
    /// input or a curve that does not evaluate finitely.
    pub fn project(&self, p: P, hint: Option<f64>, acc: Accuracy) -> Option<f64> {
        if !p.finite() {
            return None;
        }
        let hint = hint.filter(|h| h.is_finite());
        let t = self.project_raw(p, hint, acc)?;
        let start = self.domain().map_or(0.0, |d| d.0);
        Some(wrap(t, self.period(), start, hint)).filter(|t| t.is_finite())
    }

    /// Projection without the final periodic normalisation; returns a parameter.
    fn project_raw(&self, p: P, hint: Option<f64>, acc: Accuracy) -> Option<f64> {
        match self {
            Curve::Line { origin, direction } => {
                let dd = direction.dot_p(*direction);
                if dd > 0.0 && dd.is_finite() {
                    Some((p - *origin).dot_p(*direction) / dd)
                } else {
                    Some(hint.unwrap_or(0.0))
                }
            }
            Curve::Circle { frame, .. } => {
                let w = p - frame.origin;
                let (x, y) = (w.dot_p(frame.x), w.dot_p(frame.y));
                if x == 0.0 && y == 0.0 {
                    Some(hint.unwrap_or(0.0))
                } else {
                    Some(y.atan2(x))
                }
            }
            Curve::Ellipse { frame, a, b } => {
                let w = p - frame.origin;
                let (x, y) = (w.dot_p(frame.x), w.dot_p(frame.y));
                // The eccentric angle of the point's direction, scaled onto the ellipse, is
                // close to the answer; a few spread seeds make the global minimum certain.
                let seed = (y * a).atan2(x * b);
                let seeds = (0..8).map(|k| seed + k as f64 * std::f64::consts::FRAC_PI_4);
                best_of_seeds(self, p, vec![seeds.collect()], &[], Bounds::FREE, acc, hint)
            }
            Curve::Parabola { frame, focal } => {
                let w = p - frame.origin;
                let y = w.dot_p(frame.y);
                let seed = if *focal != 0.0 {
                    y / (2.0 * focal)
                } else {
                    0.0
                };
                let seeds = window(seed, UNBOUNDED_WINDOW * (1.0 + seed.abs()));
                best_of_seeds(self, p, vec![seeds.collect()], &[], Bounds::FREE, acc, hint)
            }
            Curve::Hyperbola { frame, b, .. } => {
                let w = p - frame.origin;
                let y = w.dot_p(frame.y);
                let seed = if *b != 0.0 { (y / b).asinh() } else { 0.0 };
                let seeds = window(seed, UNBOUNDED_WINDOW);
                best_of_seeds(self, p, vec![seeds.collect()], &[], Bounds::FREE, acc, hint)
            }
            Curve::Polyline(pts) => polyline_project(pts, p, hint),
            Curve::BSpline(_) | Curve::Offset { .. } => {
                let (lo, hi) = self.domain()?;
                let bounds = if self.is_periodic() {
                    Bounds::FREE
                } else {
                    Bounds::new(lo, hi)
                };
                let seeds = self.seeds(lo, hi);
                best_of_seeds(self, p, seeds, &[], bounds, acc, hint)
            }
            Curve::Trimmed { basis, .. } => {
                let (lo, hi) = self.domain()?;
                let bounds = Bounds::new(lo, hi);
                // The basis' own answer, moved into the trimmed range when periodic, is
                // usually right; samples of the range catch the cases where it is not.
                let seeds = self.seeds(lo, hi);
                let mut extra = Vec::new();
                if let Some(t) = basis.project_raw(p, hint, acc) {
                    let t = match basis.period() {
                        Some(_) => wrap(t, basis.period(), lo, None),
                        None => t,
                    };
                    extra.push(t);
                }
                best_of_seeds(self, p, seeds, &extra, bounds, acc, hint)
            }
            Curve::Composite(segs) => {
                let mut best: Option<(f64, f64)> = None;
                for (k, seg) in segs.iter().enumerate() {
                    let (a, b) = segment_map(seg);
                    if a == b {
                        continue;
                    }
                    // Map the hint into this segment's parameter when it falls there.
                    let local_hint = hint
                        .filter(|h| (*h - k as f64) >= 0.0 && (*h - k as f64) <= 1.0)
                        .map(|h| a + (h - k as f64) * (b - a));
                    let Some(x) = seg.curve.project(p, local_hint, acc) else {
                        continue;
                    };
                    let s = ((x - a) / (b - a)).clamp(0.0, 1.0);
                    let t = k as f64 + s;
                    let dist = (self.eval(t) - p).length_p();
                    if better(dist, t, best, hint, acc) {
                        best = Some((t, dist));
                    }
                }
                best.map(|b| b.0)
            }
        }
    }

    /// Seed parameters spread over `[lo, hi]`: a few per knot span, and for angular
    /// parameters at least 32 per turn (thin, eccentric shapes need them).
    pub(crate) fn seeds(&self, lo: f64, hi: f64) -> Vec<Vec<f64>> {
        if !(lo.is_finite() && hi.is_finite()) {
            return vec![vec![0.0]];
        }
        let mut breaks = Vec::new();
        self.breaks(lo, hi, true, &mut breaks);
        let mut per = SEED_PER_PIECE;
        if let Curve::BSpline(b) = self {
            per = per.max(3 * b.degree + 2);
        }
        if matches!(self, Curve::Offset { .. }) {
            per *= 2;
        }
        sample_pieces(lo, hi, &breaks, per, SEED_MAX)
    }
}

/// `2k + 1` seeds spread over `seed ± half`.
fn window(seed: f64, half: f64) -> impl Iterator<Item = f64> {
    (-4..=4).map(move |k| seed + half * k as f64 / 4.0)
}

/// Whether a candidate `(t, dist)` beats `best`: clearly closer, or as close (within the
/// accuracy) and nearer the hint.
fn better(dist: f64, t: f64, best: Option<(f64, f64)>, hint: Option<f64>, acc: Accuracy) -> bool {
    let Some((bt, bd)) = best else {
        return dist.is_finite();
    };
    if dist < bd - acc.distance {
        return true;
    }
    if dist <= bd + acc.distance
        && let Some(h) = hint
    {
        return (t - h).abs() < (bt - h).abs();
    }
    dist < bd
}

/// Newton from every sample of each smooth piece of `pieces` that is closer than its
/// neighbours in the piece — each brackets a local minimum of the distance — and from the
/// `extra` seeds; the closest result wins. Pieces matter: across a kink the distance can
/// fall on both sides of a local minimum's samples without one showing up as a minimum.
fn best_of_seeds<P: GeomPoint>(
    c: &Curve<P>,
    p: P,
    pieces: Vec<Vec<f64>>,
    extra: &[f64],
    bounds: Bounds,
    acc: Accuracy,
    hint: Option<f64>,
) -> Option<f64> {
    // A hint that already lands on the curve is taken at once: the common case of a
    // caller walking along points of the curve.
    if let Some(h) = hint
        && let Some((t, d)) = curve_newton(c, p, h, bounds, acc)
        && d <= acc.distance
    {
        return Some(t);
    }
    let dist = |t: f64| (c.eval(t) - p).length_p();
    let mut starts: Vec<(f64, f64)> = Vec::new();
    let mut all_samples: Vec<f64> = pieces
        .iter()
        .flatten()
        .copied()
        .filter(|t| t.is_finite())
        .collect();
    all_samples.sort_by(f64::total_cmp);
    for piece in pieces {
        // (t, distance, slope of the squared distance / 2).
        let scored: Vec<(f64, f64, f64)> = piece
            .into_iter()
            .filter(|t| t.is_finite())
            .map(|t| {
                let t = t.clamp(bounds.lo, bounds.hi);
                let d = c.ders(t, 1);
                let r = d[0] - p;
                (t, r.length_p(), r.dot_p(d[1]))
            })
            .filter(|s| s.1.is_finite())
            .collect();
        let last = scored.len().saturating_sub(1);
        let mut brackets = Vec::new();
        for k in local_minima(&scored) {
            // The minimum lies on one side of the sample or the other.
            starts.push((scored[k].0, scored[k].1));
            for n in [k.saturating_sub(1), (k + 1).min(last)] {
                if n != k {
                    brackets.push((scored[n].0.min(scored[k].0), scored[n].0.max(scored[k].0)));
                }
            }
        }
        // A slope going from negative to positive brackets a minimum even when two close
        // minima hide it from the sampled values.
        for w in scored.windows(2) {
            if w[0].2 < 0.0 && w[1].2 > 0.0 {
                brackets.push((w[0].0, w[1].0));
            }
        }
        // Golden section narrows each bracket before Newton, which alone can stall where
        // the curve is stationary (repeated control points).
        for (a, b) in brackets {
            let t = golden_min(dist, a, b, 24);
            starts.push((t, dist(t)));
        }
    }
    starts.sort_by(|a, b| a.1.total_cmp(&b.1));
    starts.truncate(MAX_STARTS);
    starts.extend(extra.iter().chain(hint.as_ref()).map(|&t| (t, 0.0)));
    let mut best: Option<(f64, f64)> = None;
    for &(t0, d0) in &starts {
        // Newton may leave a good start for another stationary point (two close minima
        // around a tight loop); the start itself stays a candidate.
        if d0 > 0.0 && better(d0, t0, best, hint, acc) {
            best = Some((t0, d0));
        }
        if let Some((t, d)) = curve_newton(c, p, t0, bounds, acc)
            && better(d, t, best, hint, acc)
        {
            best = Some((t, d));
        }
    }
    // Two minima closer than the sample spacing (a near-cusp) can hide the nearer one: look
    // again, finely, two sample intervals either side of the best answer.
    if let Some((tb, db)) = best
        && db > acc.distance
        && all_samples.len() > 1
    {
        let k = all_samples.partition_point(|&x| x < tb);
        let lo = all_samples[k.saturating_sub(2)].max(bounds.lo);
        let hi = all_samples[(k + 1).min(all_samples.len() - 1)].min(bounds.hi);
        if hi > lo {
            const FINE: usize = 48;
            let fine: Vec<(f64, f64, ())> = (0..=FINE)
                .map(|i| {
                    let t = lo + (hi - lo) * i as f64 / FINE as f64;
                    (t, dist(t), ())
                })
                .collect();
            for m in local_minima(&fine) {
                let (a, b) = (fine[m.saturating_sub(1)].0, fine[(m + 1).min(FINE)].0);
                let t0 = golden_min(dist, a, b, 24);
                let d0 = dist(t0);
                if better(d0, t0, best, hint, acc) {
                    best = Some((t0, d0));
                }
                if let Some((t, d)) = curve_newton(c, p, t0, bounds, acc)
                    && better(d, t, best, hint, acc)
                {
                    best = Some((t, d));
                }
            }
        }
    }
    best.map(|b| b.0)
}

/// Indices of samples `(t, distance, …)` no farther than their neighbours.
pub(crate) fn local_minima<T>(d: &[(f64, f64, T)]) -> Vec<usize> {
    let last = d.len().saturating_sub(1);
    (0..d.len())
        .filter(|&k| (k == 0 || d[k].1 <= d[k - 1].1) && (k == last || d[k].1 <= d[k + 1].1))
        .collect()
}

/// Closest point on a polyline: per segment in closed form.
fn polyline_project<P: GeomPoint>(pts: &[P], p: P, hint: Option<f64>) -> Option<f64> {
    match pts.len() {
        0 => None,
        1 => Some(0.0),
        _ => {
            let mut best: Option<(f64, f64)> = None;
            for (i, w) in pts.windows(2).enumerate() {
                let d = w[1] - w[0];
                let dd = d.dot_p(d);
                let s = if dd > 0.0 {
                    ((p - w[0]).dot_p(d) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let t = i as f64 + s;
                let dist = (w[0] + d * s - p).length_p();
                if better(dist, t, best, hint, Accuracy::new(0.0)) {
                    best = Some((t, dist));
                }
            }
            best.map(|b| b.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    use crate::curve::Curve;
    use crate::{Accuracy, Curve3, Frame, Vec3};

    fn circle() -> Curve3 {
        Curve::Circle {
            frame: Frame::WORLD.into(),
            radius: 2.0,
        }
    }

    #[test]
    fn circle_projection_wraps() {
        let c = circle();
        let acc = Accuracy::default();
        let t = c.project(Vec3::new(0.0, -5.0, 1.0), None, acc).unwrap();
        assert!((t - 1.5 * PI).abs() < 1e-15);
        let t = c
            .project(Vec3::new(0.0, -5.0, 1.0), Some(0.1), acc)
            .unwrap();
        assert!((t + FRAC_PI_2).abs() < 1e-15);
        assert_eq!(
            c.project(Vec3::new(0.0, 0.0, 3.0), Some(1.0), acc),
            Some(1.0)
        );
    }

    #[test]
    fn trimmed_circle_projection_stays_in_range() {
        let c = Curve::Trimmed {
            basis: Box::new(circle()),
            t0: 5.0,
            t1: 1.0,
            sense: true,
        };
        let acc = Accuracy::default();
        let t = c.project(Vec3::new(2.0, 0.0, 0.0), None, acc).unwrap();
        assert!((t - TAU).abs() < 1e-12);
        // Closest point of the arc (5 → 1+2π) to a point at angle π is an end.
        let t = c.project(Vec3::new(-2.0, 0.0, 0.0), None, acc).unwrap();
        assert!(
            (t - 5.0).abs() < 1e-9 || (t - (1.0 + TAU)).abs() < 1e-9,
            "{t}"
        );
    }

    #[test]
    fn ellipse_projection() {
        let c: Curve3 = Curve::Ellipse {
            frame: Frame::WORLD.into(),
            a: 3.0,
            b: 1.0,
        };
        let acc = Accuracy::default();
        for i in 0..16 {
            let t = i as f64 * TAU / 16.0;
            let q = c.eval(t) + c.derivs(t).d1.cross(Vec3::Z).normalize() * 0.2;
            let s = c.project(q, None, acc).unwrap();
            assert!((s - t).abs() < 1e-8, "{s} vs {t}");
        }
    }

    #[test]
    fn non_finite_point_gives_none() {
        assert_eq!(circle().project(Vec3::NAN, None, Accuracy::default()), None);
    }
}
