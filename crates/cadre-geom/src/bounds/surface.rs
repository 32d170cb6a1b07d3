//! Bounding boxes of surface patches over parameter rectangles.

use super::{angular_breaks, bracketed_root, sample_params, sinusoid_critical};
use crate::eval::surface::Ders;
use crate::{BoundingBox, Frame, Surface, Vec3};

/// Upper bound on samples per parameter direction (before extremum refinement).
const MAX_SAMPLES: usize = 160;
/// Newton iterations when polishing an interior extremum.
const INTERIOR_ITERATIONS: usize = 24;

/// The radial profile of the rotational analytic surfaces, `S = o + f(v) E(u) + g(v) z`.
enum Profile {
    /// `f`, `g` affine in v (cylinder, cone): extremes at the ends of the v range.
    Affine,
    /// `f = c + r cos v`, `g = r sin v` (sphere with c = 0, torus with c = R).
    Circular,
}

impl Surface {
    /// The box of the patch `[u0, u1] × [v0, v1]` (each pair in either order).
    ///
    /// Exact for planes, cylinders, cones, spheres and tori (closed-form extrema of each
    /// coordinate over the angular ranges, which may exceed a period) and for extrusions of
    /// analytic profiles (box of the profile arc plus the sweep). B-spline, revolution and
    /// offset patches are sampled per knot span / π/4 of angle and every coordinate
    /// extremum on the four boundary curves and in the interior is solved for by Newton's
    /// method, so the box consists of surface points and misses only extrema hidden between
    /// samples. Non-periodic directions are clipped to the domain; non-finite points are
    /// skipped, so unbounded ranges give empty or partial boxes.
    pub fn bbox_over(&self, u0: f64, u1: f64, v0: f64, v1: f64) -> BoundingBox {
        let (u0, u1) = (u0.min(u1), u0.max(u1));
        let (v0, v1) = (v0.min(v1), v0.max(v1));
        if !(u0 <= u1 && v0 <= v1) {
            return BoundingBox::EMPTY;
        }
        match self {
            Surface::Plane { .. } => BoundingBox::from_points(
                [(u0, v0), (u1, v0), (u0, v1), (u1, v1)].map(|(u, v)| self.eval(u, v)),
            ),
            Surface::Cylinder { frame, .. } | Surface::Cone { frame, .. } => {
                rotational_box(self, frame, Profile::Affine, u0, u1, v0, v1)
            }
            Surface::Sphere { frame, .. } | Surface::Torus { frame, .. } => {
                rotational_box(self, frame, Profile::Circular, u0, u1, v0, v1)
            }
            Surface::Extrusion { profile, direction } => {
                let (u0, u1) = clip(u0, u1, self.u_period(), self.domain().0);
                // Box of a Minkowski sum = sum of the boxes.
                let c = profile.bbox_between(u0, u1);
                let (a, b) = (*direction * v0, *direction * v1);
                if c.is_empty() || !(a.is_finite() && b.is_finite()) {
                    return BoundingBox::EMPTY;
                }
                BoundingBox {
                    min: c.min + a.min(b),
                    max: c.max + a.max(b),
                }
            }
            Surface::Trimmed { basis, .. } => {
                let ((du0, du1), (dv0, dv1)) = self.domain();
                let (a0, a1) = match basis.u_period() {
                    None => (u0.clamp(du0, du1), u1.clamp(du0, du1)),
                    Some(_) => (u0, u1),
                };
                let (b0, b1) = match basis.v_period() {
                    None => (v0.clamp(dv0, dv1), v1.clamp(dv0, dv1)),
                    Some(_) => (v0, v1),
                };
                basis.bbox_over(a0, a1, b0, b1)
            }
            Surface::BSpline(_) | Surface::Revolution { .. } | Surface::Offset { .. } => {
                let ((du, dv), (pu, pv)) = (self.domain(), (self.u_period(), self.v_period()));
                let (u0, u1) = clip(u0, u1, pu, du);
                let (v0, v1) = clip(v0, v1, pv, dv);
                if [u0, u1, v0, v1].iter().all(|x| x.is_finite()) {
                    self.sampled_box(u0, u1, v0, v1)
                } else {
                    BoundingBox::EMPTY
                }
            }
        }
    }

    /// Box from a sample grid plus refined extrema on the boundary and inside.
    fn sampled_box(&self, u0: f64, u1: f64, v0: f64, v1: f64) -> BoundingBox {
        let (mut ub, mut vb) = (Vec::new(), Vec::new());
        self.u_breaks(u0, u1, true, &mut ub);
        self.v_breaks(v0, v1, true, &mut vb);
        let (nu, nv) = self.samples_per_piece();
        let us = sample_params(u0, u1, &ub, nu, MAX_SAMPLES);
        let vs = sample_params(v0, v1, &vb, nv, MAX_SAMPLES);
        let grid: Vec<Vec<Ders>> = us
            .iter()
            .map(|&u| vs.iter().map(|&v| self.ders(u, v, 1)).collect())
            .collect();
        let mut bb = BoundingBox::EMPTY;
        grid.iter().flatten().for_each(|d| bb.add_point(d[0][0]));
        for axis in 0..3 {
            // Every grid line: the boundary curves and the knot lines among them, where the
            // surface has kinks so extrema can sit without the gradient vanishing, and the
            // others because an interior extremum is close to one.
            for (jv, &v) in vs.iter().enumerate() {
                for k in 1..us.len() {
                    let (a, b) = (&grid[k - 1][jv], &grid[k][jv]);
                    let (ga, gb) = (a[1][0][axis], b[1][0][axis]);
                    let reach = 2.0 * ga.abs().max(gb.abs()) * (us[k] - us[k - 1]);
                    let (fa, fb) = (a[0][0][axis], b[0][0][axis]);
                    if ga * gb < 0.0
                        && could_extend(&bb, axis, fa.min(fb) - reach, fa.max(fb) + reach)
                    {
                        let g = |u: f64| {
                            let d = self.ders(u, v, 2);
                            (d[1][0][axis], d[2][0][axis])
                        };
                        bb.add_point(self.eval(bracketed_root(g, us[k - 1], us[k], ga), v));
                    }
                }
            }
            for (iu, &u) in us.iter().enumerate() {
                for k in 1..vs.len() {
                    let (a, b) = (&grid[iu][k - 1], &grid[iu][k]);
                    let (ga, gb) = (a[0][1][axis], b[0][1][axis]);
                    let reach = 2.0 * ga.abs().max(gb.abs()) * (vs[k] - vs[k - 1]);
                    let (fa, fb) = (a[0][0][axis], b[0][0][axis]);
                    if ga * gb < 0.0
                        && could_extend(&bb, axis, fa.min(fb) - reach, fa.max(fb) + reach)
                    {
                        let g = |v: f64| {
                            let d = self.ders(u, v, 2);
                            (d[0][1][axis], d[0][2][axis])
                        };
                        bb.add_point(self.eval(u, bracketed_root(g, vs[k - 1], vs[k], ga)));
                    }
                }
            }
            // Interior: a cell where both partials of this coordinate change sign may hold
            // a critical point; polish it with Newton on the gradient.
            for i in 1..us.len() {
                for j in 1..vs.len() {
                    let c = [
                        grid[i - 1][j - 1],
                        grid[i][j - 1],
                        grid[i - 1][j],
                        grid[i][j],
                    ];
                    let changes = |a: usize, b: usize| {
                        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                        for d in &c {
                            lo = lo.min(d[a][b][axis]);
                            hi = hi.max(d[a][b][axis]);
                        }
                        lo <= 0.0 && hi >= 0.0
                    };
                    // Only cells whose corners, widened by how far the partials could carry
                    // the coordinate across the cell, reach the box's current faces.
                    let (du, dv) = (us[i] - us[i - 1], vs[j] - vs[j - 1]);
                    let (mut lo, mut hi, mut reach) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
                    for d in &c {
                        lo = lo.min(d[0][0][axis]);
                        hi = hi.max(d[0][0][axis]);
                        reach =
                            reach.max(2.0 * (d[1][0][axis].abs() * du + d[0][1][axis].abs() * dv));
                    }
                    if changes(1, 0)
                        && changes(0, 1)
                        && could_extend(&bb, axis, lo - reach, hi + reach)
                    {
                        let cell = (us[i - 1], us[i], vs[j - 1], vs[j]);
                        if let Some(p) = self.polish_critical(axis, cell, (u0, u1, v0, v1)) {
                            bb.add_point(p);
                        }
                    }
                }
            }
        }
        bb
    }

    /// Newton on `∇S_axis = 0` from the cell's centre, kept within the cell widened by half
    /// its size and within the patch. Any point reached lies on the patch, so the result is
    /// always a valid box point; convergence only makes it the extremum.
    fn polish_critical(
        &self,
        axis: usize,
        cell: (f64, f64, f64, f64),
        patch: (f64, f64, f64, f64),
    ) -> Option<Vec3> {
        let (a0, a1, b0, b1) = cell;
        let (hu, hv) = (0.5 * (a1 - a0), 0.5 * (b1 - b0));
        let (lo_u, hi_u) = ((a0 - hu).max(patch.0), (a1 + hu).min(patch.1));
        let (lo_v, hi_v) = ((b0 - hv).max(patch.2), (b1 + hv).min(patch.3));
        let (mut u, mut v) = (0.5 * (a0 + a1), 0.5 * (b0 + b1));
        for _ in 0..INTERIOR_ITERATIONS {
            let d = self.ders(u, v, 2);
            let (gu, gv) = (d[1][0][axis], d[0][1][axis]);
            let (huu, huv, hvv) = (d[2][0][axis], d[1][1][axis], d[0][2][axis]);
            let det = huu * hvv - huv * huv;
            let norm = huu.abs() + hvv.abs() + huv.abs();
            let (du, dv) = if det.abs() > 1e-10 * norm * norm && det != 0.0 {
                ((huv * gv - hvv * gu) / det, (huv * gu - huu * gv) / det)
            } else {
                // Ridge or flat direction: step only along directions with curvature.
                let step = |g: f64, h: f64| if h.abs() > 1e-300 { -g / h } else { 0.0 };
                (step(gu, huu), step(gv, hvv))
            };
            if !(du.is_finite() && dv.is_finite()) {
                break;
            }
            let (nu, nv) = ((u + du).clamp(lo_u, hi_u), (v + dv).clamp(lo_v, hi_v));
            let moved = (nu - u).abs() > 1e-15 * (1.0 + u.abs())
                || (nv - v).abs() > 1e-15 * (1.0 + v.abs());
            (u, v) = (nu, nv);
            if !moved {
                break;
            }
        }
        let p = self.eval(u, v);
        p.is_finite().then_some(p)
    }

    /// Samples per smooth piece in (u, v).
    fn samples_per_piece(&self) -> (usize, usize) {
        match self {
            Surface::BSpline(b) => ((b.u_degree + 3).max(6), (b.v_degree + 3).max(6)),
            Surface::Extrusion { profile, .. } => (profile.samples_per_piece(), 6),
            Surface::Revolution { profile, .. } => (6, profile.samples_per_piece()),
            Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => {
                let (a, b) = basis.samples_per_piece();
                (a + 2, b + 2)
            }
            _ => (6, 6),
        }
    }

    /// u values strictly inside `(u0, u1)`, increasing, where the surface may be less
    /// smooth: B-spline knots, breaks of a swept profile, those of an offset's or trimmed
    /// surface's basis.
    pub fn u_breaks_within(&self, u0: f64, u1: f64) -> Vec<f64> {
        let mut out = Vec::new();
        self.u_breaks(u0, u1, false, &mut out);
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// Like [`Surface::u_breaks_within`] for v.
    pub fn v_breaks_within(&self, v0: f64, v1: f64) -> Vec<f64> {
        let mut out = Vec::new();
        self.v_breaks(v0, v1, false, &mut out);
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// Appends the u breaks and, when `angular`, every π/4 of an angular u.
    fn u_breaks(&self, u0: f64, u1: f64, angular: bool, out: &mut Vec<f64>) {
        match self {
            Surface::Plane { .. } => {}
            Surface::Cylinder { .. }
            | Surface::Cone { .. }
            | Surface::Sphere { .. }
            | Surface::Torus { .. }
            | Surface::Revolution { .. } => {
                if angular {
                    angular_breaks(u0, u1, out)
                }
            }
            Surface::BSpline(b) => out.extend(b.u_breaks_within(u0, u1)),
            Surface::Extrusion { profile, .. } => profile.breaks(u0, u1, angular, out),
            Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => {
                basis.u_breaks(u0, u1, angular, out)
            }
        }
    }

    /// Appends the v breaks and, when `angular`, every π/4 of an angular v.
    fn v_breaks(&self, v0: f64, v1: f64, angular: bool, out: &mut Vec<f64>) {
        match self {
            Surface::Plane { .. }
            | Surface::Cylinder { .. }
            | Surface::Cone { .. }
            | Surface::Extrusion { .. } => {}
            Surface::Sphere { .. } | Surface::Torus { .. } => {
                if angular {
                    angular_breaks(v0, v1, out)
                }
            }
            Surface::Revolution { profile, .. } => profile.breaks(v0, v1, angular, out),
            Surface::BSpline(b) => out.extend(b.v_breaks_within(v0, v1)),
            Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => {
                basis.v_breaks(v0, v1, angular, out)
            }
        }
    }
}

/// Whether a coordinate range `[lo, hi]` on `axis` could grow the box.
fn could_extend(bb: &BoundingBox, axis: usize, lo: f64, hi: f64) -> bool {
    bb.is_empty() || lo <= bb.min[axis] || hi >= bb.max[axis]
}

/// Clips `[a, b]` to the domain `d` unless the direction is periodic.
fn clip(a: f64, b: f64, period: Option<f64>, d: (f64, f64)) -> (f64, f64) {
    match period {
        Some(_) => (a, b),
        None => (a.clamp(d.0, d.1), b.clamp(d.0, d.1)),
    }
}

/// Exact box of a cylinder, cone, sphere or torus patch. Coordinate `i` is
/// `o_i + f(v)·q_i(u) + g(v)·z_i` with `q_i(u) = x_i cos u + y_i sin u`; for fixed v it is
/// affine in `q_i`, which sweeps exactly `[m_i, M_i]` over the u range, so its extremes are
/// the extremes over v of `f(v)·h + g(v)·z_i` for `h ∈ {m_i, M_i}`.
fn rotational_box(
    s: &Surface,
    frame: &Frame,
    profile: Profile,
    u0: f64,
    u1: f64,
    v0: f64,
    v1: f64,
) -> BoundingBox {
    // At u = 0, E(u) = x, so f(v) = (S(0, v) − o)·x and g(v) = (S(0, v) − o)·z.
    let fg = |v: f64| {
        let d = s.eval(0.0, v) - frame.origin;
        (d.dot(frame.x), d.dot(frame.z))
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for i in 0..3 {
        let (xi, yi, zi) = (frame.x[i], frame.y[i], frame.z[i]);
        let mut us = vec![u0, u1];
        sinusoid_critical(xi, yi, u0, u1, &mut us);
        let (mut m, mut big) = (f64::INFINITY, f64::NEG_INFINITY);
        for u in us {
            let q = xi * u.cos() + yi * u.sin();
            m = m.min(q);
            big = big.max(q);
        }
        for h in [m, big] {
            let mut vs = vec![v0, v1];
            if let Profile::Circular = profile {
                sinusoid_critical(h, zi, v0, v1, &mut vs);
            }
            for v in vs {
                let (f, g) = fg(v);
                let value = frame.origin[i] + f * h + g * zi;
                if value.is_finite() {
                    lo[i] = lo[i].min(value);
                    hi[i] = hi[i].max(value);
                }
            }
        }
    }
    let bb = BoundingBox {
        min: Vec3::from_array(lo),
        max: Vec3::from_array(hi),
    };
    if bb.is_empty() {
        BoundingBox::EMPTY
    } else {
        bb
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    use crate::bspline::BSplineSurface;
    use crate::{Curve, Frame, Surface, Vec3};

    fn close(a: [f64; 6], b: [f64; 6], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn full_sphere_and_cap() {
        let f = Frame::from_axis(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 1.0, 0.0), None).unwrap();
        let s = Surface::Sphere {
            frame: f,
            radius: 2.0,
        };
        let b = s.bbox_over(0.0, TAU, -FRAC_PI_2, FRAC_PI_2).to_array();
        assert!(close(b, [-1.0, 0.0, 1.0, 3.0, 4.0, 5.0], 1e-14), "{b:?}");
        // Northern cap above 60°, sphere axis along world z.
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 2.0,
        };
        let b = s.bbox_over(0.0, TAU, PI / 3.0, FRAC_PI_2).to_array();
        let r = 2.0 * (PI / 3.0).cos();
        assert!(
            close(b, [-r, -r, 2.0 * (PI / 3.0).sin(), r, r, 2.0], 1e-14),
            "{b:?}"
        );
    }

    #[test]
    fn cylinder_over_more_than_a_turn_and_wrapped() {
        let s = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 1.0,
        };
        let b = s.bbox_over(-1.0, 9.0, 0.0, 2.0).to_array();
        assert!(close(b, [-1.0, -1.0, 0.0, 1.0, 1.0, 2.0], 1e-15));
        // A quarter across the seam: angles 3π/2 … 2π+π/2 wrapped as (−π/2, π/2).
        let b = s.bbox_over(1.5 * PI, 2.5 * PI, 0.0, 1.0).to_array();
        assert!(close(b, [0.0, -1.0, 0.0, 1.0, 1.0, 1.0], 1e-15), "{b:?}");
    }

    #[test]
    fn torus_quarter_is_exact() {
        let s = Surface::Torus {
            frame: Frame::WORLD,
            major_radius: 3.0,
            minor_radius: 1.0,
        };
        let b = s.bbox_over(0.0, FRAC_PI_2, 0.0, PI).to_array();
        assert!(close(b, [0.0, 0.0, 0.0, 4.0, 4.0, 1.0], 1e-14), "{b:?}");
    }

    #[test]
    fn cone_box_and_unbounded_range() {
        let s = Surface::Cone {
            frame: Frame::WORLD,
            radius: 1.0,
            semi_angle: PI / 4.0,
        };
        let b = s.bbox_over(0.0, TAU, 0.0, 1.0).to_array();
        assert!(close(b, [-2.0, -2.0, 0.0, 2.0, 2.0, 1.0], 1e-14), "{b:?}");
        assert!(
            s.bbox_over(0.0, 1.0, 0.0, f64::INFINITY).is_empty()
                || s.bbox_over(0.0, 1.0, 0.0, f64::INFINITY).min.is_finite()
        );
    }

    #[test]
    fn bspline_box_is_within_hull_and_hits_extremes() {
        // A bump: the middle control point pulls the surface to z = 0.5625·2 at the centre.
        let net = (0..3)
            .map(|i| {
                (0..3)
                    .map(|j| {
                        Vec3::new(i as f64, j as f64, if i == 1 && j == 1 { 2.0 } else { 0.0 })
                    })
                    .collect()
            })
            .collect();
        let s = Surface::BSpline(Box::new(BSplineSurface::bezier(net, None).unwrap()));
        let b = s.bbox_over(0.0, 1.0, 0.0, 1.0).to_array();
        // z(½, ½) = 2 · (2·½·½)² = 0.5.
        assert!(close(b, [0.0, 0.0, 0.0, 2.0, 2.0, 0.5], 1e-12), "{b:?}");
    }

    #[test]
    fn revolution_and_extrusion_boxes() {
        let rev = Surface::Revolution {
            profile: Box::new(Curve::Line {
                origin: Vec3::new(2.0, 0.0, 0.0),
                direction: Vec3::Z,
            }),
            axis_origin: Vec3::ZERO,
            axis_direction: Vec3::Z,
        };
        let b = rev.bbox_over(0.0, TAU, 0.0, 3.0).to_array();
        assert!(close(b, [-2.0, -2.0, 0.0, 2.0, 2.0, 3.0], 1e-12), "{b:?}");
        let ext = Surface::Extrusion {
            profile: Box::new(Curve::Circle {
                frame: Frame::WORLD.into(),
                radius: 1.0,
            }),
            direction: Vec3::new(0.0, 0.0, 2.0),
        };
        let b = ext.bbox_over(0.0, PI, -1.0, 1.0).to_array();
        assert!(close(b, [-1.0, 0.0, -2.0, 1.0, 1.0, 2.0], 1e-15), "{b:?}");
    }

    #[test]
    fn trimmed_surface_domain_wraps() {
        let s = Surface::Trimmed {
            basis: Box::new(Surface::Cylinder {
                frame: Frame::WORLD,
                radius: 1.0,
            }),
            u0: 5.0,
            u1: 1.0,
            v0: 2.0,
            v1: -1.0,
        };
        assert_eq!(s.domain(), ((5.0, 1.0 + TAU), (-1.0, 2.0)));
    }
}
