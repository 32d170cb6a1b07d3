//! Surface evaluation: points, partial derivatives, normals, domains and periods for every
//! [`Surface`] variant.

use std::f64::consts::{FRAC_PI_2, TAU};

use crate::eval::wrapped_range;
use crate::{Frame, Surface, Vec3};

/// A surface's point with first and second partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    /// `S(u, v)`.
    pub point: Vec3,
    /// `∂S/∂u`.
    pub du: Vec3,
    /// `∂S/∂v`.
    pub dv: Vec3,
    /// `∂²S/∂u²`.
    pub duu: Vec3,
    /// `∂²S/∂u∂v`.
    pub duv: Vec3,
    /// `∂²S/∂v²`.
    pub dvv: Vec3,
}

/// Partial derivatives `d[i][j] = ∂ⁱ⁺ʲS/∂uⁱ∂vʲ` for `i + j ≤ 3` (other entries unused).
pub(crate) type Ders = [[Vec3; 4]; 4];

/// Relative step of the central differences giving third derivatives of offset surfaces
/// (consumed only by nested offsets).
const FD_STEP: f64 = 1e-4;

impl Surface {
    /// The point at `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> Vec3 {
        match self {
            // Point-only basis, without filling the 4 × 4 derivative array `ders` returns.
            Surface::BSpline(b) => b.point_at(u, v),
            Surface::Trimmed { basis, .. } => basis.eval(u, v),
            _ => self.ders(u, v, 0)[0][0],
        }
    }

    /// Point, first and second partial derivatives at `(u, v)`.
    pub fn derivs(&self, u: f64, v: f64) -> SurfaceDerivs {
        let d = self.ders(u, v, 2);
        SurfaceDerivs {
            point: d[0][0],
            du: d[1][0],
            dv: d[0][1],
            duu: d[2][0],
            duv: d[1][1],
            dvv: d[0][2],
        }
    }

    /// The unit normal `normalize(∂S/∂u × ∂S/∂v)` at `(u, v)`.
    ///
    /// Where the partials are parallel (sphere poles, cone apex, degenerate B-spline edges)
    /// the normal of a point a tiny parameter step inside the domain is returned instead,
    /// which is the limit normal at such poles; `None` when that fails too (degenerate
    /// surfaces, non-finite input).
    pub fn normal(&self, u: f64, v: f64) -> Option<Vec3> {
        if let Some(n) = self.normal_exact(u, v) {
            return Some(n);
        }
        let ((u0, u1), (v0, v1)) = self.domain();
        let step = |a: f64, b: f64, x: f64| {
            let span = if (b - a).is_finite() { b - a } else { 1.0 };
            let h = 1e-7 * span.max(x.abs()).max(1e-9);
            // Step towards the inside of the domain.
            if x + h > b { -h } else { h }
        };
        let (hu, hv) = (step(u0, u1, u), step(v0, v1, v));
        [
            (u, v + hv),
            (u + hu, v),
            (u + hu, v + hv),
            (u, v - hv),
            (u - hu, v),
        ]
        .into_iter()
        .find_map(|(a, b)| self.normal_exact(a, b))
    }

    fn normal_exact(&self, u: f64, v: f64) -> Option<Vec3> {
        let d = self.ders(u, v, 1);
        let (su, sv) = (d[1][0], d[0][1]);
        let n = su.cross(sv);
        let len = n.length();
        let scale = su.length() * sv.length();
        (len.is_finite() && len > 1e-12 * scale && len > 0.0).then(|| n / len)
    }

    /// The natural parameter rectangle `((u_min, u_max), (v_min, v_max))`; unbounded
    /// directions are `±∞` (plane; cylinder, cone and extrusion along v; a revolution or
    /// extrusion of an unbounded profile along u).
    ///
    /// A trimmed surface whose first value exceeds the second in a periodic direction wraps
    /// forward, like a trimmed periodic curve (`(u0, u1 + period)`).
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        const ALL: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);
        match self {
            Surface::Plane { .. } => (ALL, ALL),
            Surface::Cylinder { .. } | Surface::Cone { .. } => ((0.0, TAU), ALL),
            Surface::Sphere { .. } => ((0.0, TAU), (-FRAC_PI_2, FRAC_PI_2)),
            Surface::Torus { .. } => ((0.0, TAU), (0.0, TAU)),
            Surface::BSpline(b) if b.is_well_formed() => b.domain(),
            Surface::BSpline(_) => ((0.0, 0.0), (0.0, 0.0)),
            Surface::Revolution { profile, .. } => ((0.0, TAU), profile.domain().unwrap_or(ALL)),
            Surface::Extrusion { profile, .. } => (profile.domain().unwrap_or(ALL), ALL),
            Surface::Offset { basis, .. } => basis.domain(),
            Surface::Trimmed {
                basis,
                u0,
                u1,
                v0,
                v1,
            } => (
                wrapped_range(*u0, *u1, basis.u_period()),
                wrapped_range(*v0, *v1, basis.v_period()),
            ),
        }
    }

    /// The period in u, for surfaces closed and periodic in u: `2π` for cylinder, cone,
    /// sphere, torus and revolutions; the profile's for extrusions of periodic curves.
    /// B-splines report `None` (evaluation does not wrap), as do trimmed surfaces.
    pub fn u_period(&self) -> Option<f64> {
        match self {
            Surface::Cylinder { .. }
            | Surface::Cone { .. }
            | Surface::Sphere { .. }
            | Surface::Torus { .. }
            | Surface::Revolution { .. } => Some(TAU),
            Surface::Extrusion { profile, .. } => profile.period(),
            Surface::Offset { basis, .. } => basis.u_period(),
            Surface::Plane { .. } | Surface::BSpline(_) | Surface::Trimmed { .. } => None,
        }
    }

    /// The period in v: `2π` for tori, the profile's for revolutions of periodic curves, else
    /// `None`.
    pub fn v_period(&self) -> Option<f64> {
        match self {
            Surface::Torus { .. } => Some(TAU),
            Surface::Revolution { profile, .. } => profile.period(),
            Surface::Offset { basis, .. } => basis.v_period(),
            _ => None,
        }
    }

    /// Partial derivatives up to total order `order` (≤ 3) at `(u, v)`; higher entries may
    /// be left zero.
    pub(crate) fn ders(&self, u: f64, v: f64, order: usize) -> Ders {
        let mut d = [[Vec3::ZERO; 4]; 4];
        match self {
            Surface::Plane { frame } => {
                d[0][0] = frame.origin + frame.x * u + frame.y * v;
                d[1][0] = frame.x;
                d[0][1] = frame.y;
            }
            Surface::Cylinder { frame, radius } => {
                let r = *radius;
                rotational(&mut d, frame, u, [r, 0.0, 0.0, 0.0], [v, 1.0, 0.0, 0.0]);
            }
            Surface::Cone {
                frame,
                radius,
                semi_angle,
            } => {
                let t = semi_angle.tan();
                let f = [radius + v * t, t, 0.0, 0.0];
                rotational(&mut d, frame, u, f, [v, 1.0, 0.0, 0.0]);
            }
            Surface::Sphere { frame, radius } => {
                let r = *radius;
                let (s, c) = v.sin_cos();
                let f = [r * c, -r * s, -r * c, r * s];
                let g = [r * s, r * c, -r * s, -r * c];
                rotational(&mut d, frame, u, f, g);
            }
            Surface::Torus {
                frame,
                major_radius,
                minor_radius,
            } => {
                let r = *minor_radius;
                let (s, c) = v.sin_cos();
                let f = [major_radius + r * c, -r * s, -r * c, r * s];
                let g = [r * s, r * c, -r * s, -r * c];
                rotational(&mut d, frame, u, f, g);
            }
            Surface::BSpline(b) => b.derivatives_into(u, v, order, &mut d),
            Surface::Revolution {
                profile,
                axis_origin,
                axis_direction,
            } => {
                let a = axis_direction.try_normalize().unwrap_or(Vec3::Z);
                let p = profile.ders(v, order);
                let (s, c) = u.sin_cos();
                for (j, &pj) in p.iter().enumerate().take(order + 1) {
                    // Only the point itself is measured from the axis origin.
                    let w = if j == 0 { pj - *axis_origin } else { pj };
                    let axial = a * a.dot(w);
                    let perp = w - axial;
                    let side = a.cross(w);
                    // d^i/du^i of (cos u, sin u) = (cos(u + iπ/2), sin(u + iπ/2)).
                    let trig = [(c, s), (-s, c), (-c, -s), (s, -c)];
                    for (i, &(ci, si)) in trig.iter().enumerate().take(order + 1 - j) {
                        d[i][j] = perp * ci + side * si;
                    }
                    d[0][j] += axial;
                }
                d[0][0] += *axis_origin;
            }
            Surface::Extrusion { profile, direction } => {
                let p = profile.ders(u, order);
                for (i, &pi) in p.iter().enumerate() {
                    d[i][0] = pi;
                }
                d[0][0] += *direction * v;
                d[0][1] = *direction;
            }
            Surface::Offset { basis, distance } => {
                d = offset_ders2(basis, *distance, u, v, order.min(2));
                if order >= 3 {
                    // Third partials by central differences of the exact second ones; only
                    // nested offsets use them (exact ones would need fourth partials).
                    let hu = FD_STEP * u.abs().max(1.0);
                    let hv = FD_STEP * v.abs().max(1.0);
                    let up = offset_ders2(basis, *distance, u + hu, v, 2);
                    let um = offset_ders2(basis, *distance, u - hu, v, 2);
                    let vp = offset_ders2(basis, *distance, u, v + hv, 2);
                    let vm = offset_ders2(basis, *distance, u, v - hv, 2);
                    d[3][0] = (up[2][0] - um[2][0]) / (2.0 * hu);
                    d[2][1] = (up[1][1] - um[1][1]) / (2.0 * hu);
                    d[1][2] = (vp[1][1] - vm[1][1]) / (2.0 * hv);
                    d[0][3] = (vp[0][2] - vm[0][2]) / (2.0 * hv);
                }
            }
            Surface::Trimmed { basis, .. } => d = basis.ders(u, v, order),
        }
        d
    }
}

/// Fills the derivatives of `S = o + f(v) E(u) + g(v) z`, `E(u) = cos u x + sin u y`, from
/// `f` and `g` and their first three derivatives: cylinder, cone, sphere and torus all have
/// this form, and `∂ⁱ∂ʲS = f⁽ʲ⁾ E⁽ⁱ⁾ + [i = 0] g⁽ʲ⁾ z`.
fn rotational(d: &mut Ders, frame: &Frame, u: f64, f: [f64; 4], g: [f64; 4]) {
    let (s, c) = u.sin_cos();
    let e0 = frame.x * c + frame.y * s;
    let e1 = frame.y * c - frame.x * s;
    let e = [e0, e1, -e0, -e1];
    for i in 0..4 {
        for j in 0..(4 - i) {
            d[i][j] = e[i] * f[j];
            if i == 0 {
                d[i][j] += frame.z * g[j];
            }
        }
    }
    d[0][0] += frame.origin;
}

/// Offset surface derivatives up to order 2: `S = B + d·N`, `N = W/|W|`, `W = Bu × Bv`.
/// `W`'s partials follow from the product rule (needing `B`'s third partials); `N`'s from
/// `N_a = (W_a − N s_a)/s`, `s = |W|`, `s_a = N·W_a`, and
/// `N_ab = W_ab/s − (W_a s_b + W_b s_a + W s_ab)/s² + 2 W s_a s_b/s³` with
/// `s_ab = (W_a·W_b + W·W_ab − s_a s_b)/s`. Where `W` vanishes (a singular point of the
/// basis) the basis derivatives are returned unchanged.
fn offset_ders2(basis: &Surface, dist: f64, u: f64, v: f64, order: usize) -> Ders {
    let b = basis.ders(u, v, order + 1);
    let w = b[1][0].cross(b[0][1]);
    let s = w.length();
    if s.is_nan() || s <= 1e-300 || !s.is_finite() {
        return b;
    }
    let mut d = b;
    let n = w / s;
    d[0][0] += n * dist;
    if order == 0 {
        return d;
    }
    let (su, sv) = (b[1][0], b[0][1]);
    let wu = b[2][0].cross(sv) + su.cross(b[1][1]);
    let wv = b[1][1].cross(sv) + su.cross(b[0][2]);
    let (su_s, sv_s) = (n.dot(wu), n.dot(wv));
    let nu = (wu - n * su_s) / s;
    let nv = (wv - n * sv_s) / s;
    d[1][0] += nu * dist;
    d[0][1] += nv * dist;
    if order == 1 {
        return d;
    }
    let wuu = b[3][0].cross(sv) + 2.0 * b[2][0].cross(b[1][1]) + su.cross(b[2][1]);
    let wuv = b[2][1].cross(sv) + b[2][0].cross(b[0][2]) + su.cross(b[1][2]);
    let wvv = b[1][2].cross(sv) + 2.0 * b[1][1].cross(b[0][2]) + su.cross(b[0][3]);
    let second = |wa: Vec3, wb: Vec3, wab: Vec3, sa: f64, sb: f64| {
        let sab = (wa.dot(wb) + w.dot(wab) - sa * sb) / s;
        wab / s - (wa * sb + wb * sa + w * sab) / (s * s) + w * (2.0 * sa * sb / (s * s * s))
    };
    d[2][0] += second(wu, wu, wuu, su_s, su_s) * dist;
    d[1][1] += second(wu, wv, wuv, su_s, sv_s) * dist;
    d[0][2] += second(wv, wv, wvv, sv_s, sv_s) * dist;
    d
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI};

    use crate::{Curve, Frame, Surface, Vec3};

    #[test]
    fn sphere_pole_normal_falls_back() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 2.0,
        };
        let n = s.normal(0.3, FRAC_PI_2).unwrap();
        assert!((n - Vec3::Z).length() < 1e-5);
        let n = s.normal(0.3, 0.0).unwrap();
        assert!((n - Vec3::new(0.3f64.cos(), 0.3f64.sin(), 0.0)).length() < 1e-14);
    }

    #[test]
    fn revolution_of_line_is_cylinder() {
        let rev = Surface::Revolution {
            profile: Box::new(Curve::Line {
                origin: Vec3::new(2.0, 0.0, 0.0),
                direction: Vec3::Z,
            }),
            axis_origin: Vec3::ZERO,
            axis_direction: Vec3::Z,
        };
        let cyl = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 2.0,
        };
        for (u, v) in [(0.0, 0.0), (1.0, 0.5), (-2.0, 3.0)] {
            // Both: u the angle, v along the axis.
            assert!((rev.eval(u, v) - cyl.eval(u, v)).length() < 1e-14);
            let a = rev.derivs(u, v);
            let b = cyl.derivs(u, v);
            assert!((a.du - b.du).length() < 1e-14 && (a.dv - b.dv).length() < 1e-14);
            assert!((a.duu - b.duu).length() < 1e-14 && (a.duv - b.duv).length() < 1e-14);
        }
        assert_eq!(rev.u_period(), Some(2.0 * PI));
        assert_eq!(rev.v_period(), None);
    }

    #[test]
    fn offset_sphere_is_bigger_sphere() {
        let s = Surface::Offset {
            basis: Box::new(Surface::Sphere {
                frame: Frame::WORLD,
                radius: 2.0,
            }),
            distance: 1.0,
        };
        let d = s.derivs(0.7, 0.4);
        let big = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 3.0,
        }
        .derivs(0.7, 0.4);
        for (a, b) in [
            (d.point, big.point),
            (d.du, big.du),
            (d.dv, big.dv),
            (d.duu, big.duu),
            (d.duv, big.duv),
            (d.dvv, big.dvv),
        ] {
            assert!((a - b).length() < 1e-13, "{a} vs {b}");
        }
    }

    #[test]
    fn degenerate_surfaces_are_finite() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 0.0,
        };
        assert_eq!(s.normal(0.1, 0.2), None);
        assert!(s.eval(0.1, 0.2).is_finite());
        let o = Surface::Offset {
            basis: Box::new(s),
            distance: 1.0,
        };
        let d = o.ders(0.3, 0.2, 3);
        assert!(d.iter().flatten().all(|p| p.is_finite()));
    }
}
