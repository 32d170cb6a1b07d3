//! What the renderer draws ([`RenderScene`]), built from the model: the assembled tessellation
//! (part meshes and the occurrence tree), a record of every face keyed by its dense model id
//! (the B-Rep face, its exact surface's kind and parameter box, where the exact back-ends find
//! what to draw) and the analytic primitives drawn beside the meshes.

use cadre_brep::measure::SurfaceKind;
use cadre_brep::{FaceId, MeshId, Model, SurfaceId};
use cadre_mesh::ModelMesh;
use cadre_mesh::scene::{Scene, SceneIds};
use glam::DVec3;

use crate::analytic::AnalyticPrimitive;

/// A scene for the renderer: everything [`crate::Renderer::prepare`] uploads.
///
/// The ids in the visibility buffer and in picks are dense model ids (`index + 1` in the
/// model's arenas, [`SceneIds`]): [`RenderScene::face`] says what a face id stands for, and a
/// STEP id is looked up through the model for display ([`RenderScene::face_step_id`]).
#[derive(Clone, Debug, Default)]
pub struct RenderScene {
    /// The tessellation: one mesh per part (triangles tagged with their face ids, the
    /// B-Rep edges as polylines, the vertices), the materials and the occurrence tree.
    pub assembly: Scene,
    /// The record of face id `k + 1` at `k`: the model's B-Rep faces, then its tessellated
    /// items (as [`SceneIds`] numbers them). Empty for a scene without a model.
    pub faces: Vec<RenderFace>,
    /// Spheres and rectangles drawn by ray casting, in the same visibility buffer as the
    /// meshes; each is an instance of its own, after the meshes'
    /// ([`crate::PreparedScene::primitive_instance`]).
    pub primitives: Vec<AnalyticPrimitive>,
    /// The faces drawn from their exact surfaces and trim trees (`--method trim`), when the
    /// scene was built with them ([`RenderScene::with_trims`]); their meshes draw the rest.
    pub trim: Option<std::sync::Arc<crate::TrimScene>>,
    /// Polylines drawn over the surfaces (toolpaths, sketches, wires) by the lines pass.
    pub lines: crate::LineSet,
    /// Labels drawn over the surfaces (part names, notes, PMI text) by the text pass.
    pub labels: crate::LabelSet,
}

/// What one face id stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RenderFace {
    /// A B-Rep face: its exact definition is in the model (surface and trim loops), which is
    /// what a back-end drawing faces exactly reads.
    Brep {
        /// The model's face.
        face: FaceId,
        /// Its support surface.
        surface: SurfaceId,
        /// What kind of surface that is (a trimmed surface's basis), for choosing the
        /// back-end that draws it.
        kind: SurfaceKind,
        /// The (u, v) box its mesh covers, `[u0, v0, u1, v1]` (`None` for a face that was not
        /// meshed): the parameter range its trims enclose.
        uv_box: Option<[f64; 4]>,
    },
    /// A tessellated item of the file (no exact surface).
    Tessellated {
        /// The model's mesh.
        mesh: MeshId,
    },
}

impl RenderScene {
    /// The scene of a meshed model: its assembly (as [`cadre_mesh::assemble::build_scene`]
    /// makes it) and the record of every face.
    pub fn from_model(model: &Model, mesh: &ModelMesh) -> RenderScene {
        let faces = model
            .faces
            .iter()
            .enumerate()
            .map(|(k, face)| RenderFace::Brep {
                face: FaceId(k as u32),
                surface: face.surface,
                kind: SurfaceKind::of(&model.surfaces[face.surface.index()]),
                uv_box: mesh.faces.get(k).and_then(Option::as_ref).and_then(|fm| {
                    fm.points.iter().fold(None, |acc: Option<[f64; 4]>, p| {
                        let (u, v) = (p.uv.x, p.uv.y);
                        Some(match acc {
                            None => [u, v, u, v],
                            Some([u0, v0, u1, v1]) => [u0.min(u), v0.min(v), u1.max(u), v1.max(v)],
                        })
                    })
                }),
            })
            .chain((0..model.meshes.len()).map(|k| RenderFace::Tessellated {
                mesh: MeshId(k as u32),
            }))
            .collect();
        RenderScene {
            assembly: cadre_mesh::assemble::build_scene(model, mesh),
            faces,
            primitives: Vec::new(),
            trim: None,
            lines: crate::LineSet::default(),
            labels: crate::LabelSet::default(),
        }
    }

    /// This scene with `model`'s faces drawn from their exact surfaces, trimmed per pixel by
    /// trees fitted within `tolerance` model units of the exact trims, where the renderer can
    /// ([`crate::TrimScene`] says which faces keep their meshes, and why). `model` must be
    /// the one the scene was made from.
    pub fn with_trims(mut self, model: &Model, tolerance: f64) -> RenderScene {
        self.trim = Some(std::sync::Arc::new(crate::TrimScene::build(
            model, tolerance,
        )));
        self
    }

    /// The scene of meshes without a model (read from a mesh file, made by hand): no face
    /// records, its ids stand for themselves.
    pub fn from_assembly(assembly: Scene) -> RenderScene {
        RenderScene {
            assembly,
            ..RenderScene::default()
        }
    }

    /// This scene with `lines` drawn over its surfaces.
    pub fn with_lines(mut self, lines: crate::LineSet) -> RenderScene {
        self.lines = lines;
        self
    }

    /// This scene with `labels` drawn over its surfaces.
    pub fn with_labels(mut self, labels: crate::LabelSet) -> RenderScene {
        self.labels = labels;
        self
    }

    /// This scene with `primitives` drawn beside its meshes.
    pub fn with_primitives(mut self, primitives: Vec<AnalyticPrimitive>) -> RenderScene {
        self.primitives = primitives;
        self
    }

    /// What the dense ids stand for and their STEP ids.
    pub fn ids(&self) -> &SceneIds {
        &self.assembly.ids
    }

    /// The record of face id `id` (as the visibility buffer and picks give it).
    pub fn face(&self, id: u32) -> Option<&RenderFace> {
        self.faces.get((id as usize).checked_sub(1)?)
    }

    /// The STEP id of face id `id` through the model (0 for none; a scene without a model
    /// gives the id itself).
    pub fn face_step_id(&self, id: u32) -> u64 {
        self.assembly.ids.face_step_id(id)
    }

    /// The world box of every placed mesh and every primitive, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let meshes = crate::scene_bounds(&self.assembly);
        self.primitives
            .iter()
            .map(AnalyticPrimitive::world_box)
            .chain(meshes)
            .chain(self.lines.bounds())
            .chain(self.labels.bounds())
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pin_assembly() -> (Model, ModelMesh) {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/pin-assembly.step"
        );
        let file = cadre_step::syntax::StepFile::read(std::path::Path::new(path)).expect("reads");
        let model = cadre_step::map_file(&file);
        let mesh = cadre_mesh::mesh_model(&model, &cadre_mesh::MeshParams::default(), None);
        (model, mesh)
    }

    #[test]
    fn every_face_id_of_the_assembly_has_its_record() {
        let (model, mesh) = pin_assembly();
        let scene = RenderScene::from_model(&model, &mesh);
        assert_eq!(scene.faces.len(), model.faces.len() + model.meshes.len());
        let mut seen = 0;
        for m in &scene.assembly.meshes {
            for prim in &m.primitives {
                for &id in &prim.face_ids {
                    let Some(RenderFace::Brep {
                        face,
                        surface,
                        kind,
                        uv_box,
                    }) = scene.face(id)
                    else {
                        panic!("face id {id} has no B-Rep record");
                    };
                    let model_face = &model.faces[face.index()];
                    assert_eq!(*surface, model_face.surface);
                    assert_eq!(*kind, SurfaceKind::of(&model.surfaces[surface.index()]));
                    let [u0, v0, u1, v1] = uv_box.expect("a drawn face was meshed");
                    assert!(u0 <= u1 && v0 <= v1);
                    assert_eq!(scene.face_step_id(id), model_face.step_id);
                    seen += 1;
                }
            }
        }
        assert!(seen > 0);
        // No record past the table, none for id 0 (background).
        assert_eq!(scene.face(0), None);
        assert_eq!(scene.face(scene.faces.len() as u32 + 1), None);
    }

    #[test]
    fn a_pin_is_cylinders_and_planes() {
        let (model, mesh) = pin_assembly();
        let scene = RenderScene::from_model(&model, &mesh);
        let kinds: std::collections::HashSet<SurfaceKind> = scene
            .faces
            .iter()
            .filter_map(|f| match f {
                RenderFace::Brep { kind, .. } => Some(*kind),
                RenderFace::Tessellated { .. } => None,
            })
            .collect();
        assert!(kinds.contains(&SurfaceKind::Cylinder), "{kinds:?}");
        assert!(kinds.contains(&SurfaceKind::Plane), "{kinds:?}");
        assert!(SurfaceKind::Cylinder.is_quadric() && !SurfaceKind::Torus.is_quadric());
    }

    #[test]
    fn bounds_hold_the_primitives() {
        let sphere = AnalyticPrimitive {
            shape: crate::AnalyticShape::Sphere { radius: 2.0 },
            frame: cadre_geom::Frame {
                origin: DVec3::new(10.0, 0.0, 0.0),
                ..cadre_geom::Frame::WORLD
            },
            face_id: 1,
            colour: [1.0; 4],
        };
        let scene = RenderScene::default().with_primitives(vec![sphere]);
        assert_eq!(
            scene.bounds(),
            Some((DVec3::new(8.0, -2.0, -2.0), DVec3::new(12.0, 2.0, 2.0)))
        );
        // Negative control: no mesh and no primitive, no box.
        assert_eq!(RenderScene::default().bounds(), None);
    }
}
