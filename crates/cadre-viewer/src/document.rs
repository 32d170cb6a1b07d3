//! An open model: the STEP file read, mapped to B-Rep, tessellated and assembled into a
//! scene, with what the viewer looks up by STEP id and by instance.

use cadre_render::Pick;
use std::path::{Path, PathBuf};
use std::time::Instant;

use cadre_brep::{FaceId, Model};
use cadre_mesh::{Deflection, MeshParams, ModelMesh, deflection_diagonal, mesh_model};
use cadre_render::{RenderFace, RenderScene};
use glam::{DAffine3, DVec3};

use crate::ViewerError;

/// Whether `path` names a scene file of quadric primitives (`.json`) rather than STEP.
pub fn is_scene_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Default tessellation: 0.05 % of the model's diagonal, like `cadre render`.
pub const DEFLECTION_RELATIVE: f64 = 0.0005;

/// A stage of loading, for the progress bar.
#[derive(Clone, Debug, PartialEq)]
pub enum LoadStage {
    /// Reading and parsing the file.
    Reading,
    /// Mapping entities to the B-Rep model.
    Mapping,
    /// Tessellating: faces done of the total.
    Meshing {
        /// Faces done.
        done: usize,
        /// Faces in all.
        total: usize,
    },
    /// Building the scene.
    Assembling,
}

impl LoadStage {
    /// Overall fraction done (reading and mapping are quick next to meshing).
    pub fn fraction(&self) -> f32 {
        match self {
            LoadStage::Reading => 0.02,
            LoadStage::Mapping => 0.1,
            LoadStage::Meshing { done, total } => {
                0.15 + 0.8 * (*done as f32 / (*total).max(1) as f32).min(1.0)
            }
            LoadStage::Assembling => 0.97,
        }
    }

    /// What is going on, for the status line.
    pub fn label(&self) -> String {
        match self {
            LoadStage::Reading => "reading".into(),
            LoadStage::Mapping => "mapping entities".into(),
            LoadStage::Meshing { done, total } => format!("tessellating {done}/{total} faces"),
            LoadStage::Assembling => "assembling".into(),
        }
    }
}

/// One placed part of the scene (scene instance order, as the renderer numbers them).
#[derive(Clone, Debug)]
pub struct InstanceInfo {
    /// Scene node.
    pub node: usize,
    /// Placement in the world.
    pub world: DAffine3,
    /// The node's name (the part's or the occurrence's).
    pub name: String,
}

/// An open model.
pub struct Document {
    /// The file it came from.
    pub path: PathBuf,
    /// The B-Rep model.
    pub model: Model,
    /// Its tessellation.
    pub mesh: ModelMesh,
    /// What the renderer draws: the assembled tessellation (meshes, materials, assembly
    /// tree) and what each picked face id stands for in the model.
    pub scene: RenderScene,
    /// Placed parts, in the renderer's instance order.
    pub instances: Vec<InstanceInfo>,
    /// Per scene node: its parent.
    pub parents: Vec<Option<usize>>,
    /// Per scene node: the instance it places, when it has a mesh.
    pub instance_of_node: Vec<Option<usize>>,
    /// World box of the scene, or `None` when it has nothing to draw.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Messages about entities that did not load (with their STEP ids), for the UI.
    pub warnings: Vec<String>,
    /// Seconds from opening the file to the scene.
    pub load_seconds: f64,
}

impl Document {
    /// Reads, maps, tessellates and assembles `path`, reporting each stage to `progress`.
    pub fn load(
        path: &Path,
        progress: &(dyn Fn(LoadStage) + Sync),
    ) -> Result<Document, ViewerError> {
        let t0 = Instant::now();
        progress(LoadStage::Reading);
        if is_scene_file(path) {
            return Document::load_scene(path, t0);
        }
        let file = cadre_step::syntax::StepFile::read(path).map_err(|e| ViewerError::Load {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        progress(LoadStage::Mapping);
        let model = cadre_step::map_file(&file);
        let mut warnings: Vec<String> = file.diagnostics().iter().map(|e| e.to_string()).collect();
        warnings.extend(model.warnings.iter().map(|w| w.to_string()));
        let params = MeshParams {
            deflection: Deflection::Relative(DEFLECTION_RELATIVE)
                .resolve(deflection_diagonal(&model)),
            ..MeshParams::default()
        };
        let total = model.faces.len();
        progress(LoadStage::Meshing { done: 0, total });
        let report = |done: usize| {
            // Every hundredth face is often enough for a progress bar.
            if done.is_multiple_of(100) || done == total {
                progress(LoadStage::Meshing { done, total });
            }
        };
        let mesh = mesh_model(&model, &params, Some(&report));
        warnings.extend(
            mesh.failures
                .iter()
                .map(|f| format!("face #{} not meshed: {}", f.step_id, f.reason)),
        );
        progress(LoadStage::Assembling);
        let scene = RenderScene::from_model(&model, &mesh);
        Ok(Document::assemble(
            path.to_path_buf(),
            model,
            mesh,
            scene,
            warnings,
            t0.elapsed().as_secs_f64(),
        ))
    }

    /// A scene file of quadric primitives (`cadre_render::scene_file`): no B-Rep, no mesh.
    fn load_scene(path: &Path, t0: Instant) -> Result<Document, ViewerError> {
        let load_error = |message: String| ViewerError::Load {
            path: path.to_path_buf(),
            message,
        };
        let text = std::fs::read_to_string(path).map_err(|e| load_error(e.to_string()))?;
        let loaded =
            cadre_render::scene_file::load_scene(&text).map_err(|e| load_error(e.to_string()))?;
        let scene = RenderScene::default().with_primitives(loaded.primitives);
        Ok(Document::assemble(
            path.to_path_buf(),
            Model::default(),
            ModelMesh::default(),
            scene,
            loaded.warnings,
            t0.elapsed().as_secs_f64(),
        ))
    }

    /// The document of an already assembled scene.
    fn assemble(
        path: PathBuf,
        model: Model,
        mesh: ModelMesh,
        scene: RenderScene,
        warnings: Vec<String>,
        load_seconds: f64,
    ) -> Document {
        let tree = &scene.assembly;
        let mut parents = vec![None; tree.nodes.len()];
        for (n, node) in tree.nodes.iter().enumerate() {
            for &c in &node.children {
                if let Some(p) = parents.get_mut(c) {
                    *p = Some(n);
                }
            }
        }
        let mut instance_of_node = vec![None; tree.nodes.len()];
        let instances: Vec<InstanceInfo> = tree
            .instances()
            .enumerate()
            .map(|(i, (node, world))| {
                if let Some(slot) = instance_of_node.get_mut(node) {
                    *slot = Some(i);
                }
                InstanceInfo {
                    node,
                    world,
                    name: tree.nodes[node].name.clone(),
                }
            })
            .collect();
        let bounds = scene.bounds();
        Document {
            path,
            model,
            mesh,
            scene,
            instances,
            parents,
            instance_of_node,
            bounds,
            warnings,
            load_seconds,
        }
    }

    /// The file's name, for titles.
    pub fn title(&self) -> String {
        self.path.file_name().map_or_else(
            || self.path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        )
    }

    /// The B-Rep face of a picked face id (a dense model id, [`RenderScene::face`]).
    pub fn face(&self, id: u32) -> Option<FaceId> {
        match self.scene.face(id)? {
            RenderFace::Brep { face, .. } => Some(*face),
            RenderFace::Tessellated { .. } => None,
        }
    }

    /// The edge of a picked edge id.
    pub fn edge(&self, id: u32) -> Option<cadre_brep::EdgeId> {
        self.scene.ids().edge(id)
    }

    /// The vertex of a picked vertex id.
    pub fn vertex(&self, id: u32) -> Option<cadre_brep::VertexId> {
        self.scene.ids().vertex(id)
    }

    /// The picked item's name as the file writes it: its STEP id, looked up in the model
    /// (`#123`; `#?` for an entity without one).
    pub fn step_label(&self, pick: Pick) -> String {
        let model = &self.model;
        let step = match pick {
            Pick::Face { face, .. } => match self.scene.face(face) {
                Some(RenderFace::Brep { face, .. }) => {
                    model.faces.get(face.index()).map(|f| f.step_id)
                }
                Some(RenderFace::Tessellated { mesh }) => {
                    model.meshes.get(mesh.index()).map(|m| m.step_id)
                }
                None => None,
            },
            Pick::Edge { edge, .. } => self
                .edge(edge)
                .and_then(|e| model.edges.get(e.index()))
                .map(|e| e.step_id),
            Pick::Vertex { vertex, .. } => self
                .vertex(vertex)
                .and_then(|v| model.vertices.get(v.index()))
                .map(|v| v.step_id),
            Pick::Part { .. } => None,
        }
        .unwrap_or(0);
        if step == 0 {
            "#?".to_string()
        } else {
            format!("#{step}")
        }
    }

    /// The world box of a B-Rep face as placed by `instance`.
    pub fn face_bounds(&self, instance: usize, face: FaceId) -> Option<(DVec3, DVec3)> {
        let world = self.instances.get(instance)?.world;
        let fm = self.mesh.faces.get(face.index())?.as_ref()?;
        bounds_of(fm.points.iter().map(|p| world.transform_point3(p.xyz)))
    }

    /// The world box of a whole instance.
    pub fn instance_bounds(&self, instance: usize) -> Option<(DVec3, DVec3)> {
        let info = self.instances.get(instance)?;
        let tree = &self.scene.assembly;
        let mesh = tree.meshes.get(tree.nodes[info.node].mesh?)?;
        bounds_of(
            mesh.positions
                .iter()
                .map(|p| info.world.transform_point3(DVec3::from(p.map(f64::from)))),
        )
    }

    /// Whether `node` or one of its ancestors is in `hidden`.
    pub fn node_hidden(&self, node: usize, hidden: &[bool]) -> bool {
        let mut n = Some(node);
        // The tree has no cycles, but a bound keeps a malformed one from hanging the UI.
        for _ in 0..=self.parents.len() {
            let Some(i) = n else { return false };
            if hidden.get(i).copied().unwrap_or(false) {
                return true;
            }
            n = self.parents.get(i).copied().flatten();
        }
        false
    }
}

/// The box of `points` (finite ones), or `None` for none.
pub fn bounds_of(points: impl Iterator<Item = DVec3>) -> Option<(DVec3, DVec3)> {
    points
        .filter(|p| p.is_finite())
        .fold(None, |acc, p| match acc {
            None => Some((p, p)),
            Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pin-assembly.step")
    }

    #[test]
    fn a_scene_file_of_quadrics_opens_as_a_document() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/teapot.json");
        let doc = Document::load(&path, &|_| {}).expect("loads");
        assert_eq!(doc.scene.primitives.len(), 10);
        assert!(doc.bounds.is_some() && doc.warnings.is_empty());
        assert!(doc.model.faces.is_empty());
    }

    #[test]
    fn the_example_loads_with_progress_and_instances() {
        let stages = std::sync::Mutex::new(Vec::new());
        let doc = Document::load(&example(), &|s| stages.lock().unwrap().push(s)).expect("loads");
        let stages = stages.into_inner().unwrap();
        assert_eq!(stages.first(), Some(&LoadStage::Reading));
        assert!(
            stages
                .iter()
                .any(|s| matches!(s, LoadStage::Meshing { .. }))
        );
        let fractions: Vec<f32> = stages.iter().map(LoadStage::fraction).collect();
        assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{fractions:?}");
        assert!(doc.instances.len() >= 2);
        assert!(doc.bounds.is_some());
        let b = doc.instance_bounds(0).expect("instance box");
        assert!((b.1 - b.0).length() > 0.0);
        assert_eq!(doc.title(), "pin-assembly.step");
    }

    #[test]
    fn a_missing_file_is_an_error_naming_it() {
        let err = match Document::load(Path::new("/nonexistent/x.step"), &|_| {}) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("loaded a missing file"),
        };
        assert!(err.contains("/nonexistent/x.step"), "{err}");
    }

    #[test]
    fn hiding_a_node_hides_its_descendants() {
        let doc = Document::load(&example(), &|_| {}).expect("loads");
        let leaf = doc.instances[0].node;
        let mut hidden = vec![false; doc.scene.assembly.nodes.len()];
        assert!(!doc.node_hidden(leaf, &hidden));
        let root = doc.scene.assembly.roots[0];
        hidden[root] = true;
        assert!(doc.node_hidden(leaf, &hidden));
    }
}
