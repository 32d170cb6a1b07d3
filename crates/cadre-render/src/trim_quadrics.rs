//! B-spline faces that are planes, circular cylinders or spheres, drawn as what they are. Many
//! exporters write every surface as a B-spline (I-DEAS, some CATIA and Creo settings, OCCT's
//! NURBS conversion): a drilled hole is then a rational B-spline, and the trim back-end drew
//! it from its control net, and `--method raycast` tessellated it with the other
//! B-splines. Here such a face's surface is sampled over the face, the plane, cylinder or
//! sphere through the samples is found (`cadre_brep::measure::recognise`), and, where every sample
//! lies within [`RECOGNITION_REL`] of the face's size of it (and within a hundredth of the
//! trim tolerance), a copy of the model gets the closed form in its place. The face's trim
//! loops are then found on the closed form as on any native face (its edges' points
//! projected onto it), so the trim tree is in the closed form's (u, v), and the face is ray
//! cast exactly like a drawn plane or cylinder.

use cadre_brep::measure::recognise::{RoundSurface, round_surface_through};
use cadre_brep::{FaceId, Model, SurfaceId};
use cadre_geom::{Frame, Surface, Vec3};
use rayon::prelude::*;

/// A closed form replaces a B-spline face's surface where the samples lie within this share
/// of their extent of it (a rational B-spline circle is exact to rounding; a fitted one is
/// not a circle).
pub const RECOGNITION_REL: f64 = 1e-6;

/// Samples along each side of a face's (u, v) box.
const SAMPLES: usize = 12;

/// The faces of `model` re-expressed as closed forms, and `model` with them in place (each
/// such face on a surface of its own, its sense kept); `tolerance` is the trim tolerance
/// (model units). Unchanged when no face is.
pub fn closed_form_faces(model: &Model, tolerance: f64) -> (Vec<FaceId>, Option<Model>) {
    // Face by face in parallel, as the trees are built: sampling a B-spline face and
    // projecting its edges for its (u, v) box is most of the cost.
    let found: Vec<(FaceId, Surface, bool)> = (0..model.faces.len())
        .into_par_iter()
        .filter_map(|i| {
            let face = FaceId(i as u32);
            let surface = &model.surfaces[model.faces[i].surface.index()];
            if !matches!(surface, Surface::BSpline(_)) {
                return None;
            }
            let (closed, flips) = recognised(model, face, surface, tolerance)?;
            Some((face, closed, flips))
        })
        .collect();
    if found.is_empty() {
        return (Vec::new(), None);
    }
    let mut out = model.clone();
    for (face, surface, flips) in &found {
        let id = SurfaceId(out.surfaces.len() as u32);
        out.surfaces.push(surface.clone());
        let f = &mut out.faces[face.index()];
        f.surface = id;
        f.same_sense ^= flips;
    }
    (found.into_iter().map(|(f, _, _)| f).collect(), Some(out))
}

/// The plane, cylinder or sphere a B-spline face's `surface` is over the face, and whether
/// its natural normal is the B-spline's opposite (a sphere only where a frame keeps the face
/// clear of its poles and seam, [`sphere_frame`]).
fn recognised(
    model: &Model,
    face: FaceId,
    surface: &Surface,
    tolerance: f64,
) -> Option<(Surface, bool)> {
    let f = &model.faces[face.index()];
    let acc = cadre_geom::tolerance::Accuracy::default();
    let [u0, u1, v0, v1] = cadre_brep::bounds::face_uv_box(model, f, surface, acc)?;
    let at = |k: usize, a: f64, b: f64| a + (b - a) * k as f64 / (SAMPLES - 1) as f64;
    let mut samples = Vec::with_capacity(SAMPLES * SAMPLES);
    for i in 0..SAMPLES {
        for j in 0..SAMPLES {
            let (u, v) = (at(i, u0, u1), at(j, v0, v1));
            let point = surface.eval(u, v);
            let normal = surface.normal(u, v)?;
            if !point.is_finite() {
                return None;
            }
            samples.push((point, normal));
        }
    }
    let extent = cadre_geom::BoundingBox::from_points(samples.iter().map(|s| s.0)).diagonal();
    let within = (RECOGNITION_REL * extent).min(0.01 * tolerance);
    if within.is_nan() || within <= 0.0 {
        return None;
    }
    let (mid_u, mid_v) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
    let d = surface.derivs(mid_u, mid_v);
    let centre = surface.eval(mid_u, mid_v);
    if let Some(plane) = plane_through(&samples, within, (centre, d.du, d.dv)) {
        return Some((plane, false));
    }
    match round_surface_through(&samples, within)? {
        RoundSurface::Cylinder { axis, radius, .. } => {
            // The seam (u = 0) opposite the face's middle: a face short of a whole turn
            // then lies in one span of u. A whole turn's seam is the B-spline's own
            // (its first u or v line, whichever goes round), where its loops put it.
            let foot =
                |p: Vec3| axis.origin + axis.direction * (p - axis.origin).dot(axis.direction);
            let closed_u = surface.eval(u0, mid_v).distance(surface.eval(u1, mid_v)) <= within;
            let closed_v = surface.eval(mid_u, v0).distance(surface.eval(mid_u, v1)) <= within;
            let seam = if closed_u {
                surface.eval(u0, mid_v)
            } else if closed_v {
                surface.eval(mid_u, v0)
            } else {
                2.0 * foot(centre) - centre
            };
            let x = seam - foot(seam);
            let frame = Frame::from_axis(axis.origin, axis.direction, Some(x))?;
            let cylinder = Surface::Cylinder { frame, radius };
            // The B-spline's normal against the cylinder's (outward) at the face's middle.
            let outward = centre - foot(centre);
            let flips = d.du.cross(d.dv).dot(outward) < 0.0;
            Some((cylinder, flips))
        }
        RoundSurface::Sphere {
            centre: c, radius, ..
        } => {
            let frame = sphere_frame(&samples, c)?;
            let sphere = Surface::Sphere { frame, radius };
            // The B-spline's normal against the sphere's (outward) at the face's middle.
            let flips = d.du.cross(d.dv).dot(centre - c) < 0.0;
            Some((sphere, flips))
        }
    }
}

/// Most a recognised sphere's samples may rise towards a pole of the frame chosen for them
/// (the sine of 80° of latitude): the face then keeps clear of the poles, where a sphere's
/// (u, v) collapses and a B-spline's trim loops have no pole edge to follow.
const SPHERE_LATITUDE_SIN: f64 = 0.985;

/// Least angle (radians) between a recognised sphere's samples and the seam of the frame
/// chosen for them (u = 0, opposite the face's middle).
const SPHERE_SEAM_MARGIN: f64 = 0.05;

/// A frame for a sphere centred at `centre` through `samples` in which the samples keep
/// clear of the poles and of the seam: its x axis points away from their mean direction (the
/// seam opposite the face's middle, which lies at u = π on the equator), its z axis across
/// their narrowest spread (of twelve directions about the middle, the one they rise least
/// along). `None` when no such frame is (a whole sphere, a cap over a pole of every frame,
/// a band round it).
fn sphere_frame(samples: &[(Vec3, Vec3)], centre: Vec3) -> Option<Frame> {
    let directions: Vec<Vec3> = samples
        .iter()
        .map(|(p, _)| (*p - centre).try_normalize())
        .collect::<Option<_>>()?;
    let middle = directions.iter().copied().sum::<Vec3>().try_normalize()?;
    let across = middle.any_orthonormal_vector();
    let (z, rise) = (0..12)
        .map(|k| {
            let angle = std::f64::consts::PI * f64::from(k) / 12.0;
            let z = across * angle.cos() + middle.cross(across) * angle.sin();
            let rise = directions
                .iter()
                .map(|d| d.dot(z).abs())
                .fold(0.0, f64::max);
            (z, rise)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    if rise > SPHERE_LATITUDE_SIN {
        return None;
    }
    let frame = Frame::from_axis(centre, z, Some(-middle))?;
    let clear = directions.iter().all(|d| {
        let u = d
            .dot(frame.y)
            .atan2(d.dot(frame.x))
            .rem_euclid(std::f64::consts::TAU);
        u > SPHERE_SEAM_MARGIN && u < std::f64::consts::TAU - SPHERE_SEAM_MARGIN
    });
    clear.then_some(frame)
}

/// The plane through `samples` (points and normals) when every point lies within `within`
/// of it and every normal along it, its frame at `origin` with x along `du` and its normal
/// `du × dv` (the B-spline's sense).
fn plane_through(
    samples: &[(Vec3, Vec3)],
    within: f64,
    (origin, du, dv): (Vec3, Vec3, Vec3),
) -> Option<Surface> {
    let frame = Frame::from_axis(origin, du.cross(dv), Some(du))?;
    let flat = samples.iter().all(|(p, n)| {
        (*p - origin).dot(frame.z).abs() <= within && n.cross(frame.z).length() <= 1e-9
    });
    flat.then_some(Surface::Plane { frame })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(path: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(path);
        let file = cadre_step::syntax::StepFile::read(&path).expect("reads");
        cadre_step::map_file(&file)
    }

    /// Each of `faces` replaced in `replaced` is the B-spline's surface at the face's points
    /// (its box's corners and a point within), with the face's normal on the same side;
    /// how many became spheres and cylinders.
    fn check_replaced(model: &Model, faces: &[FaceId], replaced: &Model) -> (usize, usize) {
        let mut kinds = (0, 0);
        for &face in faces {
            let before = &model.surfaces[model.faces[face.index()].surface.index()];
            let f = &replaced.faces[face.index()];
            let after = &replaced.surfaces[f.surface.index()];
            kinds.0 += usize::from(matches!(after, Surface::Sphere { .. }));
            kinds.1 += usize::from(matches!(after, Surface::Cylinder { .. }));
            let [u0, u1, v0, v1] = cadre_brep::bounds::face_uv_box(
                model,
                &model.faces[face.index()],
                before,
                Default::default(),
            )
            .expect("box");
            for (u, v) in [(u0, v0), (u1, v1), (0.5 * (u0 + u1), 0.3 * v0 + 0.7 * v1)] {
                let p = before.eval(u, v);
                let (a, b) = after
                    .project(p, None, Default::default())
                    .expect("projects");
                assert!(after.eval(a, b).distance(p) < 1e-6, "{face:?}");
                // The face's normal, as each surface and sense give it, is the same.
                let sense = |s: bool| if s { 1.0 } else { -1.0 };
                let n0 = before.normal(u, v).unwrap() * sense(model.faces[face.index()].same_sense);
                let n1 = after.normal(a, b).unwrap() * sense(f.same_sense);
                assert!(n0.dot(n1) > 0.999, "{face:?}: {n0:?} {n1:?}");
            }
        }
        kinds
    }

    /// OCCT's NURBS conversion of a plate with an oblique bore (every face a B-spline, the
    /// bore a rational one): the six planes and the bore are found, each closed form is the
    /// B-spline's surface at the face's points, and the faces keep their side.
    #[test]
    fn bspline_planes_and_a_bore_are_found() {
        let model = model("bspline-bore.step");
        let (faces, replaced) = closed_form_faces(&model, 1e-3);
        assert_eq!(faces.len(), 7, "{faces:?}");
        let kinds = check_replaced(&model, &faces, &replaced.expect("a model"));
        assert_eq!(kinds, (0, 1), "one cylinder");
    }

    /// OCCT's NURBS conversion of a sphere's corner cut by three planes (a spherical
    /// triangle, as a corner blend is): the sphere is found, in a frame that keeps the face
    /// clear of its poles and seam, and the planes.
    #[test]
    fn a_bspline_sphere_corner_is_found() {
        let model = model("bspline-sphere-corner.step");
        let (faces, replaced) = closed_form_faces(&model, 1e-3);
        assert_eq!(faces.len(), 4, "{faces:?}");
        let kinds = check_replaced(&model, &faces, &replaced.expect("a model"));
        assert_eq!(kinds, (1, 0), "one sphere");
    }

    /// A frame is chosen only where the samples keep clear of its poles and seam: a whole
    /// band round a sphere's equator (no middle to put the seam opposite) gets none.
    #[test]
    fn a_sphere_band_gets_no_frame() {
        let patch: Vec<(Vec3, Vec3)> = (0..12)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (u, v) = (
                    std::f64::consts::TAU / 12.0 * f64::from(i),
                    -0.2 + 0.2 * f64::from(j),
                );
                let d = Vec3::new(u.cos() * v.cos(), u.sin() * v.cos(), v.sin());
                (d * 5.0, d)
            })
            .collect();
        // Negative control: the same band over a quarter turn gets one.
        let quarter: Vec<(Vec3, Vec3)> = patch
            .iter()
            .filter(|(p, _)| p.y >= 0.0 && p.x >= 0.0)
            .copied()
            .collect();
        assert!(sphere_frame(&quarter, Vec3::ZERO).is_some());
        assert!(sphere_frame(&patch, Vec3::ZERO).is_none());
    }

    /// Negative control: a B-spline that is neither (the corpus' quarter sphere with its
    /// nearly collapsed sides) is left as it is.
    #[test]
    fn a_sphere_patch_is_left_a_bspline() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../cadre-mesh/tests/data/quarter_sphere_collapsed_sides.step");
        let file = cadre_step::syntax::StepFile::read(&path).expect("reads");
        let model = cadre_step::map_file(&file);
        let (faces, replaced) = closed_form_faces(&model, 1e-3);
        assert!(faces.is_empty() && replaced.is_none(), "{faces:?}");
    }
}
