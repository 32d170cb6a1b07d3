//! The scene description format of the quadric primitives (seed 001): a JSON file of objects
//! (quadrics cut by planes, as surface patches or volumes), lights, an optional camera, and
//! generated crowds of spheres, cylinders and cones. `cadre render scene.json -o out.png` and
//! `cadre view scene.json` read it; `docs/scene-format.md` documents it.
//!
//! A malformed file is an error naming its line and column; an object that cannot be drawn
//! (unbounded by its planes, empty, or with a degenerate frame) is left out with a warning
//! naming its index, and the others load.

mod generate;

use std::sync::Arc;

use cadre_geom::quadric::tetra::BernsteinTetrahedron;
use cadre_geom::{CutKind, CutQuadric, Frame, HalfSpace, Quadric};
use glam::DVec3;
use serde::Deserialize;
use thiserror::Error;

pub use generate::Generate;

use crate::{AnalyticPrimitive, AnalyticShape, Light, QuadricShape};

/// Why a scene file could not be read.
#[derive(Debug, Error)]
pub enum SceneFileError {
    /// Not JSON, or not the format.
    #[error("line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong there.
        message: String,
    },
    /// A generated crowd asks for more objects than [`MAX_OBJECTS`].
    #[error("{count} objects asked for; at most {MAX_OBJECTS}")]
    TooMany {
        /// Objects asked for.
        count: u64,
    },
}

/// The most objects a scene may hold (listed and generated): bounded memory on any input.
pub const MAX_OBJECTS: u64 = 20_000_000;

/// A scene file as written.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The view; absent: fitted to the scene from the iso direction.
    #[serde(default)]
    pub camera: Option<CameraSpec>,
    /// Lights placed in the world; absent or empty: the CAD rig fixed to the camera.
    #[serde(default)]
    pub lights: Vec<LightSpec>,
    /// The objects.
    #[serde(default)]
    pub objects: Vec<ObjectSpec>,
    /// Crowds of generated objects.
    #[serde(default)]
    pub generate: Vec<Generate>,
    /// The first light casts shadows.
    #[serde(default)]
    pub shadows: bool,
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    /// Eye position.
    pub eye: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// Up direction.
    #[serde(default = "z_up")]
    pub up: [f64; 3],
    /// Vertical field of view, degrees.
    #[serde(default = "default_fov")]
    pub fov: f64,
}

fn z_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

fn default_fov() -> f64 {
    30.0
}

/// A light in the world (intensities linear RGB).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LightSpec {
    /// Sunlight from `direction` (towards the light).
    Directional {
        /// Towards the light.
        direction: [f64; 3],
        /// Radiance.
        radiance: [f32; 3],
    },
    /// A point light: intensity / d².
    Point {
        /// Position.
        position: [f64; 3],
        /// Intensity.
        intensity: [f32; 3],
        /// Fade-out distance (0: none).
        #[serde(default)]
        range: f64,
    },
    /// A spot light: a point light in a cone about `axis`.
    Spot {
        /// Position.
        position: [f64; 3],
        /// Direction it shines in.
        axis: [f64; 3],
        /// Intensity.
        intensity: [f32; 3],
        /// Fade-out distance (0: none).
        #[serde(default)]
        range: f64,
        /// Half-angle of full light, degrees.
        inner: f64,
        /// Half-angle where the light ends, degrees.
        outer: f64,
    },
}

/// One object: a quadric in its own frame, cut by planes.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    /// The quadric, in the object's frame.
    pub shape: ShapeSpec,
    /// Cutting planes in the object's frame, each [nx, ny, nz, d]: what keeps
    /// nx x + ny y + nz z + d ≤ 0 is kept.
    #[serde(default)]
    pub planes: Vec<[f64; 4]>,
    /// The solid inside the quadric (Q ≤ 0) and its planes, instead of its surface.
    #[serde(default)]
    pub volume: bool,
    /// The frame's origin.
    #[serde(default)]
    pub origin: [f64; 3],
    /// The frame's z axis (default world z).
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
    /// The frame's x direction (made perpendicular to the axis; default any).
    #[serde(default)]
    pub x: Option<[f64; 3]>,
    /// Linear RGB, with an optional opacity.
    #[serde(default = "grey")]
    pub colour: Vec<f32>,
}

fn grey() -> Vec<f32> {
    vec![0.6, 0.6, 0.62, 1.0]
}

/// A quadric by class and size, in its own frame (axis z), or by its coefficients.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A sphere of this radius about the origin.
    Sphere(f64),
    /// x²/a² + y²/b² + z²/c² = 1.
    Ellipsoid([f64; 3]),
    /// A circular cylinder of this radius about z.
    Cylinder(f64),
    /// x²/a² + y²/b² = 1.
    EllipticCylinder([f64; 2]),
    /// x²/a² − y²/b² = 1.
    HyperbolicCylinder([f64; 2]),
    /// x² = 2p y.
    ParabolicCylinder(f64),
    /// x²/a² + y²/b² = z²/c² (apex at the origin).
    Cone([f64; 3]),
    /// x²/a² + y²/b² − z²/c² = 1.
    HyperboloidOneSheet([f64; 3]),
    /// z²/c² − x²/a² − y²/b² = 1.
    HyperboloidTwoSheets([f64; 3]),
    /// x²/a² + y²/b² = z.
    EllipticParaboloid([f64; 2]),
    /// x²/a² − y²/b² = z.
    HyperbolicParaboloid([f64; 2]),
    /// y = ±(b/a) x.
    IntersectingPlanes([f64; 2]),
    /// x = ±a.
    ParallelPlanes(f64),
    /// a x² + b y² + c z² + 2d xy + 2e xz + 2f yz + 2g x + 2h y + 2i z + j = 0.
    Coefficients([f64; 10]),
    /// The quadratic Bernstein patch of a tetrahedron (its faces are added to the planes).
    Bernstein {
        /// The tetrahedron's vertices.
        vertices: [[f64; 3]; 4],
        /// Weights of the vertex pairs 00, 11, 22, 33, 01, 02, 03, 12, 13, 23.
        weights: [f64; 10],
    },
}

impl ShapeSpec {
    /// The quadric, and the tetrahedron's planes for a Bernstein patch; `None` for a
    /// degenerate one (a flat tetrahedron).
    fn quadric(&self) -> Option<(Quadric, Vec<HalfSpace>)> {
        let plain = |q: Quadric| Some((q, Vec::new()));
        match *self {
            ShapeSpec::Sphere(r) => plain(Quadric::sphere(r)),
            ShapeSpec::Ellipsoid([a, b, c]) => plain(Quadric::ellipsoid(a, b, c)),
            ShapeSpec::Cylinder(r) => plain(Quadric::cylinder(r)),
            ShapeSpec::EllipticCylinder([a, b]) => plain(Quadric::elliptic_cylinder(a, b)),
            ShapeSpec::HyperbolicCylinder([a, b]) => plain(Quadric::hyperbolic_cylinder(a, b)),
            ShapeSpec::ParabolicCylinder(p) => plain(Quadric::parabolic_cylinder(p)),
            ShapeSpec::Cone([a, b, c]) => plain(Quadric::cone(a, b, c)),
            ShapeSpec::HyperboloidOneSheet([a, b, c]) => {
                plain(Quadric::hyperboloid_one_sheet(a, b, c))
            }
            ShapeSpec::HyperboloidTwoSheets([a, b, c]) => {
                plain(Quadric::hyperboloid_two_sheets(a, b, c))
            }
            ShapeSpec::EllipticParaboloid([a, b]) => plain(Quadric::elliptic_paraboloid(a, b)),
            ShapeSpec::HyperbolicParaboloid([a, b]) => plain(Quadric::hyperbolic_paraboloid(a, b)),
            ShapeSpec::IntersectingPlanes([a, b]) => plain(Quadric::intersecting_planes(a, b)),
            ShapeSpec::ParallelPlanes(a) => plain(Quadric::parallel_planes(a)),
            ShapeSpec::Coefficients(c) => plain(Quadric::from_coefficients(
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9],
            )),
            ShapeSpec::Bernstein { vertices, weights } => {
                let patch = BernsteinTetrahedron {
                    vertices: vertices.map(DVec3::from),
                    weights,
                }
                .patch()?;
                Some((patch.quadric, patch.planes))
            }
        }
    }
}

/// A scene read from a file, ready to draw.
#[derive(Clone, Debug, Default)]
pub struct LoadedScene {
    /// The objects, face id k + 1 for object k (generated ones after the listed ones).
    pub primitives: Vec<AnalyticPrimitive>,
    /// The file's camera: eye, target, up and vertical field of view (radians).
    pub camera: Option<(DVec3, DVec3, DVec3, f64)>,
    /// The file's lights (empty: use the default rig).
    pub lights: Vec<Light>,
    /// Objects left out, and why (each names the object's index).
    pub warnings: Vec<String>,
    /// The first light casts shadows ([`crate::FrameOptions::shadows`]).
    pub shadows: bool,
}

/// Reads a scene file's text.
pub fn load_scene(text: &str) -> Result<LoadedScene, SceneFileError> {
    let file: SceneFile = serde_json::from_str(text).map_err(|e| SceneFileError::Parse {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let generated: u64 = file.generate.iter().map(|g| g.count).sum();
    let count = generated.saturating_add(file.objects.len() as u64);
    if count > MAX_OBJECTS {
        return Err(SceneFileError::TooMany { count });
    }
    let mut out = LoadedScene {
        camera: file.camera.map(|c| {
            (
                DVec3::from(c.eye),
                DVec3::from(c.target),
                DVec3::from(c.up),
                c.fov.clamp(0.01, 179.0).to_radians(),
            )
        }),
        lights: file.lights.iter().map(LightSpec::light).collect(),
        shadows: file.shadows,
        ..LoadedScene::default()
    };
    for (k, object) in file.objects.iter().enumerate() {
        match object.primitive(k as u32 + 1) {
            Ok(p) => out.primitives.push(p),
            Err(why) => out.warnings.push(format!("object {k}: {why}; left out")),
        }
    }
    for (k, crowd) in file.generate.iter().enumerate() {
        let first = out.primitives.len() as u32 + 1;
        match crowd.primitives(first) {
            Ok(mut ps) => out.primitives.append(&mut ps),
            Err(why) => out.warnings.push(format!("generate {k}: {why}; left out")),
        }
    }
    Ok(out)
}

impl LightSpec {
    fn light(&self) -> Light {
        match *self {
            LightSpec::Directional {
                direction,
                radiance,
            } => Light::Directional {
                direction: DVec3::from(direction).normalize_or(DVec3::Z),
                radiance,
            },
            LightSpec::Point {
                position,
                intensity,
                range,
            } => Light::Point {
                position: DVec3::from(position),
                intensity,
                range: range.max(0.0),
            },
            LightSpec::Spot {
                position,
                axis,
                intensity,
                range,
                inner,
                outer,
            } => Light::Spot {
                position: DVec3::from(position),
                axis: DVec3::from(axis).normalize_or(DVec3::NEG_Z),
                intensity,
                range: range.max(0.0),
                inner: inner.to_radians(),
                outer: outer.to_radians(),
            },
        }
    }
}

impl ObjectSpec {
    /// The object as a primitive writing `face_id`, or why it cannot be drawn.
    fn primitive(&self, face_id: u32) -> Result<AnalyticPrimitive, String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.origin) || !self.planes.iter().all(|p| finite(p)) {
            return Err("a number is not finite".into());
        }
        let (quadric, mut planes) = self.shape.quadric().ok_or("its tetrahedron is flat")?;
        if !finite(&quadric.matrix.to_cols_array()) {
            return Err("its quadric has a non-finite coefficient (a zero size?)".into());
        }
        planes.extend(self.planes.iter().map(|p| HalfSpace {
            normal: DVec3::new(p[0], p[1], p[2]),
            offset: p[3],
        }));
        if planes.iter().any(|h| h.normal.length() == 0.0) {
            return Err("a plane has a zero normal".into());
        }
        let cut = CutQuadric {
            quadric,
            planes,
            kind: CutKind::volume_if(self.volume),
        };
        let shape = QuadricShape::new(cut).map_err(|e| e.to_string())?;
        let axis = DVec3::from(self.axis.unwrap_or([0.0, 0.0, 1.0]));
        let frame = Frame::from_axis(DVec3::from(self.origin), axis, self.x.map(DVec3::from))
            .ok_or("its axis is zero")?;
        Ok(AnalyticPrimitive {
            shape: AnalyticShape::Quadric(Arc::clone(&shape)),
            frame,
            face_id,
            colour: colour(&self.colour),
        })
    }
}

/// RGB or RGBA as given (opaque by default, grey for anything else).
fn colour(c: &[f32]) -> [f32; 4] {
    match *c {
        [r, g, b] => [r, g, b, 1.0],
        [r, g, b, a] => [r, g, b, a],
        _ => [0.6, 0.6, 0.62, 1.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_loads_its_objects_and_reports_the_bad_ones() {
        let text = r#"{
            "camera": {"eye": [10, -10, 8], "target": [0, 0, 0]},
            "lights": [{"point": {"position": [5, 5, 5], "intensity": [30, 30, 30]}}],
            "objects": [
                {"shape": {"sphere": 1.0}, "colour": [1, 0, 0]},
                {"shape": {"cylinder": 0.5}, "planes": [[0, 0, 1, -2], [0, 0, -1, 0]], "volume": true},
                {"shape": {"cylinder": 0.5}, "planes": [[0, 0, 1, -2]]},
                {"shape": {"cone": [1, 1, 1]}, "axis": [0, 0, 0], "planes": [[0, 0, 1, -1], [0, 0, -1, 0]]}
            ]
        }"#;
        let scene = load_scene(text).unwrap();
        assert_eq!(scene.primitives.len(), 2);
        assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
        assert!(scene.warnings[0].starts_with("object 2: the primitive is unbounded"));
        assert!(scene.warnings[1].starts_with("object 3: its axis is zero"));
        assert_eq!(scene.primitives[1].face_id, 2);
        assert_eq!(scene.lights.len(), 1);
        assert!(scene.camera.is_some());
    }

    #[test]
    fn a_malformed_file_names_its_line() {
        let text = "{\n  \"objects\": [\n    {\"shape\": {\"spheer\": 1.0}}\n  ]\n}";
        match load_scene(text) {
            Err(SceneFileError::Parse { line, .. }) => assert_eq!(line, 3),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn hostile_numbers_leave_objects_out_without_a_panic() {
        // Every shape with zero, negative, huge, tiny and non-finite-making sizes, and planes
        // that are zero, parallel or far: each object loads or is named and left out.
        let sizes = ["0", "-1", "1e300", "1e-300", "3", "1e-12"];
        let shapes = [
            "sphere",
            "cylinder",
            "parabolic_cylinder",
            "parallel_planes",
        ];
        let pairs = [
            "elliptic_cylinder",
            "hyperbolic_cylinder",
            "elliptic_paraboloid",
            "hyperbolic_paraboloid",
            "intersecting_planes",
        ];
        let triples = [
            "ellipsoid",
            "cone",
            "hyperboloid_one_sheet",
            "hyperboloid_two_sheets",
        ];
        let planes = [
            "[]",
            "[[0, 0, 0, 1]]",
            "[[0, 0, 1, -1e300], [0, 0, -1, -1e300]]",
            "[[0, 0, 1, 1], [0, 0, -1, 1]]",
            "[[1e300, 0, 0, 1], [0, 1e-300, 0, 1], [0, 0, 1, -2], [0, 0, -1, -2]]",
        ];
        let mut objects = Vec::new();
        for size in sizes {
            for p in planes {
                for volume in [false, true] {
                    for shape in shapes {
                        objects.push(format!(r#"{{"shape": {{"{shape}": {size}}}, "planes": {p}, "volume": {volume}}}"#));
                    }
                    for shape in pairs {
                        objects.push(format!(r#"{{"shape": {{"{shape}": [{size}, 1]}}, "planes": {p}, "volume": {volume}}}"#));
                    }
                    for shape in triples {
                        objects.push(format!(r#"{{"shape": {{"{shape}": [1, {size}, 2]}}, "planes": {p}, "volume": {volume}}}"#));
                    }
                }
            }
        }
        objects.push(r#"{"shape": {"coefficients": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]}}"#.into());
        objects.push(
            r#"{"shape": {"bernstein": {"vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "weights": [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]}}}"#
                .into(),
        );
        let text = format!(r#"{{"objects": [{}]}}"#, objects.join(", "));
        let scene = load_scene(&text).expect("valid JSON of the format");
        assert_eq!(
            scene.primitives.len() + scene.warnings.len(),
            objects.len(),
            "every object loads or is named"
        );
        assert!(scene.primitives.iter().all(|p| {
            let (c, r) = p.bounding_sphere();
            c.is_finite() && r.is_finite()
        }));
    }

    #[test]
    fn too_many_generated_objects_are_refused() {
        let text = r#"{"generate": [{"count": 100000000000, "kinds": ["sphere"]}]}"#;
        assert!(matches!(
            load_scene(text),
            Err(SceneFileError::TooMany { .. })
        ));
    }
}
