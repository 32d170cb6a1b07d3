//! The faces drawn from their exact definition (seed 000, Part III): each face's support
//! surface, evaluated on the GPU over its trim tree's (u, v) box at a tessellation chosen per
//! frame from a screen-space error, and its trim tree (`cadre_trim`), tested per fragment.
//! [`TrimScene::build`] decides which faces the trim back-end draws
//! (`passes/visibility/trim`); every other face keeps its mesh, and says why.

use cadre_brep::{FaceId, Model};
use cadre_geom::Surface;
use cadre_trim::{ModelTrees, model_trees};
use glam::DVec3;

/// [`TrimFaceSurface::kind`]: `o + u x + v y`.
pub const SURFACE_PLANE: u32 = 0;
/// [`TrimFaceSurface::kind`]: `o + r (cos u x + sin u y) + v z`.
pub const SURFACE_CYLINDER: u32 = 1;
/// [`TrimFaceSurface::kind`]: `o + (r + v tan α)(cos u x + sin u y) + v z`.
pub const SURFACE_CONE: u32 = 2;
/// [`TrimFaceSurface::kind`]: `o + r cos v (cos u x + sin u y) + r sin v z`.
pub const SURFACE_SPHERE: u32 = 3;
/// [`TrimFaceSurface::kind`]: `o + (R + r cos v)(cos u x + sin u y) + r sin v z`.
pub const SURFACE_TORUS: u32 = 4;

/// One face the trim back-end draws: its surface in closed form and where its trim tree is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimFaceSurface {
    /// One of the `SURFACE_*` kinds.
    pub kind: u32,
    /// The surface's frame: origin, x, y, z (model units, the mesh's coordinates).
    pub frame: [DVec3; 4],
    /// The kind's two numbers: radius and 0 (cylinder, sphere), radius and tan α (cone),
    /// major and minor radius (torus), 0 and 0 (plane).
    pub params: [f64; 2],
    /// Its tree's index in [`TrimScene::trees`]' buffers.
    pub tree: u32,
    /// The tree's (u, v) box: lower corner and size (the tessellated domain).
    pub uv_origin: [f64; 2],
    /// The box's size.
    pub uv_size: [f64; 2],
    /// Bounds of the surface's second derivatives over the box: |S_uu|, |S_uv|, |S_vv| (model
    /// units per parameter unit²), from which a tessellation's chord error follows.
    pub curvature: [f64; 3],
}

/// Which faces of a model the trim back-end draws, and the trees it reads.
#[derive(Clone, Debug, Default)]
pub struct TrimScene {
    /// The trim trees of the model's faces, packed.
    pub trees: ModelTrees,
    /// Per model face, what the trim back-end draws of it (`None`: its mesh draws it).
    pub faces: Vec<Option<TrimFaceSurface>>,
    /// The faces left to their meshes: STEP id and why.
    pub fallback: Vec<(u64, String)>,
    /// The object-space tolerance the trims were fitted within (model units).
    pub tolerance: f64,
}

impl TrimScene {
    /// The trees of `model`'s faces within `tolerance` model units of the exact trims, and
    /// the faces the trim back-end can draw: planes, cylinders, cones, spheres and tori (a
    /// rectangular trim of one counts as it); faces on other surfaces or without a tree keep
    /// their meshes.
    pub fn build(model: &Model, tolerance: f64) -> TrimScene {
        let trees = model_trees(model, tolerance);
        let mut fallback: Vec<(u64, String)> = trees.failures.clone();
        let faces = (0..model.faces.len())
            .map(|i| {
                let tree = trees.face_index[i]?;
                let face = &model.faces[i];
                let surface = &model.surfaces[face.surface.index()];
                let record = &trees.buffers.faces[tree as usize];
                let origin = [record.origin.x, record.origin.y];
                let size = [f64::from(record.size[0]), f64::from(record.size[1])];
                match closed_form(surface, origin, size) {
                    Some((kind, frame, params, curvature)) => Some(TrimFaceSurface {
                        kind,
                        frame,
                        params,
                        tree,
                        uv_origin: origin,
                        uv_size: size,
                        curvature,
                    }),
                    None => {
                        fallback.push((
                            face.step_id,
                            format!(
                                "{} surface: no GPU evaluator yet",
                                surface_name(model, FaceId(i as u32))
                            ),
                        ));
                        None
                    }
                }
            })
            .collect();
        fallback.sort_by_key(|(id, _)| *id);
        TrimScene {
            trees,
            faces,
            fallback,
            tolerance,
        }
    }

    /// How many faces the trim back-end draws.
    pub fn drawn(&self) -> usize {
        self.faces.iter().flatten().count()
    }
}

/// The STEP type name of a face's surface.
fn surface_name(model: &Model, face: FaceId) -> &'static str {
    model.surfaces[model.faces[face.index()].surface.index()].type_name()
}

/// A surface's kind, frame, numbers and second-derivative bounds over the (u, v) box
/// `origin + [0, size]`, for the kinds the GPU evaluates in closed form.
#[allow(clippy::type_complexity)]
fn closed_form(
    surface: &Surface,
    origin: [f64; 2],
    size: [f64; 2],
) -> Option<(u32, [DVec3; 4], [f64; 2], [f64; 3])> {
    let axes = |f: &cadre_geom::Frame| [f.origin, f.x, f.y, f.z];
    // The largest |cos v| over the box's v range (the sphere's parallels).
    let v_range = (origin[1], origin[1] + size[1]);
    Some(match surface {
        Surface::Trimmed { basis, .. } => return closed_form(basis, origin, size),
        Surface::Plane { frame } => (SURFACE_PLANE, axes(frame), [0.0; 2], [0.0; 3]),
        Surface::Cylinder { frame, radius } => (
            SURFACE_CYLINDER,
            axes(frame),
            [*radius, 0.0],
            [radius.abs(), 0.0, 0.0],
        ),
        Surface::Cone {
            frame,
            radius,
            semi_angle,
        } => {
            let tan = semi_angle.tan();
            // |S_uu| is the radius at v, largest at one end of the v range.
            let rho = (radius + v_range.0 * tan)
                .abs()
                .max((radius + v_range.1 * tan).abs());
            (
                SURFACE_CONE,
                axes(frame),
                [*radius, tan],
                [rho, tan.abs(), 0.0],
            )
        }
        Surface::Sphere { frame, radius } => {
            let r = radius.abs();
            (SURFACE_SPHERE, axes(frame), [*radius, 0.0], [r, r, r])
        }
        Surface::Torus {
            frame,
            major_radius,
            minor_radius,
        } => {
            let (big, small) = (major_radius.abs(), minor_radius.abs());
            (
                SURFACE_TORUS,
                axes(frame),
                [*major_radius, *minor_radius],
                [big + small, small, small],
            )
        }
        _ => return None,
    })
}

/// The point of a closed-form surface at (u, v), as the GPU evaluates it (`trim.wgsl`'s
/// `surface_point`): the CPU twin the tests check the records against.
pub fn closed_form_point(s: &TrimFaceSurface, u: f64, v: f64) -> DVec3 {
    let [o, x, y, z] = s.frame;
    let radial = x * u.cos() + y * u.sin();
    let [a, b] = s.params;
    match s.kind {
        SURFACE_PLANE => o + x * u + y * v,
        SURFACE_CYLINDER => o + radial * a + z * v,
        SURFACE_CONE => o + radial * (a + v * b) + z * v,
        SURFACE_SPHERE => o + radial * (a * v.cos()) + z * (a * v.sin()),
        _ => o + radial * (a + b * v.cos()) + z * (b * v.sin()),
    }
}

/// The direction of S_u × S_v of a closed-form surface at (u, v), as `surface.wgsl`
/// evaluates it (the limit direction where it vanishes).
pub fn closed_form_normal(s: &TrimFaceSurface, u: f64, v: f64) -> DVec3 {
    let [_, x, y, z] = s.frame;
    let radial = x * u.cos() + y * u.sin();
    let [a, b] = s.params;
    let sign = |t: f64| if t < 0.0 { -1.0 } else { 1.0 };
    let meridian = radial * v.cos() + z * v.sin();
    match s.kind {
        SURFACE_PLANE => z,
        SURFACE_CYLINDER => radial * a,
        SURFACE_CONE => (radial - z * b) * sign(a + v * b),
        SURFACE_SPHERE => meridian * sign(a),
        _ => meridian * sign((a + b * v.cos()) * b),
    }
}

/// Samples per side of the (u, v) box when bounding a face's surface.
const SPHERE_SAMPLES: usize = 9;

/// The GPU record of face id `face_id` drawn from `s`. `points` are its mesh's vertices
/// (position, normal, (u, v)), which say which side of the surface is the face's outside
/// (the mesh's normals follow the shell's orientation).
pub(crate) fn surface_record(
    s: &TrimFaceSurface,
    face_id: u32,
    points: impl Iterator<Item = ([f32; 3], [f32; 3], [f32; 2])>,
) -> crate::layout::TrimSurface {
    let mut agreement = 0.0;
    for (_, normal, uv) in points {
        let exact = closed_form_normal(s, f64::from(uv[0]), f64::from(uv[1]));
        agreement += exact
            .normalize_or_zero()
            .dot(DVec3::from(normal.map(f64::from)));
    }
    let sign = if agreement < 0.0 { -1.0 } else { 1.0 };
    // The box's surface sampled on a grid, widened by the grid's chord error: a sphere that
    // holds every point of the box, so of the face.
    let n = SPHERE_SAMPLES - 1;
    let samples: Vec<[f32; 3]> = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| {
            let u = s.uv_origin[0] + s.uv_size[0] * i as f64 / n as f64;
            let v = s.uv_origin[1] + s.uv_size[1] * j as f64 / n as f64;
            closed_form_point(s, u, v).as_vec3().to_array()
        })
        .collect();
    let (centre, radius) = crate::coverage::bounding_sphere(samples.into_iter());
    let h = [s.uv_size[0] / n as f64, s.uv_size[1] / n as f64];
    let [muu, muv, mvv] = s.curvature;
    let chord = (h[0] * h[0] * muu + 2.0 * h[0] * h[1] * muv + h[1] * h[1] * mvv) / 8.0;
    let [o, x, y, z] = s.frame.map(|a| a.as_vec3());
    let f = |v: glam::Vec3, w: f64| [v.x, v.y, v.z, w as f32];
    crate::layout::TrimSurface {
        origin: f(o, s.params[0]),
        axis_x: f(x, s.params[1]),
        axis_y: f(y, sign),
        axis_z: f(z, 0.0),
        uv: [
            s.uv_origin[0] as f32,
            s.uv_origin[1] as f32,
            s.uv_size[0] as f32,
            s.uv_size[1] as f32,
        ],
        sphere: [
            centre.x as f32,
            centre.y as f32,
            centre.z as f32,
            (radius + chord) as f32 * (1.0 + 1e-5),
        ],
        curvature: [muu as f32, muv as f32, mvv as f32, 0.0],
        ids: [s.kind, face_id, s.tree, 0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pin_assembly() -> Model {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/pin-assembly.step"
        );
        let file = cadre_step::syntax::StepFile::read(std::path::Path::new(path)).expect("reads");
        cadre_step::map_file(&file)
    }

    /// The closed forms the GPU evaluates are the model's surfaces: every drawn face's
    /// record gives the model's point at random (u, v) of its box.
    #[test]
    fn closed_forms_are_the_model_surfaces() {
        let model = pin_assembly();
        let scene = TrimScene::build(&model, 0.01);
        assert!(scene.drawn() > 0);
        assert_eq!(scene.drawn() + scene.fallback.len(), model.faces.len());
        let mut checked = 0;
        for (i, face) in scene.faces.iter().enumerate() {
            let Some(s) = face else { continue };
            let surface = &model.surfaces[model.faces[i].surface.index()];
            for k in 0..8 {
                let t = [f64::from(k) / 7.0, f64::from((k * 3) % 8) / 7.0];
                let u = s.uv_origin[0] + t[0] * s.uv_size[0];
                let v = s.uv_origin[1] + t[1] * s.uv_size[1];
                let exact = surface.eval(u, v);
                let ours = closed_form_point(s, u, v);
                assert!(
                    (exact - ours).length() < 1e-9,
                    "face {i}: {exact} vs {ours}"
                );
                checked += 1;
            }
        }
        assert!(checked > 0);
        // Negative control: another face's record misses the surface.
        let drawn: Vec<&TrimFaceSurface> = scene.faces.iter().flatten().collect();
        let (a, b) = (drawn[0], drawn[drawn.len() - 1]);
        let u = a.uv_origin[0] + 0.5 * a.uv_size[0];
        let v = a.uv_origin[1] + 0.5 * a.uv_size[1];
        assert!((closed_form_point(a, u, v) - closed_form_point(b, u, v)).length() > 1e-6);
    }
}
