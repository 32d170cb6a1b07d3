//! Swept faces of the trim back-end: surfaces of linear extrusion `S = C(u) + v d` and of
//! revolution `S = c + R_a(u) (C(v) − c)` (a rotation by the angle u about the unit axis
//! `a` through `c`), evaluated on the GPU from their profile curve `C` in the parameters the
//! file's pcurves use (`sweep.wgsl` is the GPU twin). A B-spline route would not keep them:
//! a circle's rational B-spline is not parameterised by its angle.
//!
//! A profile is packed at the end of [`TrimScene::bspline_data`](crate::trim_surfaces::TrimScene)
//! behind a kind word (`u32` bits): [`PROFILE_BSPLINE`] then degree and control points
//! (`u32` bits), knots and homogeneous control points (x w, y w, z w, w); [`PROFILE_LINE`]
//! and [`PROFILE_ELLIPSE`] then nine numbers `o`, `X`, `Y`: `C(t) = o + t X` and
//! `C(t) = o + cos t X + sin t Y` (a circle's `X`, `Y` are its radius times its axes).

use cadre_geom::{Curve3, Surface};
use glam::DVec3;

use crate::trim_surfaces::{
    MAX_BSPLINE_DEGREE, NO_BREAKS, SURFACE_EXTRUSION, SURFACE_REVOLUTION, TrimFaceSurface,
    pack_breaks,
};

/// Profile kind: a (rational) B-spline curve.
pub const PROFILE_BSPLINE: u32 = 0;
/// Profile kind: the line `o + t X`.
pub const PROFILE_LINE: u32 = 1;
/// Profile kind: the ellipse (or circle) `o + cos t X + sin t Y`.
pub const PROFILE_ELLIPSE: u32 = 2;

/// Samples per knot span, and per box side where the profile has no knots, when bounding a
/// sweep's second derivatives.
const CURVATURE_SAMPLES: usize = 16;

/// The record of a face on the swept `surface` over the (u, v) box `origin + [0, size]`
/// (its profile packed at the end of `data`), or why the GPU cannot draw it.
pub fn sweep_surface(
    surface: &Surface,
    tree: u32,
    (origin, size): ([f64; 2], [f64; 2]),
    data: &mut Vec<f32>,
) -> Result<TrimFaceSurface, String> {
    let (kind, profile, frame) = match surface {
        Surface::Extrusion { profile, direction } => (
            SURFACE_EXTRUSION,
            profile,
            [DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, *direction],
        ),
        Surface::Revolution {
            profile,
            axis_origin,
            axis_direction,
        } => {
            let axis = axis_direction.normalize_or_zero();
            if axis == DVec3::ZERO {
                return Err("surface of revolution without an axis direction".to_string());
            }
            (
                SURFACE_REVOLUTION,
                profile,
                [*axis_origin, DVec3::ZERO, DVec3::ZERO, axis],
            )
        }
        other => return Err(format!("{} is not a sweep", other.type_name())),
    };
    // The profile is packed relative to the frame's origin (a point near the face: f32
    // keeps its precision there, see `trim_surfaces::net_centre`); a revolution's is moved
    // along its axis to the foot of the profile's centre, which turns the same.
    let near = profile_anchor(profile);
    let frame = if kind == SURFACE_REVOLUTION {
        let [o, x, y, axis] = frame;
        [o + axis * (near - o).dot(axis), x, y, axis]
    } else {
        let [_, x, y, z] = frame;
        [near, x, y, z]
    };
    let start = data.len();
    let (at, knots) = match pack_profile(profile, frame[0], data) {
        Ok(packed) => packed,
        Err(why) => {
            data.truncate(start);
            return Err(why);
        }
    };
    // The profile runs along u for an extrusion, along v for a revolution; its knots are
    // grid lines (a degree-1 profile folds there).
    let (u_knots, v_knots): (&[f64], &[f64]) = if kind == SURFACE_EXTRUSION {
        (&knots, &[])
    } else {
        (&[], &knots)
    };
    let breaks = if knots.is_empty() {
        NO_BREAKS
    } else {
        pack_breaks((u_knots, v_knots), origin, size, data)
    };
    Ok(TrimFaceSurface {
        kind,
        frame,
        params: [0.0; 2],
        tree,
        uv_origin: origin,
        uv_size: size,
        curvature: sampled_curvature(surface, (u_knots, v_knots), origin, size),
        data: at,
        breaks,
    })
}

/// A point near the profile `curve`: the centre of a B-spline's control points, a line's or
/// a conic's origin.
fn profile_anchor(curve: &Curve3) -> DVec3 {
    match curve {
        Curve3::Trimmed { basis, .. } => profile_anchor(basis),
        Curve3::Line { origin, .. } => *origin,
        Curve3::Circle { frame, .. } | Curve3::Ellipse { frame, .. } => frame.origin,
        Curve3::BSpline(b) => crate::trim_surfaces::net_centre(b.control_points.iter().copied()),
        _ => DVec3::ZERO,
    }
}

/// Packs `curve` as a sweep's profile at the end of `data`, its points relative to `anchor`
/// (the record's origin): its offset and its interior knots (none but a B-spline's), or
/// why the GPU cannot evaluate it.
fn pack_profile(
    curve: &Curve3,
    anchor: DVec3,
    data: &mut Vec<f32>,
) -> Result<(u32, Vec<f64>), String> {
    let at = u32::try_from(data.len()).map_err(|_| "profile data past 2³² floats".to_string())?;
    let word = |n: usize| f32::from_bits(n as u32);
    let vectors = |data: &mut Vec<f32>, kind: u32, v: [DVec3; 3]| {
        data.push(f32::from_bits(kind));
        data.extend(v.iter().flat_map(|v| v.to_array()).map(|x| x as f32));
    };
    match curve {
        // A trimmed curve keeps its basis' parameter.
        Curve3::Trimmed { basis, .. } => return pack_profile(basis, anchor, data),
        Curve3::Line { origin, direction } => {
            vectors(
                data,
                PROFILE_LINE,
                [*origin - anchor, *direction, DVec3::ZERO],
            );
        }
        Curve3::Circle { frame, radius } => vectors(
            data,
            PROFILE_ELLIPSE,
            [frame.origin - anchor, frame.x * *radius, frame.y * *radius],
        ),
        Curve3::Ellipse { frame, a, b } => {
            vectors(
                data,
                PROFILE_ELLIPSE,
                [frame.origin - anchor, frame.x * *a, frame.y * *b],
            );
        }
        Curve3::BSpline(b) => {
            let n = b.control_points.len();
            if b.degree > MAX_BSPLINE_DEGREE {
                return Err(format!(
                    "profile B-spline of degree {}: the GPU evaluates degrees up to {MAX_BSPLINE_DEGREE}",
                    b.degree
                ));
            }
            if n <= b.degree || b.knots.len() != n + b.degree + 1 {
                return Err("profile B-spline not well formed".to_string());
            }
            data.push(f32::from_bits(PROFILE_BSPLINE));
            data.extend([word(b.degree), word(n)]);
            data.extend(b.knots.iter().map(|&k| k as f32));
            for (i, c) in b.control_points.iter().enumerate() {
                let w = b.weights.as_ref().map_or(1.0, |w| w[i]);
                let c = *c - anchor;
                data.extend([c.x * w, c.y * w, c.z * w, w].map(|x| x as f32));
            }
            return Ok((at, b.knots.clone()));
        }
        other => {
            return Err(format!(
                "surface swept from a {} profile: no GPU evaluator yet",
                other.type_name().to_lowercase()
            ));
        }
    }
    Ok((at, Vec::new()))
}

/// The point and first derivative of the profile packed at `at`, at `t`, as `sweep.wgsl`
/// evaluates them (a B-spline past its knots extends its end piece).
pub fn packed_profile_point(data: &[f32], at: u32, t: f64) -> (DVec3, DVec3) {
    let at = at as usize;
    let f = |k: usize| f64::from(data[k]);
    let v = |k: usize| DVec3::new(f(k), f(k + 1), f(k + 2));
    match data[at].to_bits() {
        PROFILE_BSPLINE => {
            let (p, n) = (
                data[at + 1].to_bits() as usize,
                data[at + 2].to_bits() as usize,
            );
            let knots: Vec<f64> = (0..n + p + 1).map(|k| f(at + 3 + k)).collect();
            let cp = at + 3 + n + p + 1;
            let span = cadre_geom::nurbs::basis::find_span(&knots, n, p, t);
            let basis = cadre_geom::nurbs::basis::BasisDers::new(span, t, p, 1, &knots);
            let (mut c, mut d) = (glam::DVec4::ZERO, glam::DVec4::ZERO);
            for (r, (&n0, &n1)) in basis.row(0).iter().zip(basis.row(1)).enumerate() {
                let k = cp + 4 * (span - p + r);
                let h = glam::DVec4::new(f(k), f(k + 1), f(k + 2), f(k + 3));
                c += h * n0;
                d += h * n1;
            }
            let point = c.truncate() / c.w;
            (point, (d.truncate() - point * d.w) / c.w)
        }
        PROFILE_LINE => (v(at + 1) + v(at + 4) * t, v(at + 4)),
        _ => (
            v(at + 1) + v(at + 4) * t.cos() + v(at + 7) * t.sin(),
            v(at + 7) * t.cos() - v(at + 4) * t.sin(),
        ),
    }
}

/// `q` turned by `angle` about the unit axis `a` (Rodrigues).
fn rotate(q: DVec3, a: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    q * c + a.cross(q) * s + a * (a.dot(q) * (1.0 - c))
}

/// The point of a swept face's surface at (u, v) and the direction of S_u × S_v, as
/// `sweep.wgsl` evaluates them. Where S_u × S_v vanishes on a revolution's axis (a profile
/// meeting it: the pole of a dome) the direction is taken a ten-thousandth of the box
/// towards its middle, the limit of the normals there.
pub fn sweep_point(s: &TrimFaceSurface, data: &[f32], u: f64, v: f64) -> (DVec3, DVec3) {
    // The profile is packed relative to the frame's origin (`pack_profile`).
    let [origin, _, _, axis] = s.frame;
    if s.kind == SURFACE_EXTRUSION {
        let (c, dc) = packed_profile_point(data, s.data, u);
        return (origin + c + axis * v, dc.cross(axis));
    }
    let turned = |v: f64| {
        let (c, dc) = packed_profile_point(data, s.data, v);
        let q = rotate(c, axis, u);
        let su = axis.cross(q);
        (origin + q, su, rotate(dc, axis, u), c.length())
    };
    let (point, su, sv, reach) = turned(v);
    if su.length() > 1e-5 * reach {
        return (point, su.cross(sv));
    }
    let middle = s.uv_origin[1] + 0.5 * s.uv_size[1];
    let step = 1e-4 * s.uv_size[1] * if middle < v { -1.0 } else { 1.0 };
    let (_, su, sv, _) = turned(v + step);
    (point, su.cross(sv))
}

/// Bounds of |S_uu|, |S_uv|, |S_vv| of a sweep over the box: the largest sampled (per knot
/// span of the profile, and evenly where it has none), doubled, as for rational B-splines.
fn sampled_curvature(
    surface: &Surface,
    (u_knots, v_knots): (&[f64], &[f64]),
    origin: [f64; 2],
    size: [f64; 2],
) -> [f64; 3] {
    let samples = |knots: &[f64], lo: f64, size: f64| -> Vec<f64> {
        let hi = lo + size;
        let mut cuts: Vec<f64> = knots
            .iter()
            .copied()
            .filter(|&k| k > lo && k < hi)
            .collect();
        cuts.insert(0, lo);
        cuts.push(hi);
        cuts.dedup();
        let per = CURVATURE_SAMPLES;
        let mut out: Vec<f64> = cuts
            .windows(2)
            .flat_map(|w| (0..per).map(move |k| w[0] + (w[1] - w[0]) * k as f64 / per as f64))
            .collect();
        out.push(hi);
        // At most 65 a side: every k-th.
        let k = out.len().div_ceil(65).max(1);
        out.into_iter().step_by(k).collect()
    };
    let us = samples(u_knots, origin[0], size[0]);
    let vs = samples(v_knots, origin[1], size[1]);
    let mut m = [0.0f64; 3];
    for &u in &us {
        for &v in &vs {
            let d = surface.derivs(u, v);
            for (bound, x) in m.iter_mut().zip([d.duu, d.duv, d.dvv]) {
                if x.is_finite() {
                    *bound = bound.max(x.length());
                }
            }
        }
    }
    m.map(|x| 2.0 * x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::bspline::BSplineCurve;
    use cadre_geom::curve::CurveFrame;

    /// A rational cubic B-spline profile with an interior knot, in the x-z plane.
    fn bspline_profile() -> Curve3 {
        let points: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(10.0 + 3.0 * (i as f64).sin(), 0.0, 4.0 * i as f64))
            .collect();
        let knots = vec![0.0, 0.0, 0.0, 0.0, 1.5, 3.0, 3.0, 3.0, 3.0];
        let weights = Some(vec![1.0, 1.3, 0.8, 1.1, 1.0]);
        Curve3::BSpline(BSplineCurve::try_new(3, knots, points, weights).expect("curve"))
    }

    fn sweeps() -> Vec<(Surface, [f64; 2], [f64; 2])> {
        let frame = CurveFrame {
            origin: DVec3::new(1.0, 2.0, 3.0),
            x: DVec3::X,
            y: DVec3::Z,
        };
        let axis_origin = DVec3::new(0.5, -0.5, 0.0);
        vec![
            (
                Surface::Extrusion {
                    profile: Box::new(bspline_profile()),
                    direction: DVec3::new(0.0, 7.0, 1.0),
                },
                [0.2, -1.0],
                [2.6, 3.0],
            ),
            (
                Surface::Extrusion {
                    profile: Box::new(Curve3::Ellipse {
                        frame,
                        a: 5.0,
                        b: 2.0,
                    }),
                    direction: DVec3::new(0.0, 3.0, 0.0),
                },
                [0.5, 0.0],
                [4.0, 2.0],
            ),
            (
                Surface::Revolution {
                    profile: Box::new(bspline_profile()),
                    axis_origin,
                    axis_direction: DVec3::Z,
                },
                [0.0, 0.1],
                [5.0, 2.8],
            ),
            (
                Surface::Revolution {
                    profile: Box::new(Curve3::Circle { frame, radius: 2.0 }),
                    axis_origin,
                    axis_direction: DVec3::new(0.0, 0.0, 2.0),
                },
                [1.0, -1.0],
                [4.0, 2.5],
            ),
            (
                Surface::Revolution {
                    profile: Box::new(Curve3::Line {
                        origin: DVec3::new(4.0, 0.0, 0.0),
                        direction: DVec3::new(1.0, 0.0, 2.0),
                    }),
                    axis_origin,
                    axis_direction: DVec3::Z,
                },
                [0.0, -1.0],
                [6.0, 3.0],
            ),
        ]
    }

    /// Every sweep's packed record evaluates to the model's surface, with the direction of
    /// its S_u × S_v, across the box; the curvature bounds hold the surface's second
    /// derivatives there. Negative control: another sweep's record misses it.
    #[test]
    fn packed_sweeps_are_the_model_surfaces() {
        let mut data = Vec::new();
        let records: Vec<TrimFaceSurface> = sweeps()
            .iter()
            .map(|(s, o, z)| sweep_surface(s, 0, (*o, *z), &mut data).expect("drawn"))
            .collect();
        for (k, ((surface, o, z), record)) in sweeps().iter().zip(&records).enumerate() {
            let other = &records[(k + 1) % records.len()];
            let mut missed = 0;
            for i in 0..=12 {
                for j in 0..=12 {
                    let u = o[0] + z[0] * f64::from(i) / 12.0;
                    let v = o[1] + z[1] * f64::from(j) / 12.0;
                    let (point, normal) = sweep_point(record, &data, u, v);
                    let d = surface.derivs(u, v);
                    assert!(
                        (point - d.point).length() < 1e-4,
                        "{k} ({u}, {v}): {point} vs {}",
                        d.point
                    );
                    let exact = d.du.cross(d.dv);
                    if exact.length() > 1e-6 {
                        let cos = normal.normalize().dot(exact.normalize());
                        assert!(cos > 0.9999, "{k} ({u}, {v}): normal off, cos {cos}");
                    }
                    let c = record.curvature;
                    assert!(d.duu.length() <= c[0] + 1e-9, "{k}: S_uu");
                    assert!(d.duv.length() <= c[1] + 1e-9, "{k}: S_uv");
                    assert!(d.dvv.length() <= c[2] + 1e-9, "{k}: S_vv");
                    missed +=
                        usize::from((sweep_point(other, &data, u, v).0 - d.point).length() > 1e-3);
                }
            }
            assert!(
                missed > 100,
                "{k}: another record matched {} points",
                169 - missed
            );
        }
    }

    /// A revolution whose profile meets its axis (a dome's pole) still gets a normal there:
    /// the axis' direction, as the nearby normals tend to.
    #[test]
    fn a_pole_on_the_axis_has_the_limit_normal() {
        let frame = CurveFrame {
            origin: DVec3::ZERO,
            x: DVec3::X,
            y: DVec3::Z,
        };
        let dome = Surface::Revolution {
            profile: Box::new(Curve3::Circle { frame, radius: 3.0 }),
            axis_origin: DVec3::ZERO,
            axis_direction: DVec3::Z,
        };
        let half_pi = std::f64::consts::FRAC_PI_2;
        let mut data = Vec::new();
        let s = sweep_surface(&dome, 0, ([0.0, 0.0], [6.0, half_pi]), &mut data).expect("drawn");
        let (point, normal) = sweep_point(&s, &data, 1.0, half_pi);
        assert!(
            (point - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-6,
            "{point}"
        );
        let near = dome.derivs(1.0, half_pi - 1e-3);
        let expected = near.du.cross(near.dv).normalize();
        assert!(
            normal.normalize().dot(expected) > 0.999,
            "{normal} vs {expected}"
        );
        // Negative control: without the step the normal vanishes there.
        let (c, _) = packed_profile_point(&data, s.data, half_pi);
        assert!(DVec3::Z.cross(c).length() < 1e-6);
    }

    /// Profiles the GPU has no evaluator for are refused, saying which, and leave nothing
    /// behind in the packed data.
    #[test]
    fn other_profiles_are_refused_by_name() {
        let polyline = Surface::Extrusion {
            profile: Box::new(Curve3::Polyline(vec![DVec3::ZERO, DVec3::X])),
            direction: DVec3::Z,
        };
        let mut data = vec![1.0];
        let why = sweep_surface(&polyline, 0, ([0.0; 2], [1.0; 2]), &mut data).unwrap_err();
        assert!(why.contains("polyline"), "{why}");
        assert_eq!(data, vec![1.0]);
    }
}
