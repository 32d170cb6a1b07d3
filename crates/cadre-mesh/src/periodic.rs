//! B-spline surfaces closed in a direction (first and last rows of the net meet) have no
//! period of their own: evaluation does not wrap. A face on one whose trim is unwrapped across
//! the closing seam gets, for triangulation, the same surface repeated on each side, which is
//! exact for the clamped knot vectors STEP uses.

use cadre_brep::trim::periods;
use cadre_geom::{BSplineSurface, Surface, Vec2};

/// The (u, v) box of `points`: (lower corner, upper corner); infinite and inverted when empty.
pub fn uv_bounds(points: impl IntoIterator<Item = Vec2>) -> (Vec2, Vec2) {
    points.into_iter().fold(
        (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// Most copies added on one side (trims span at most one period past the domain).
const MAX_COPIES: usize = 2;

/// The surface to triangulate a face on whose (u, v) polygons span `lo..hi`: `None` when the
/// surface itself covers that range.
pub fn unwrapped_surface(surface: &Surface, lo: Vec2, hi: Vec2) -> Option<Surface> {
    let Surface::BSpline(b) = surface else {
        return None;
    };
    if !b.is_well_formed() {
        return None;
    }
    let p = periods(surface);
    let ((u0, u1), (v0, v1)) = b.domain();
    let mut out: Option<BSplineSurface> = None;
    for (axis, (d0, d1)) in [(0, (u0, u1)), (1, (v0, v1))] {
        let Some(period) = p[axis] else { continue };
        let eps = 1e-9 * period;
        let before = copies(d0 - lo[axis] - eps, period);
        let after = copies(hi[axis] - d1 - eps, period);
        if before + after == 0 {
            continue;
        }
        let base = out.as_ref().unwrap_or(b);
        out = extend(base, axis, before, after, period);
    }
    out.map(|b| Surface::BSpline(Box::new(b)))
}

fn copies(overhang: f64, period: f64) -> usize {
    if overhang <= 0.0 {
        0
    } else {
        ((overhang / period).ceil() as usize).min(MAX_COPIES)
    }
}

/// The net repeated `before` times before and `after` times after itself along `axis`.
fn extend(
    b: &BSplineSurface,
    axis: usize,
    before: usize,
    after: usize,
    period: f64,
) -> Option<BSplineSurface> {
    let (degree, knots) = if axis == 0 {
        (b.u_degree, &b.u_knots)
    } else {
        (b.v_degree, &b.v_knots)
    };
    let clamped = |k: &[f64]| {
        k.len() >= 2 * (degree + 1)
            && k[..=degree].iter().all(|&x| x == k[0])
            && k[k.len() - 1 - degree..]
                .iter()
                .all(|&x| x == k[k.len() - 1])
    };
    if !clamped(knots) {
        return None;
    }
    let total = before + 1 + after;
    let mut new_knots: Vec<f64> = Vec::with_capacity(knots.len() * total);
    for c in 0..total {
        let shift = (c as f64 - before as f64) * period;
        let k = knots.iter().map(|x| x + shift);
        if c == 0 {
            new_knots.extend(k.take(knots.len() - 1));
        } else if c + 1 == total {
            new_knots.extend(k.skip(degree + 1));
        } else {
            new_knots.extend(k.skip(degree + 1).take(knots.len() - degree - 2));
        }
    }
    // Rows (or columns) of the net: the first of each copy after the first is the previous
    // copy's last, so it is dropped.
    fn repeat<T: Clone>(items: &[T], total: usize) -> Vec<T> {
        let mut out = items.to_vec();
        for _ in 1..total {
            out.extend_from_slice(&items[1..]);
        }
        out
    }
    let (control_points, weights) = if axis == 0 {
        (
            repeat(&b.control_points, total),
            b.weights.as_ref().map(|w| repeat(w, total)),
        )
    } else {
        (
            b.control_points.iter().map(|r| repeat(r, total)).collect(),
            b.weights
                .as_ref()
                .map(|w| w.iter().map(|r| repeat(r, total)).collect()),
        )
    };
    let (uk, vk) = if axis == 0 {
        (new_knots, b.v_knots.clone())
    } else {
        (b.u_knots.clone(), new_knots)
    };
    BSplineSurface::try_new(b.u_degree, b.v_degree, uk, vk, control_points, weights).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::Vec3;

    /// A quadratic rational B-spline cylinder (radius 2, height 3), closed in u on [0, 1].
    fn closed_cylinder() -> Surface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let ring = [
            (1.0, 0.0, 1.0),
            (1.0, 1.0, w),
            (0.0, 1.0, 1.0),
            (-1.0, 1.0, w),
            (-1.0, 0.0, 1.0),
            (-1.0, -1.0, w),
            (0.0, -1.0, 1.0),
            (1.0, -1.0, w),
            (1.0, 0.0, 1.0),
        ];
        let net = ring
            .iter()
            .map(|&(x, y, _)| {
                vec![
                    Vec3::new(2.0 * x, 2.0 * y, 0.0),
                    Vec3::new(2.0 * x, 2.0 * y, 3.0),
                ]
            })
            .collect();
        let weights = Some(ring.iter().map(|&(_, _, w)| vec![w, w]).collect());
        let uk = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
        let vk = vec![0., 0., 1., 1.];
        Surface::BSpline(Box::new(
            BSplineSurface::try_new(2, 1, uk, vk, net, weights).unwrap(),
        ))
    }

    #[test]
    fn the_extended_surface_repeats_the_original_one_period_over() {
        let s = closed_cylinder();
        let e = unwrapped_surface(&s, Vec2::new(-0.3, 0.0), Vec2::new(1.2, 1.0)).unwrap();
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            for v in [0.0, 0.4, 1.0] {
                let p = s.eval(u, v);
                assert!((e.eval(u, v) - p).length() < 1e-12);
                assert!((e.eval(u + 1.0, v) - p).length() < 1e-12, "u+1 at {u}");
                assert!((e.eval(u - 1.0, v) - p).length() < 1e-12, "u-1 at {u}");
            }
        }
        // Within the domain nothing is needed.
        assert!(unwrapped_surface(&s, Vec2::new(0.1, 0.0), Vec2::new(0.9, 1.0)).is_none());
    }
}
