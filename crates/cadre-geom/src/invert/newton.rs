//! Newton minimisation of the distance from a point to a curve or surface.

use super::valley::valley_newton;
use crate::curve::Curve;
use crate::point::GeomPoint;
use crate::{Accuracy, Surface, Vec3};

/// Parameter bounds for the iteration: clamped where finite.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounds {
    pub lo: f64,
    pub hi: f64,
}

impl Bounds {
    pub const FREE: Bounds = Bounds {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };
    pub fn new(lo: f64, hi: f64) -> Self {
        Bounds { lo, hi }
    }
    pub(crate) fn clamp(&self, t: f64) -> f64 {
        t.clamp(self.lo, self.hi)
    }
}

/// Minimises `|C(t) − p|` from `t` within `bounds`. Returns the parameter and the distance.
pub(crate) fn curve_newton<P: GeomPoint>(
    c: &Curve<P>,
    p: P,
    mut t: f64,
    bounds: Bounds,
    acc: Accuracy,
) -> Option<(f64, f64)> {
    t = bounds.clamp(t);
    let mut d = c.ders(t, 2);
    let mut dist = (d[0] - p).length_p();
    if !dist.is_finite() {
        return None;
    }
    for _ in 0..acc.max_iterations {
        let r = d[0] - p;
        let g = r.dot_p(d[1]);
        let gn = d[1].dot_p(d[1]);
        let h = gn + r.dot_p(d[2]);
        // Exact Newton where the distance is locally convex, Gauss–Newton otherwise.
        let hh = if h > 1e-12 * gn { h } else { gn };
        if hh.is_nan() || hh <= 0.0 {
            break;
        }
        let mut step = -g / hh;
        let mut improved = false;
        for _ in 0..30 {
            let nt = bounds.clamp(t + step);
            let nd = c.ders(nt, 2);
            let ndist = (nd[0] - p).length_p();
            if ndist.is_finite() && ndist <= dist {
                let moved = (nd[0] - d[0]).length_p();
                t = nt;
                d = nd;
                dist = ndist;
                improved = moved > 0.0;
                if moved <= 0.1 * acc.distance {
                    return Some((t, dist));
                }
                break;
            }
            step *= 0.5;
        }
        if !improved {
            break;
        }
    }
    Some((t, dist))
}

/// Minimises `|S(u, v) − p|` from `(u, v)` within the bounds. Returns `(u, v, distance)`.
pub(crate) fn surface_newton(
    s: &Surface,
    p: Vec3,
    start: (f64, f64),
    bounds: (Bounds, Bounds),
    acc: Accuracy,
) -> Option<(f64, f64, f64)> {
    let (u, v, dist, exhausted) = newton_2d(s, p, start, bounds, acc)?;
    if !exhausted {
        // A minimum, or a clamped bound the step cannot cross.
        return Some((u, v, dist));
    }
    // The iterations ran out still moving: on a narrow curved valley (one partial
    // thousands of times the other) follow its floor, within the domain: past a periodic
    // B-spline's ends its polynomial extension is not the surface, and a walk along the
    // floor would find feet there (trj1_t4m-ac.stp face #661, a rational sphere patch).
    let ((u0, u1), (v0, v1)) = s.domain();
    let within = |b: Bounds, lo: f64, hi: f64| {
        let (lo, hi) = (b.lo.max(lo), b.hi.min(hi));
        if lo <= hi { Bounds::new(lo, hi) } else { b }
    };
    let inside = (within(bounds.0, u0, u1), within(bounds.1, v0, v1));
    match valley_newton(s, p, (u, v), inside, acc.max_iterations, acc.distance) {
        Some(better) if better.2 < dist => Some(better),
        _ => Some((u, v, dist)),
    }
}

/// Newton in both parameters: `(u, v, distance, exhausted)`, `exhausted` when the
/// iterations ran out before the step became small or stopped improving.
pub(crate) fn newton_2d(
    s: &Surface,
    p: Vec3,
    (mut u, mut v): (f64, f64),
    (bu, bv): (Bounds, Bounds),
    acc: Accuracy,
) -> Option<(f64, f64, f64, bool)> {
    u = bu.clamp(u);
    v = bv.clamp(v);
    let mut d = s.derivs(u, v);
    let mut dist = (d.point - p).length();
    if !dist.is_finite() {
        return None;
    }
    let mut exhausted = true;
    for _ in 0..acc.max_iterations {
        let r = d.point - p;
        let (gu, gv) = (r.dot(d.du), r.dot(d.dv));
        let (a, b, c) = (d.du.dot(d.du), d.du.dot(d.dv), d.dv.dot(d.dv));
        let (ha, hb, hc) = (a + r.dot(d.duu), b + r.dot(d.duv), c + r.dot(d.dvv));
        let solve = |a: f64, b: f64, c: f64| {
            // Levenberg damping keeps the system solvable at poles (a zero partial).
            let lambda = 1e-12 * (a.abs() + c.abs()).max(1e-300);
            let (a, c) = (a + lambda, c + lambda);
            let det = a * c - b * b;
            (det > 0.0 && a > 0.0).then(|| ((b * gv - c * gu) / det, (b * gu - a * gv) / det))
        };
        let Some((mut du, mut dv)) = solve(ha, hb, hc).or_else(|| solve(a, b, c)) else {
            exhausted = false;
            break;
        };
        let mut improved = false;
        for halvings in 0..30 {
            let (nu, nv) = (bu.clamp(u + du), bv.clamp(v + dv));
            let nd = s.derivs(nu, nv);
            let ndist = (nd.point - p).length();
            if ndist.is_finite() && ndist <= dist {
                let moved = (nd.point - d.point).length();
                let gained = dist - ndist;
                (u, v, d, dist) = (nu, nv, nd, ndist);
                improved = moved > 0.0;
                // Converged when the move is small and either the whole step was taken or
                // the distance no longer falls. A step the line search had to cut, still
                // gaining, is small because the valley curves (a strongly anisotropic
                // parametrisation: trj6_b1-ec-214.stp's face #6387 changes 35,000 mm per
                // unit v): stopping there left edge points 0.3 mm from their foot instead
                // of 2e-5. At a pole, where the distance does not depend on one parameter,
                // the cut steps gain nothing and stop as before.
                if moved <= 0.1 * acc.distance && (halvings == 0 || gained <= 0.1 * acc.distance) {
                    return Some((u, v, dist, false));
                }
                break;
            }
            du *= 0.5;
            dv *= 0.5;
        }
        if !improved {
            exhausted = false;
            break;
        }
    }
    Some((u, v, dist, exhausted))
}
