//! The (u, v) → triangulation-plane scaling and the curvature-based sampling steps.

use cadre_geom::{Surface, Vec2};

use crate::MeshParams;

/// Largest stretch of the metric plane, either way, beyond the isotropic-in-3D scaling, that
/// a face falls back to when the stretch its curvature asks for ([`WIDE_STRETCH`]) makes
/// refinement run away.
///
/// Measured on the corpus at `--deflection-rel 0.001 --angle 0.5` with this cap alone: the
/// uncapped stretch ran away wherever the boundary did not already hold the columns a long
/// thin triangle needs (a cone face with notches, bug30053.stp #944: 20,000 folded points
/// instead of 553), because midpoint splits of skewed edges kept creating new rows; 1.8 M
/// triangles (5.8× OCCT) and 32 faces stopped by the budget. Capped at 2, 3, 5 or 10: 0.27 M
/// triangles (0.86×), none stopped; the cap matters little within that range. But a capped
/// stretch costs plain cylinders many interior points, hence the first, wide attempt.
pub(crate) const MAX_STRETCH: f64 = 4.0;

/// The stretch a face first tries: whatever the curvature asks for, bounded only to keep the
/// triangulation plane well conditioned (a cylinder: long thin triangles along its rulings,
/// often no interior point at all).
pub(crate) const WIDE_STRETCH: f64 = 1e4;

/// Affine map from (u, v) to the plane the Delaunay triangulation works in: each parameter
/// is scaled by a representative speed `|∂S/∂u|`, `|∂S/∂v|`, so circumcircle tests there
/// approximate 3D ones and triangles come out roughly isotropic on the surface.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Metric {
    /// (u, v) mapped to the origin (the domain's lower corner, for conditioning).
    pub origin: Vec2,
    /// Scale of u.
    pub su: f64,
    /// Scale of v.
    pub sv: f64,
}

impl Metric {
    /// Samples the domain box on a 5 × 5 grid: the average parameter speeds give an
    /// isotropic-in-3D scaling, which flat faces use. Curved faces divide each speed by the
    /// 3D step the curvature allows in that direction (a flat direction counts as coarse as
    /// the domain is long), so the Delaunay criterion favours the anisotropic triangles a
    /// cylinder wants (thin across the curvature, long along the rulings) instead of
    /// filling it with isotropic ones, up to [`MAX_STRETCH`]. Zero speeds (poles, apexes) are
    /// skipped.
    pub fn new(
        surface: &Surface,
        lo: Vec2,
        hi: Vec2,
        tol: &StepTol,
        planar: bool,
        max_stretch: f64,
    ) -> Metric {
        const N: usize = 5;
        let (mut su, mut nu, mut sv, mut nv) = (0.0, 0usize, 0.0, 0usize);
        let (mut hu, mut hv) = (f64::INFINITY, f64::INFINITY);
        for i in 0..N {
            for j in 0..N {
                let t = Vec2::new((i as f64 + 0.5) / N as f64, (j as f64 + 0.5) / N as f64);
                let uv = lo + (hi - lo) * t;
                let d = surface.derivs(uv.x, uv.y);
                let (a, b) = (d.du.length(), d.dv.length());
                if a.is_finite() && a > 0.0 {
                    su += a;
                    nu += 1;
                }
                if b.is_finite() && b > 0.0 {
                    sv += b;
                    nv += 1;
                }
                if !planar && let Some((du, dv)) = tol.steps(surface, uv.x, uv.y) {
                    hu = hu.min(du * a);
                    hv = hv.min(dv * b);
                }
            }
        }
        let mut su = if nu > 0 { su / nu as f64 } else { 1.0 };
        let mut sv = if nv > 0 { sv / nv as f64 } else { 1.0 };
        if nu == 0 {
            su = sv;
        } else if nv == 0 {
            sv = su;
        }
        if hu.is_finite() || hv.is_finite() {
            let (eu, ev) = ((hi.x - lo.x) * su, (hi.y - lo.y) * sv);
            let hu2 = hu.min(eu.max(hv.min(ev)));
            let hv2 = hv.min(ev.max(hu2));
            let r = (hv2 / hu2).clamp(1.0 / max_stretch, max_stretch);
            if r.is_finite() && r > 0.0 {
                su *= r;
            }
        }
        let r = (su / sv).clamp(1e-8, 1e8);
        su = sv * r;
        Metric { origin: lo, su, sv }
    }

    /// The triangulation-plane position of `uv`; values below spade's smallest accepted
    /// magnitude are flushed to zero.
    pub fn to_plane(self, uv: Vec2) -> spade::Point2<f64> {
        let flush = |x: f64| if x.abs() < 1e-40 { 0.0 } else { x };
        spade::Point2::new(
            flush((uv.x - self.origin.x) * self.su),
            flush((uv.y - self.origin.y) * self.sv),
        )
    }

    /// The (u, v) of a triangulation-plane position: the inverse of [`Metric::to_plane`],
    /// for vertices the triangulator creates itself (split points of crossing trims).
    pub fn plane_to_uv(self, p: spade::Point2<f64>) -> Vec2 {
        Vec2::new(self.origin.x + p.x / self.su, self.origin.y + p.y / self.sv)
    }
}

/// Whether the surface is flat, so that no interior point or refinement is needed.
pub(crate) fn is_planar(surface: &Surface) -> bool {
    match surface {
        Surface::Plane { .. } => true,
        Surface::Trimmed { basis, .. } | Surface::Offset { basis, .. } => is_planar(basis),
        _ => false,
    }
}

/// Tolerances a sampling step must meet.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepTol {
    deflection: f64,
    angle: f64,
}

impl StepTol {
    /// From the mesh parameters (non-positive or non-finite values fall back to defaults so
    /// the step stays finite).
    pub fn new(params: &MeshParams) -> StepTol {
        let deflection = if params.deflection.is_finite() && params.deflection > 0.0 {
            params.deflection
        } else {
            MeshParams::default().deflection
        };
        let angle = if params.angle.is_finite() && params.angle > 0.0 {
            params.angle.min(std::f64::consts::FRAC_PI_2)
        } else {
            MeshParams::default().angle
        };
        StepTol { deflection, angle }
    }

    /// Largest distance between the mesh and the surface.
    pub fn deflection(&self) -> f64 {
        self.deflection
    }

    /// Largest angle between corner normals of a triangle.
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// Arc length on a normal section of curvature `k` (1/radius) whose chord deviates at
    /// most `d` and turns at most `angle`; infinite when flat.
    fn chord(&self, k: f64, d: f64, angle: f64) -> f64 {
        if !k.is_finite() || k <= 1e-300 {
            return f64::INFINITY;
        }
        let r = 1.0 / k;
        let by_dev = if d >= r {
            std::f64::consts::PI
        } else {
            2.0 * (1.0 - d / r).acos()
        };
        // Arc length, so that the parameter step of a circle is exactly its angle step.
        r * by_dev.min(angle)
    }

    /// Parameter steps `(Δu, Δv)` at `(u, v)` from the normal curvatures of the iso-lines
    /// (and the twist, which bends the diagonals). `None` where the surface is singular.
    pub fn steps(&self, surface: &Surface, u: f64, v: f64) -> Option<(f64, f64)> {
        let d = surface.derivs(u, v);
        let (lu, lv) = (d.du.length(), d.dv.length());
        let n = d.du.cross(d.dv);
        let ln = n.length();
        // Near a pole one speed is tiny but not zero (rational B-spline spheres, pr1db.stp
        // #565: |∂S/∂u| ~ 1e-14 of |∂S/∂v|), and the twist term below, divided by it, asked
        // for a v step of 1e-16: treat such points as singular too.
        let (slow, fast) = (lu.min(lv), lu.max(lv));
        if !(slow > 1e-7 * fast && ln > 1e-12 * lu * lv && ln.is_finite()) {
            return None;
        }
        // A side collapsed to within the deflection is a pole to the mesh (a quarter step of
        // the parameter moves the point by less than the deflection, so no triangle can tell
        // it from a point): t4mec.stp face #472, a B-spline quarter sphere whose pole sides
        // are 0.003 mm long and folded, asked there for steps of 1e-5 and got a
        // 100,000-point grid.
        let ((u0, u1), (v0, v1)) = surface.domain();
        let quarter = |a: f64, b: f64| {
            if (b - a).is_finite() {
                0.25 * (b - a)
            } else {
                1.0
            }
        };
        let pole = self.deflection;
        if lu * quarter(u0, u1) <= pole || lv * quarter(v0, v1) <= pole {
            return None;
        }
        let n = n / ln;
        let twist = (d.duv.dot(n) / (lu * lv)).abs();
        let ku = (d.duu.dot(n) / (lu * lu)).abs().max(twist);
        let kv = (d.dvv.dot(n) / (lv * lv)).abs().max(twist);
        // A grid on a doubly curved surface has triangles whose circumradius exceeds half
        // the step (the cell diagonal); tighten both tolerances so the triangles, not only
        // the grid lines, meet them.
        let (kmin, kmax) = (ku.min(kv), ku.max(kv));
        let both = kmax > 0.0 && kmin > 0.05 * kmax;
        let (dd, aa) = if both {
            (
                0.5 * self.deflection,
                std::f64::consts::FRAC_1_SQRT_2 * self.angle,
            )
        } else {
            (self.deflection, self.angle)
        };
        Some((self.chord(ku, dd, aa) / lu, self.chord(kv, dd, aa) / lv))
    }
}

/// Breaks of `[lo, hi]` for sampling curvature: the B-spline knots inside (thinned to at most
/// `MAX_SPANS` spans), otherwise `UNIFORM` equal spans. Always starts at `lo`, ends at `hi`.
pub(crate) fn breaks(surface: &Surface, lo: f64, hi: f64, along_u: bool) -> Vec<f64> {
    const MAX_SPANS: usize = 24;
    const UNIFORM: usize = 4;
    let knots = spline_knots(surface, along_u);
    let mut out = vec![lo];
    match knots {
        Some(k) => {
            let inner: Vec<f64> = {
                let mut v: Vec<f64> = k.iter().copied().filter(|&x| x > lo && x < hi).collect();
                v.dedup();
                v
            };
            let stride = inner.len().div_ceil(MAX_SPANS).max(1);
            out.extend(inner.iter().copied().skip(stride - 1).step_by(stride));
        }
        None => {
            out.extend((1..UNIFORM).map(|i| lo + (hi - lo) * i as f64 / UNIFORM as f64));
        }
    }
    if hi > lo {
        out.push(hi);
    }
    out.dedup();
    out
}

fn spline_knots(surface: &Surface, along_u: bool) -> Option<&[f64]> {
    match surface {
        Surface::BSpline(b) => Some(if along_u { &b.u_knots } else { &b.v_knots }),
        Surface::Trimmed { basis, .. } | Surface::Offset { basis, .. } => {
            spline_knots(basis, along_u)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::Frame;

    #[test]
    fn cylinder_steps_follow_the_circle() {
        let s = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 5.0,
        };
        let tol = StepTol::new(&MeshParams {
            deflection: 0.01,
            angle: 0.5,
            max_face_points: 1000,
        });
        let (du, dv) = tol.steps(&s, 0.3, 1.0).unwrap();
        // Chord with sagitta 0.01 on radius 5.
        let expect = 2.0 * (1.0f64 - 0.01 / 5.0).acos();
        assert!((du - expect).abs() < 1e-9, "{du} vs {expect}");
        assert!(dv.is_infinite());
        // Anisotropic: u in units of the arc step, v in units of the height, up to the
        // largest stretch.
        let wide = Metric::new(
            &s,
            Vec2::ZERO,
            Vec2::new(1.0, 10.0),
            &tol,
            false,
            WIDE_STRETCH,
        );
        assert!((wide.su / wide.sv - 10.0 / expect).abs() < 1e-9, "{wide:?}");
        let m = Metric::new(
            &s,
            Vec2::ZERO,
            Vec2::new(1.0, 10.0),
            &tol,
            false,
            MAX_STRETCH,
        );
        assert!((m.su / m.sv - 5.0 * MAX_STRETCH).abs() < 1e-9, "{m:?}");
        let short = Metric::new(
            &s,
            Vec2::ZERO,
            Vec2::new(1.0, 2.0),
            &tol,
            false,
            MAX_STRETCH,
        );
        let stretch = 2.0 / (expect * 5.0);
        assert!(stretch > 1.0 && stretch < MAX_STRETCH);
        assert!(
            (short.su / short.sv - 5.0 * stretch).abs() < 1e-9,
            "{short:?}"
        );
        let flat = Metric::new(
            &s,
            Vec2::ZERO,
            Vec2::new(1.0, 10.0),
            &tol,
            true,
            WIDE_STRETCH,
        );
        assert!((flat.su / flat.sv - 5.0).abs() < 1e-12);
    }

    #[test]
    fn points_next_to_a_pole_count_as_singular() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 5.0,
        };
        let tol = StepTol::new(&MeshParams::default());
        assert!(tol.steps(&s, 0.3, 0.2).is_some());
        // |∂S/∂u| is 1e-9 of |∂S/∂v| here.
        assert!(
            tol.steps(&s, 0.3, std::f64::consts::FRAC_PI_2 - 1e-9)
                .is_none()
        );
    }

    #[test]
    fn a_side_collapsed_within_the_deflection_counts_as_singular() {
        // 1e-5 from a sphere's pole the parallel is 1e-5 of the meridian speed (the relative
        // test lets it through) but a quarter turn moves the point 8e-5 mm.
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 5.0,
        };
        let v = std::f64::consts::FRAC_PI_2 - 1e-5;
        let coarse = StepTol::new(&MeshParams {
            deflection: 1.0,
            ..MeshParams::default()
        });
        assert!(coarse.steps(&s, 0.3, v).is_none());
        // Control: at a deflection far below that movement the point is an ordinary one.
        let fine = StepTol::new(&MeshParams {
            deflection: 1e-6,
            ..MeshParams::default()
        });
        assert!(fine.steps(&s, 0.3, v).is_some());
    }

    #[test]
    fn breaks_cover_range() {
        let s = Surface::Plane {
            frame: Frame::WORLD,
        };
        let b = breaks(&s, 1.0, 2.0, true);
        assert_eq!(b, vec![1.0, 1.25, 1.5, 1.75, 2.0]);
    }
}
