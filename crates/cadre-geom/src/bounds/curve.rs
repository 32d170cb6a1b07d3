//! Bounding boxes of curve arcs.

use super::{angular_breaks, bracketed_root, golden_max, sample_params, sinusoid_critical};
use crate::BoundingBox;
use crate::bspline::BSplineCurve;
use crate::curve::Curve;
use crate::eval::curve::segment_map;
use crate::nurbs::basis::find_span;
use crate::point::GeomPoint;

/// Upper bound on samples along one arc (before extremum refinement).
const MAX_SAMPLES: usize = 512;

impl<P: GeomPoint> Curve<P> {
    /// The box of the arc between parameters `t0` and `t1` (in either order).
    ///
    /// Exact (up to rounding) for lines, conics and polylines, and for trimmed and composite
    /// curves built from them; B-splines and offsets are sampled per knot span and every
    /// coordinate extremum between samples is solved for, so the box is exact unless two
    /// extrema hide within one sample step. Bounded curves clip the range to their domain;
    /// 2D curves get `z = 0`. Non-finite points are skipped (an unbounded range gives an
    /// empty or partial box).
    pub fn bbox_between(&self, t0: f64, t1: f64) -> BoundingBox {
        if t0.is_nan() || t1.is_nan() {
            return BoundingBox::EMPTY;
        }
        let (t0, t1) = (t0.min(t1), t0.max(t1));
        let mut bb = BoundingBox::EMPTY;
        let mut add = |p: P| bb.add_point(p.to_vec3());
        match self {
            Curve::Line { .. } => {
                add(self.eval(t0));
                add(self.eval(t1));
            }
            Curve::Circle { frame, radius } => {
                let mut ts = vec![t0, t1];
                for i in 0..P::DIM {
                    sinusoid_critical(
                        frame.x.coord(i) * radius,
                        frame.y.coord(i) * radius,
                        t0,
                        t1,
                        &mut ts,
                    );
                }
                ts.into_iter().for_each(|t| add(self.eval(t)));
            }
            Curve::Ellipse { frame, a, b } => {
                let mut ts = vec![t0, t1];
                for i in 0..P::DIM {
                    sinusoid_critical(frame.x.coord(i) * a, frame.y.coord(i) * b, t0, t1, &mut ts);
                }
                ts.into_iter().for_each(|t| add(self.eval(t)));
            }
            Curve::Parabola { frame, .. } => {
                // Coordinate i ∝ x_i t² + 2 y_i t: extreme at t = −y_i / x_i.
                let mut ts = vec![t0, t1];
                for i in 0..P::DIM {
                    let t = -frame.y.coord(i) / frame.x.coord(i);
                    if t > t0 && t < t1 {
                        ts.push(t);
                    }
                }
                ts.into_iter().for_each(|t| add(self.eval(t)));
            }
            Curve::Hyperbola { frame, a, b } => {
                // d/dt (a x_i cosh t + b y_i sinh t) = 0  ⇔  tanh t = −b y_i / (a x_i).
                let mut ts = vec![t0, t1];
                for i in 0..P::DIM {
                    let r = -(b * frame.y.coord(i)) / (a * frame.x.coord(i));
                    if r.abs() < 1.0 {
                        let t = r.atanh();
                        if t > t0 && t < t1 {
                            ts.push(t);
                        }
                    }
                }
                ts.into_iter().for_each(|t| add(self.eval(t)));
            }
            Curve::Polyline(pts) => {
                let Some((d0, d1)) = self.domain() else {
                    return bb;
                };
                let (a, b) = (t0.clamp(d0, d1), t1.clamp(d0, d1));
                add(self.eval(a));
                add(self.eval(b));
                for (i, p) in pts.iter().enumerate() {
                    if (i as f64) > a && (i as f64) < b {
                        add(*p);
                    }
                }
            }
            Curve::BSpline(_) | Curve::Offset { .. } => {
                let (a, b) = match (self.period(), self.domain()) {
                    (None, Some((d0, d1))) => (t0.clamp(d0, d1), t1.clamp(d0, d1)),
                    _ => (t0, t1),
                };
                if a.is_finite() && b.is_finite() {
                    self.sampled_bbox(a, b, &mut bb);
                }
            }
            Curve::Trimmed { basis, .. } => {
                // Periodic bases are not clipped: callers may shift ranges by whole periods.
                let (a, b) = match (basis.period(), self.domain()) {
                    (None, Some((d0, d1))) => (t0.clamp(d0, d1), t1.clamp(d0, d1)),
                    _ => (t0, t1),
                };
                bb = basis.bbox_between(a, b);
            }
            Curve::Composite(segs) => {
                let n = segs.len() as f64;
                let (a, b) = (t0.clamp(0.0, n), t1.clamp(0.0, n));
                for (k, seg) in segs.iter().enumerate() {
                    let (s0, s1) = ((a - k as f64).max(0.0), (b - k as f64).min(1.0));
                    if s0 > s1 {
                        continue;
                    }
                    let (p0, p1) = segment_map(seg);
                    let sub = seg
                        .curve
                        .bbox_between(p0 + s0 * (p1 - p0), p0 + s1 * (p1 - p0));
                    bb = bb.union(&sub);
                }
            }
        }
        bb
    }

    /// Samples `[t0, t1]` and adds every coordinate extremum found between samples.
    fn sampled_bbox(&self, t0: f64, t1: f64, bb: &mut BoundingBox) {
        let mut breaks = Vec::new();
        self.breaks(t0, t1, true, &mut breaks);
        let ts = sample_params(t0, t1, &breaks, self.samples_per_piece(), MAX_SAMPLES);
        let ders: Vec<[P; 4]> = ts.iter().map(|&t| self.ders(t, 1)).collect();
        for d in &ders {
            bb.add_point(d[0].to_vec3());
        }
        let last = ts.len() - 1;
        // Convex-hull property: on `[ts[k], ts[k+1]]` a B-spline with positive weights lies
        // in the box of the control points of the spans it crosses. Where that box is already
        // inside `bb`, nothing found there can grow it, so the searches (a golden-section one
        // costs ~80 evaluations) are skipped; the box is unchanged bit for bit. It pays on
        // arcs with few extrema; the bench's wavy 24-point cubic has an extremum near every
        // face in most spans, so there it saves nothing (96.6 vs 98.5 µs, noise).
        let hulls: Vec<Option<BoundingBox>> = match self {
            Curve::BSpline(b) if b.is_well_formed() => {
                ts.windows(2).map(|w| span_hull(b, w[0], w[1])).collect()
            }
            _ => Vec::new(),
        };
        // Whether the arc over the sample intervals `k0..k1` provably lies inside `bb`.
        let inside = |bb: &BoundingBox, k0: usize, k1: usize| {
            k0 < k1
                && hulls.get(k0..k1).is_some_and(|hs| {
                    hs.iter().all(|h| {
                        h.is_some_and(|h| bb.min.cmple(h.min).all() && h.max.cmple(bb.max).all())
                    })
                })
        };
        for i in 0..P::DIM {
            let value = |t: f64| self.eval(t).coord(i);
            for k in 1..ts.len() {
                let (ga, gb) = (ders[k - 1][1].coord(i), ders[k][1].coord(i));
                if ga * gb < 0.0 && !inside(bb, k - 1, k) {
                    let g = |t: f64| {
                        let d = self.ders(t, 2);
                        (d[1].coord(i), d[2].coord(i))
                    };
                    let t = bracketed_root(g, ts[k - 1], ts[k], ga);
                    bb.add_point(self.eval(t).to_vec3());
                }
            }
            // A sample more extreme than its neighbours brackets an extremum even where the
            // derivative changes sign twice between samples (cusps and loops of offsets).
            for k in 0..=last {
                let x = ders[k][0].coord(i);
                let (lo, hi) = (k.saturating_sub(1), (k + 1).min(last));
                let prev = if k > 0 {
                    ders[lo][0].coord(i)
                } else {
                    f64::NAN
                };
                let next = if k < last {
                    ders[hi][0].coord(i)
                } else {
                    f64::NAN
                };
                for sign in [1.0, -1.0] {
                    // `sign·x` is a discrete maximum; at an end it must also still rise there.
                    let beats = |y: f64| y.is_nan() || sign * x >= sign * y;
                    let rising_end = (k > 0 || sign * ders[k][1].coord(i) < 0.0)
                        && (k < last || sign * ders[k][1].coord(i) > 0.0);
                    if beats(prev) && beats(next) && rising_end && lo < hi && !inside(bb, lo, hi) {
                        let t = golden_max(|t| sign * value(t), ts[lo], ts[hi]);
                        bb.add_point(self.eval(t).to_vec3());
                    }
                }
            }
        }
    }

    /// Samples per smooth piece: enough for a piece's coordinate derivatives to change sign
    /// at most once between samples in practice.
    pub(crate) fn samples_per_piece(&self) -> usize {
        match self {
            Curve::BSpline(b) => (b.degree + 3).max(6),
            Curve::Trimmed { basis, .. } => basis.samples_per_piece(),
            // Offsets can form cusps and small loops where the basis curvature exceeds
            // 1/distance: sample them more densely.
            Curve::Offset { basis, .. } => 4 * basis.samples_per_piece(),
            Curve::Composite(segs) => segs
                .iter()
                .map(|s| s.curve.samples_per_piece())
                .max()
                .unwrap_or(6),
            _ => 6,
        }
    }

    /// Parameters strictly inside `(t0, t1)`, increasing, where the curve may be less smooth
    /// than elsewhere: B-spline knots, polyline vertices, composite joints (and those of the
    /// curves it is built on). Tessellators and samplers split there.
    pub fn breaks_within(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut out = Vec::new();
        self.breaks(t0, t1, false, &mut out);
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// Appends the breaks of [`Curve::breaks_within`] and, when `angular`, every multiple of
    /// π/4 of an angular parameter (so samplers take short enough steps on conics).
    pub(crate) fn breaks(&self, t0: f64, t1: f64, angular: bool, out: &mut Vec<f64>) {
        match self {
            Curve::Circle { .. } | Curve::Ellipse { .. } => {
                if angular {
                    angular_breaks(t0, t1, out)
                }
            }
            Curve::BSpline(b) => out.extend(b.breaks_within(t0, t1)),
            Curve::Polyline(_) => integer_breaks(t0, t1, out),
            Curve::Trimmed { basis, .. } | Curve::Offset { basis, .. } => {
                basis.breaks(t0, t1, angular, out)
            }
            Curve::Composite(segs) => {
                integer_breaks(t0, t1, out);
                for (k, seg) in segs.iter().enumerate() {
                    let (s0, s1) = ((t0 - k as f64).max(0.0), (t1 - k as f64).min(1.0));
                    if s0 >= s1 {
                        continue;
                    }
                    let (p0, p1) = segment_map(seg);
                    let (x0, x1) = (p0 + s0 * (p1 - p0), p0 + s1 * (p1 - p0));
                    let mut inner = Vec::new();
                    seg.curve
                        .breaks(x0.min(x1), x0.max(x1), angular, &mut inner);
                    out.extend(inner.into_iter().map(|x| k as f64 + (x - p0) / (p1 - p0)));
                }
            }
            Curve::Line { .. } | Curve::Parabola { .. } | Curve::Hyperbola { .. } => {}
        }
    }
}

/// The box of the control points that can influence the B-spline on `(ta, tb)` (the spans
/// meeting the open interval), or `None` when a weight there is not positive (the
/// convex-hull property then fails).
fn span_hull<P: GeomPoint>(b: &BSplineCurve<P>, ta: f64, tb: f64) -> Option<BoundingBox> {
    let (n, p) = (b.control_points.len(), b.degree);
    let sa = find_span(&b.knots, n, p, ta);
    let mut sb = find_span(&b.knots, n, p, tb).max(sa);
    // An interval ending on a knot touches the next span only at its end sample.
    while sb > sa && b.knots[sb] >= tb {
        sb -= 1;
    }
    let range = sa - p..=sb;
    if let Some(w) = &b.weights
        && !w[range.clone()].iter().all(|&w| w > 0.0 && w.is_finite())
    {
        return None;
    }
    let mut h = BoundingBox::EMPTY;
    for pt in &b.control_points[range] {
        // `add_point` would skip a non-finite point, giving too small a hull.
        let q = pt.to_vec3();
        if !q.is_finite() {
            return None;
        }
        h.add_point(q);
    }
    Some(h)
}

fn integer_breaks(t0: f64, t1: f64, out: &mut Vec<f64>) {
    if !(t0.is_finite() && t1.is_finite()) || t1 - t0 > 1e6 {
        return;
    }
    let mut k = t0.floor() + 1.0;
    while k < t1 {
        out.push(k);
        k += 1.0;
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    use crate::bspline::BSplineCurve;
    use crate::curve::Curve;
    use crate::{Curve3, Frame, Vec3};

    fn close(a: [f64; 6], b: [f64; 6], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn circle_arc_box_is_exact() {
        let c: Curve3 = Curve::Circle {
            frame: Frame::WORLD.into(),
            radius: 2.0,
        };
        let b = c.bbox_between(0.0, FRAC_PI_2).to_array();
        assert!(close(b, [0.0, 0.0, 0.0, 2.0, 2.0, 0.0], 1e-15));
        let b = c.bbox_between(-0.1, PI + 0.1).to_array();
        assert!(close(
            b,
            [-2.0, -2.0 * 0.1f64.sin(), 0.0, 2.0, 2.0, 0.0],
            1e-14
        ));
        let b = c.bbox_between(3.0 * TAU, 3.0 * TAU + 7.0).to_array();
        assert!(close(b, [-2.0, -2.0, 0.0, 2.0, 2.0, 0.0], 1e-14));
    }

    #[test]
    fn rational_circle_spline_box() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c: Curve3 = Curve::BSpline(
            BSplineCurve::try_new(
                2,
                vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0],
                vec![
                    Vec3::new(1.0, 0.0, 0.0),
                    Vec3::new(1.0, 1.0, 0.0),
                    Vec3::new(0.0, 1.0, 0.0),
                    Vec3::new(-1.0, 1.0, 0.0),
                    Vec3::new(-1.0, 0.0, 0.0),
                ],
                Some(vec![1.0, s, 1.0, s, 1.0]),
            )
            .unwrap(),
        );
        let b = c.bbox_between(0.0, 2.0).to_array();
        assert!(close(b, [-1.0, 0.0, 0.0, 1.0, 1.0, 0.0], 1e-12), "{b:?}");
        // Half of the first quarter: from (1,0) to 45°.
        let b = c.bbox_between(0.5, 1.5).to_array();
        assert!((b[4] - 1.0).abs() < 1e-12, "{b:?}");
    }
}
