//! Curve evaluation: points, derivatives, domains and periods for every [`Curve`] variant.

use std::f64::consts::TAU;

use crate::curve::{CompositeSegment, Curve};
use crate::point::GeomPoint;

/// A curve's point and first two derivatives with respect to its parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveDerivs<P> {
    /// `C(t)`.
    pub point: P,
    /// `C'(t)`.
    pub d1: P,
    /// `C''(t)`.
    pub d2: P,
}

/// Relative step for the central differences that supply third derivatives of offset curves
/// (only nested offsets consume them).
const FD_STEP: f64 = 1e-4;

impl<P: GeomPoint> Curve<P> {
    /// The point at parameter `t`.
    ///
    /// Outside a bounded curve's domain: B-splines extend their end pieces polynomially (closed
    /// ones wrap), polylines and composites their end segments; conics just continue.
    pub fn eval(&self, t: f64) -> P {
        match self {
            // Point-only basis: no derivative tables (see `BSplineCurve::derivatives_on_span`).
            Curve::BSpline(b) => b.point_at(t),
            Curve::Trimmed { basis, .. } => basis.eval(t),
            _ => self.ders(t, 0)[0],
        }
    }

    /// Point, first and second derivatives at `t`.
    pub fn derivs(&self, t: f64) -> CurveDerivs<P> {
        let d = self.ders(t, 2);
        CurveDerivs {
            point: d[0],
            d1: d[1],
            d2: d[2],
        }
    }

    /// Point and derivatives up to the third at `t` (`[C, C', C'', C''']`).
    pub fn derivs3(&self, t: f64) -> [P; 4] {
        self.ders(t, 3)
    }

    /// The natural parameter interval `(min, max)`: `None` for unbounded curves (line,
    /// parabola, hyperbola); `(0, 2π)` for circles and ellipses; `(0, n−1)` for a polyline of
    /// `n` points; the (wrapped, ordered) trimming interval for a trimmed curve; `(0, n)`
    /// for a composite of `n` segments; the basis' for an offset.
    pub fn domain(&self) -> Option<(f64, f64)> {
        match self {
            Curve::Line { .. } | Curve::Parabola { .. } | Curve::Hyperbola { .. } => None,
            Curve::Circle { .. } | Curve::Ellipse { .. } => Some((0.0, TAU)),
            Curve::Polyline(pts) => (!pts.is_empty()).then(|| (0.0, (pts.len() - 1) as f64)),
            Curve::BSpline(b) => b.is_well_formed().then(|| b.domain()),
            Curve::Trimmed { .. } => {
                let (a, b) = self.start_end_params()?;
                Some((a.min(b), a.max(b)))
            }
            Curve::Composite(segs) => (!segs.is_empty()).then_some((0.0, segs.len() as f64)),
            Curve::Offset { basis, .. } => basis.domain(),
        }
    }

    /// The parameters at which the curve starts and ends, in traversal order.
    ///
    /// Equal to [`Curve::domain`] except for trimmed curves, whose traversal runs from `t0`
    /// to `t1`: for a periodic basis `t1` is moved by whole periods so that the curve runs
    /// forward (`sense` true: `t0 < t1' ≤ t0 + period`) or backward (`sense` false:
    /// `t0 − period ≤ t1' < t0`); equal trimming values on a periodic basis give the full
    /// period. For a non-periodic basis `(t0, t1)` is returned as given.
    pub fn start_end_params(&self) -> Option<(f64, f64)> {
        match self {
            Curve::Trimmed {
                basis,
                t0,
                t1,
                sense,
            } => match basis.period() {
                Some(p) if p > 0.0 => {
                    let (a, b) = (*t0, *t1);
                    if *sense {
                        let mut e = a + (b - a).rem_euclid(p);
                        if e <= a {
                            e += p;
                        }
                        Some((a, e))
                    } else {
                        let mut e = a - (a - b).rem_euclid(p);
                        if e >= a {
                            e -= p;
                        }
                        Some((a, e))
                    }
                }
                _ => Some((*t0, *t1)),
            },
            _ => self.domain(),
        }
    }

    /// Whether the curve is periodic (circles, ellipses, closed B-splines and offsets of them).
    pub fn is_periodic(&self) -> bool {
        self.period().is_some()
    }

    /// The period of a periodic curve (`2π` for circles and ellipses, the domain's length for
    /// [closed](crate::BSplineCurve::closed) B-splines), else `None`.
    pub fn period(&self) -> Option<f64> {
        match self {
            Curve::Circle { .. } | Curve::Ellipse { .. } => Some(TAU),
            Curve::BSpline(b) if b.closed && b.is_well_formed() => {
                let (a, z) = b.domain();
                Some(z - a)
            }
            Curve::Offset { basis, .. } => basis.period(),
            _ => None,
        }
    }

    /// Point and derivatives up to `order` (≤ 3) at `t`; entries above `order` may be zero.
    pub(crate) fn ders(&self, t: f64, order: usize) -> [P; 4] {
        let z = P::ZERO;
        match self {
            Curve::Line { origin, direction } => [*origin + *direction * t, *direction, z, z],
            Curve::Circle { frame, radius } => {
                let (s, c) = t.sin_cos();
                let e0 = frame.x * c + frame.y * s;
                let e1 = frame.y * c - frame.x * s;
                let r = *radius;
                [frame.origin + e0 * r, e1 * r, -e0 * r, -e1 * r]
            }
            Curve::Ellipse { frame, a, b } => {
                let (s, c) = t.sin_cos();
                let e0 = frame.x * (a * c) + frame.y * (b * s);
                let e1 = frame.y * (b * c) - frame.x * (a * s);
                [frame.origin + e0, e1, -e0, -e1]
            }
            Curve::Parabola { frame, focal } => {
                let f = *focal;
                [
                    frame.origin + (frame.x * (t * t) + frame.y * (2.0 * t)) * f,
                    (frame.x * (2.0 * t) + frame.y * 2.0) * f,
                    frame.x * (2.0 * f),
                    z,
                ]
            }
            Curve::Hyperbola { frame, a, b } => {
                let (ch, sh) = (t.cosh(), t.sinh());
                let e0 = frame.x * (a * ch) + frame.y * (b * sh);
                let e1 = frame.x * (a * sh) + frame.y * (b * ch);
                [frame.origin + e0, e1, e0, e1]
            }
            Curve::Polyline(pts) => polyline_ders(pts, t),
            Curve::BSpline(b) => {
                let mut out = [z; 4];
                b.derivatives_into(t, &mut out[..=order.min(3)]);
                out
            }
            Curve::Trimmed { basis, .. } => basis.ders(t, order),
            Curve::Composite(segs) => composite_ders(segs, t, order),
            Curve::Offset {
                basis,
                distance,
                ref_direction,
            } => {
                let mut out = offset_ders2(basis, *distance, *ref_direction, t, order.min(2));
                if order >= 3 {
                    // Third derivative by central differences of the exact second one: only a
                    // nested offset needs it, and an exact form would need B''''.
                    let h = FD_STEP * t.abs().max(1.0);
                    let dp = offset_ders2(basis, *distance, *ref_direction, t + h, 2)[2];
                    let dm = offset_ders2(basis, *distance, *ref_direction, t - h, 2)[2];
                    out[3] = (dp - dm) * (0.5 / h);
                }
                out
            }
        }
    }
}

fn polyline_ders<P: GeomPoint>(pts: &[P], t: f64) -> [P; 4] {
    let z = P::ZERO;
    match pts.len() {
        0 => [z; 4],
        1 => [pts[0], z, z, z],
        n => {
            let i = segment_index(t, n - 1);
            let d = pts[i + 1] - pts[i];
            [pts[i] + d * (t - i as f64), d, z, z]
        }
    }
}

/// Index of the unit segment `[i, i+1]` holding `t`, clamped to `0..count` (NaN gives 0).
pub(crate) fn segment_index(t: f64, count: usize) -> usize {
    let f = t.floor();
    if f >= 0.0 {
        (f as usize).min(count.saturating_sub(1))
    } else {
        0
    }
}

/// The basis-parameter interval a composite segment's unit parameter maps onto, oriented so
/// that `s = 0` is the segment's start as used in the composite.
pub(crate) fn segment_map<P: GeomPoint>(seg: &CompositeSegment<P>) -> (f64, f64) {
    let (a, b) = seg.curve.start_end_params().unwrap_or((0.0, 1.0));
    if seg.same_sense { (a, b) } else { (b, a) }
}

fn composite_ders<P: GeomPoint>(segs: &[CompositeSegment<P>], t: f64, order: usize) -> [P; 4] {
    if segs.is_empty() {
        return [P::ZERO; 4];
    }
    let k = segment_index(t, segs.len());
    let (a, b) = segment_map(&segs[k]);
    let scale = b - a;
    let d = segs[k].curve.ders(a + (t - k as f64) * scale, order);
    // Chain rule for the linear reparameterisation.
    [
        d[0],
        d[1] * scale,
        d[2] * (scale * scale),
        d[3] * (scale * scale * scale),
    ]
}

/// Offset curve point and derivatives up to `order ≤ 2`: `C = B + d·N`, `N = W/|W|` with
/// `W = L(B')` linear in the tangent (see [`GeomPoint::offset_direction`]), so `W' = L(B'')`,
/// `W'' = L(B''')`. Where `W` vanishes the normal is undefined and the basis is returned.
fn offset_ders2<P: GeomPoint>(
    basis: &Curve<P>,
    dist: f64,
    ref_dir: crate::Vec3,
    t: f64,
    order: usize,
) -> [P; 4] {
    let b = basis.ders(t, order + 1);
    let w0 = P::offset_direction(b[1], ref_dir);
    let s = w0.length_p();
    // Also rejects NaN: the normal is undefined there.
    if s.is_nan() || s <= 1e-300 || !s.is_finite() {
        return [b[0], b[1], b[2], P::ZERO];
    }
    let w1 = P::offset_direction(b[2], ref_dir);
    let w2 = P::offset_direction(b[3], ref_dir);
    let n = w0 * (1.0 / s);
    // s' = N·W', s'' = (W'·W' + W·W'' − s'²)/s.
    let s1 = n.dot_p(w1);
    let s2 = (w1.dot_p(w1) + w0.dot_p(w2) - s1 * s1) / s;
    let n1 = (w1 - n * s1) * (1.0 / s);
    let n2 = w2 * (1.0 / s) - w1 * (2.0 * s1 / (s * s)) - w0 * (s2 / (s * s))
        + w0 * (2.0 * s1 * s1 / (s * s * s));
    [b[0] + n * dist, b[1] + n1 * dist, b[2] + n2 * dist, P::ZERO]
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    use crate::curve::{CompositeSegment, Curve, CurveFrame};
    use crate::{Curve2, Curve3, Frame, Vec2, Vec3};

    fn circle3(r: f64) -> Curve3 {
        Curve::Circle {
            frame: Frame::WORLD.into(),
            radius: r,
        }
    }

    #[test]
    fn circle_points_and_derivatives() {
        let c = circle3(2.0);
        let d = c.derivs(FRAC_PI_2);
        assert!((d.point - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-15);
        assert!((d.d1 - Vec3::new(-2.0, 0.0, 0.0)).length() < 1e-15);
        assert!((d.d2 - Vec3::new(0.0, -2.0, 0.0)).length() < 1e-15);
        assert_eq!(c.domain(), Some((0.0, TAU)));
        assert_eq!(c.period(), Some(TAU));
    }

    #[test]
    fn trimmed_wraps_on_periodic_basis() {
        let c = Curve::Trimmed {
            basis: Box::new(circle3(1.0)),
            t0: 5.0,
            t1: 1.0,
            sense: true,
        };
        assert_eq!(c.start_end_params(), Some((5.0, 1.0 + TAU)));
        assert_eq!(c.domain(), Some((5.0, 1.0 + TAU)));
        let r = Curve::Trimmed {
            basis: Box::new(circle3(1.0)),
            t0: 1.0,
            t1: 5.0,
            sense: false,
        };
        let (a, b) = r.start_end_params().unwrap();
        assert_eq!(a, 1.0);
        assert!((b - (5.0 - TAU)).abs() < 1e-15);
        let full = Curve::Trimmed {
            basis: Box::new(circle3(1.0)),
            t0: 0.0,
            t1: TAU,
            sense: true,
        };
        assert_eq!(full.start_end_params(), Some((0.0, TAU)));
    }

    #[test]
    fn composite_maps_segments_and_reverses() {
        let seg0 = Curve::Polyline(vec![Vec2::ZERO, Vec2::new(2.0, 0.0)]);
        let seg1 = Curve::Polyline(vec![Vec2::new(2.0, 2.0), Vec2::new(2.0, 0.0)]);
        let c: Curve2 = Curve::Composite(vec![
            CompositeSegment {
                curve: seg0,
                same_sense: true,
            },
            CompositeSegment {
                curve: seg1,
                same_sense: false,
            },
        ]);
        assert_eq!(c.domain(), Some((0.0, 2.0)));
        assert!((c.eval(0.5) - Vec2::new(1.0, 0.0)).length() < 1e-15);
        assert!((c.eval(1.25) - Vec2::new(2.0, 0.5)).length() < 1e-15);
        assert!((c.derivs(1.5).d1 - Vec2::new(0.0, 2.0)).length() < 1e-15);
        assert!((c.eval(2.0) - Vec2::new(2.0, 2.0)).length() < 1e-15);
    }

    #[test]
    fn offset_of_circle_is_bigger_circle() {
        let f = CurveFrame {
            origin: Vec2::ZERO,
            x: Vec2::X,
            y: Vec2::Y,
        };
        // The 2D left normal of a counter-clockwise circle points inwards.
        let c: Curve2 = Curve::Offset {
            basis: Box::new(Curve::Circle {
                frame: f,
                radius: 3.0,
            }),
            distance: -1.0,
            ref_direction: Vec3::Z,
        };
        for i in 0..8 {
            let t = i as f64 * PI / 4.0;
            let d = c.derivs(t);
            assert!((d.point.length() - 4.0).abs() < 1e-14);
            assert!((d.d1.length() - 4.0).abs() < 1e-13);
            assert!((d.d2.length() - 4.0).abs() < 1e-13);
        }
        // 3D: N = B' × ref; for a CCW circle in XY and ref = Z that is outward.
        let c3: Curve3 = Curve::Offset {
            basis: Box::new(circle3(3.0)),
            distance: 1.0,
            ref_direction: Vec3::Z,
        };
        assert!((c3.eval(0.0) - Vec3::new(4.0, 0.0, 0.0)).length() < 1e-14);
    }

    #[test]
    fn degenerate_inputs_stay_finite() {
        let empty: Curve3 = Curve::Polyline(vec![]);
        assert_eq!(empty.eval(0.3), Vec3::ZERO);
        assert_eq!(empty.domain(), None);
        let c: Curve3 = Curve::Offset {
            basis: Box::new(Curve::Line {
                origin: Vec3::ZERO,
                direction: Vec3::ZERO,
            }),
            distance: 1.0,
            ref_direction: Vec3::Z,
        };
        assert!(c.derivs3(0.5).iter().all(|p| p.is_finite()));
        let comp: Curve3 = Curve::Composite(vec![]);
        assert_eq!(comp.eval(1.0), Vec3::ZERO);
    }
}
