//! B-spline surfaces closed in a direction (first and last rows of the net meet) have no
//! period of their own: evaluation does not wrap. A face on one whose trim is unwrapped across
//! the closing seam gets, for triangulation, the same surface repeated on each side, which is
//! exact for the clamped knot vectors STEP uses.

use cadre_brep::trim::periods;
use cadre_geom::{BSplineSurface, Surface, Vec2, Vec3};

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
        // A periodic B-spline written unclamped (bug24595_281390.stp: knots from -0.0156 on a
        // [0, 1] domain): the same surface over its domain with clamped ends, then repeated.
        let c = clamp(b, axis)?;
        return extend(&c, axis, before, after, period);
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

/// A control point in homogeneous coordinates (x·w, y·w, z·w, w).
type Homogeneous = [f64; 4];

/// `b` with its knot vector along `axis` clamped at the ends of its domain (each end knot
/// inserted until it is a knot of multiplicity degree + 1, the net cut to the domain): the
/// same surface over the domain, in the form [`extend`] repeats. `None` when the knots are
/// not increasing.
fn clamp(b: &BSplineSurface, axis: usize) -> Option<BSplineSurface> {
    let (degree, knots) = if axis == 0 {
        (b.u_degree, &b.u_knots)
    } else {
        (b.v_degree, &b.v_knots)
    };
    let (nu, nv) = (b.control_points.len(), b.control_points.first()?.len());
    let n = if axis == 0 { nu } else { nv };
    let (d0, d1) = (knots[degree], knots[n]);
    // Each sequence of control points along `axis`, homogeneous.
    let lines = if axis == 0 { nv } else { nu };
    let point = |line: usize, k: usize| -> Homogeneous {
        let (i, j) = if axis == 0 { (k, line) } else { (line, k) };
        let p = b.control_points[i][j];
        let w = b.weights.as_ref().map_or(1.0, |w| w[i][j]);
        [p.x * w, p.y * w, p.z * w, w]
    };
    let mut new_knots = Vec::new();
    let mut seqs: Vec<Vec<Homogeneous>> = Vec::with_capacity(lines);
    for line in 0..lines {
        let mut k = knots.clone();
        let mut pts: Vec<Homogeneous> = (0..n).map(|i| point(line, i)).collect();
        let ok = clamp_end(&mut k, &mut pts, degree, d1, false)
            && clamp_end(&mut k, &mut pts, degree, d0, true);
        if !ok {
            return None;
        }
        new_knots = k;
        seqs.push(pts);
    }
    let m = seqs.first()?.len();
    let rational = b.weights.is_some();
    let at = |line: usize, k: usize| -> (Vec3, f64) {
        let h = seqs[line][k];
        (Vec3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3]), h[3])
    };
    let (rows, cols) = if axis == 0 { (m, nv) } else { (nu, m) };
    let mut control_points = vec![vec![Vec3::ZERO; cols]; rows];
    let mut weights = vec![vec![1.0; cols]; rows];
    for (i, row) in control_points.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            let (line, k) = if axis == 0 { (j, i) } else { (i, j) };
            let (q, w) = at(line, k);
            *p = q;
            weights[i][j] = w;
        }
    }
    let (uk, vk) = if axis == 0 {
        (new_knots, b.v_knots.clone())
    } else {
        (b.u_knots.clone(), new_knots)
    };
    let mut out = BSplineSurface::try_new(
        b.u_degree,
        b.v_degree,
        uk,
        vk,
        control_points,
        rational.then_some(weights),
    )
    .ok()?;
    out.u_closed = b.u_closed;
    out.v_closed = b.v_closed;
    Some(out)
}

/// Inserts knot `at` (an end of the domain) until its multiplicity is `degree` (Boehm), then
/// cuts the knots and points beyond it and gives it multiplicity `degree + 1`: the start of
/// the domain when `start`, else its end. False when the knots are not increasing.
fn clamp_end(
    knots: &mut Vec<f64>,
    pts: &mut Vec<Homogeneous>,
    degree: usize,
    at: f64,
    start: bool,
) -> bool {
    let p = degree;
    let count = |k: &[f64]| k.iter().filter(|&&x| x == at).count();
    // At most `degree` insertions; a bounded loop whatever the input.
    for _ in 0..=p {
        if count(knots) >= p {
            break;
        }
        // The span holding `at`: [U_k, U_k+1) at the start, (U_k, U_k+1] at the end (the
        // insertion formula holds on the closed span; these keep k within the net).
        let Some(k) = (0..knots.len() - 1).rev().find(|&k| {
            if start {
                knots[k] <= at && at < knots[k + 1]
            } else {
                knots[k] < at && at <= knots[k + 1]
            }
        }) else {
            return false;
        };
        if k < p || k >= pts.len() {
            return false;
        }
        let mut q = Vec::with_capacity(pts.len() + 1);
        q.extend_from_slice(&pts[..=k - p]);
        for i in k - p + 1..=k {
            let den = knots[i + p] - knots[i];
            if den <= 0.0 {
                return false;
            }
            let a = (at - knots[i]) / den;
            let (pi, pm) = (pts[i], pts[i - 1]);
            q.push(std::array::from_fn(|c| a * pi[c] + (1.0 - a) * pm[c]));
        }
        q.extend_from_slice(&pts[k..]);
        *pts = q;
        knots.insert(k + 1, at);
    }
    let Some(first) = knots.iter().position(|&x| x == at) else {
        return false;
    };
    if count(knots) < p || first == 0 && start {
        // Already clamped at this end (multiplicity above the degree), or nothing to cut.
        return count(knots) >= p;
    }
    if start {
        // Knots `at` at first..first+p; the curve starts at point first - 1.
        let (Some(kn), Some(ps)) = (knots.get(first..), pts.get(first - 1..)) else {
            return false;
        };
        let (mut kn, ps) = (kn.to_vec(), ps.to_vec());
        kn.insert(0, at);
        *knots = kn;
        *pts = ps;
    } else {
        // The curve ends at point first - 1.
        let (Some(kn), Some(ps)) = (knots.get(..first + p), pts.get(..first)) else {
            return false;
        };
        let (mut kn, ps) = (kn.to_vec(), ps.to_vec());
        kn.push(at);
        *knots = kn;
        *pts = ps;
    }
    knots.len() == pts.len() + p + 1
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A uniform periodic quadratic B-spline ring (unclamped knots, the net wrapping by two
    /// points), extruded 2 along z: closed in u on its domain [0, 1].
    fn unclamped_ring(rational: bool) -> BSplineSurface {
        let ring: Vec<Vec3> = (0..6)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 6.0;
                Vec3::new(3.0 * a.cos(), 2.0 * a.sin(), 0.1 * i as f64)
            })
            .collect();
        let mut net: Vec<Vec<Vec3>> = ring
            .iter()
            .map(|p| vec![*p, *p + Vec3::new(0.0, 0.0, 2.0)])
            .collect();
        net.push(net[0].clone());
        net.push(net[1].clone());
        // 8 points, degree 2: 11 uniform knots; the domain [U_2, U_8] is mapped to [0, 1].
        let uk: Vec<f64> = (0..11).map(|k| (k as f64 - 2.0) / 6.0).collect();
        let weights = rational.then(|| {
            (0..8)
                .map(|i| vec![1.0 + 0.3 * ((i % 6) as f64).sin(); 2])
                .collect()
        });
        BSplineSurface::try_new(2, 1, uk, vec![0., 0., 1., 1.], net, weights).unwrap()
    }

    #[test]
    fn an_unclamped_periodic_net_is_clamped_then_repeated() {
        for rational in [false, true] {
            let b = unclamped_ring(rational);
            let s = Surface::BSpline(Box::new(b.clone()));
            // Clamping changes nothing over the domain.
            let c = clamp(&b, 0).expect("clamps");
            assert_eq!(c.domain(), b.domain());
            let cs = Surface::BSpline(Box::new(c));
            let e =
                unwrapped_surface(&s, Vec2::new(-0.4, 0.0), Vec2::new(1.3, 1.0)).expect("extended");
            for i in 0..=40 {
                let u = i as f64 / 40.0;
                for v in [0.0, 0.5, 1.0] {
                    let p = s.eval(u, v);
                    assert!((cs.eval(u, v) - p).length() < 1e-12, "clamped at {u}");
                    assert!((e.eval(u, v) - p).length() < 1e-12, "extended at {u}");
                    if u <= 0.3 {
                        assert!((e.eval(u + 1.0, v) - p).length() < 1e-12, "u+1 at {u}");
                    }
                    if u >= 0.6 {
                        assert!((e.eval(u - 1.0, v) - p).length() < 1e-12, "u-1 at {u}");
                    }
                }
            }
            // Control: without the clamp, evaluation past the domain leaves the surface.
            assert!((s.eval(1.2, 0.5) - s.eval(0.2, 0.5)).length() > 1e-3);
        }
    }
}
