//! The assembled tessellation: part meshes, materials, the occurrence tree and the dense ids
//! of the model's entities, filled by [`crate::assemble`] (typically from a STEP assembly)
//! and consumed by every writer of [`crate::export`] and by the renderer's scene.

use glam::{DAffine3, DVec3};

/// Deepest node nesting that is followed: nodes deeper than this (roots are at depth 0) are
/// skipped with their subtrees by [`Scene::instances`] and every writer. Above the STEP
/// mapper's own cap ([`cadre_brep::assembly::MAX_ASSEMBLY_DEPTH`], which warns where it cuts)
/// with room for the body nodes under the deepest part: an assembly the model keeps is never
/// cut here silently (at 256, a 300-level chain loaded whole and exported nothing).
pub const MAX_DEPTH: usize = cadre_brep::assembly::MAX_ASSEMBLY_DEPTH + 4;

/// Most node visits (one per node per path from a root) a scene may need; a deeper or wider
/// node graph (e.g. a long chain of shared sub-assemblies) is rejected by
/// [`Scene::validate`] with [`SceneError::TooManyNodeVisits`] instead of exploding.
pub const MAX_NODE_VISITS: usize = 1 << 22;

/// A complete scene to export.
///
/// Geometry is expressed in [`Scene::unit_name`] units (millimetres for cadre), both the vertex
/// positions and the node translations. Meshes are referenced by index from nodes; a mesh
/// referenced by several nodes is an instance and is written once by formats that support
/// instancing (glTF), and once per instance by flattening formats (STL, OBJ).
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Mesh definitions, referenced by [`SceneNode::mesh`].
    pub meshes: Vec<SceneMesh>,
    /// Materials, referenced by [`Primitive::material`].
    pub materials: Vec<Material>,
    /// All nodes, referenced by [`Scene::roots`] and [`SceneNode::children`].
    pub nodes: Vec<SceneNode>,
    /// Top-level nodes. Nodes not reachable from a root are not exported.
    pub roots: Vec<usize>,
    /// Length unit of positions and translations: `"mm"` for cadre. The glTF writer converts
    /// to metres with a root scale (see [`Scene::metres_per_unit`] for the names it knows).
    pub unit_name: String,
    /// What the ids of faces, edges and vertices stand for: dense model ids with their STEP
    /// ids ([`SceneIds`]).
    pub ids: SceneIds,
}

/// The ids a scene's faces, edges and vertices carry ([`Primitive::face_ids`],
/// [`SceneEdge::id`], [`SceneVertex::id`]): dense model ids, `index + 1` in the model's
/// arenas (0 = none), so that every entity has its own id whatever its STEP id (which may
/// exceed 2³² or be shared by healed entities); face ids past the B-Rep faces are the file's
/// tessellated items. The STEP ids are kept here for display and for the file writers. A
/// scene made without a model (by hand, in tests) has empty tables: its ids are their own
/// STEP ids.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneIds {
    /// STEP id of face id `k + 1`: the model's B-Rep faces, then its tessellated items.
    pub face_step_ids: Vec<u64>,
    /// How many face ids are B-Rep faces (face id `k + 1` is `FaceId(k)` below it,
    /// `MeshId(k - brep_faces)` from it).
    pub brep_faces: usize,
    /// STEP id of edge id `k + 1` (`EdgeId(k)`).
    pub edge_step_ids: Vec<u64>,
    /// STEP id of vertex id `k + 1` (`VertexId(k)`).
    pub vertex_step_ids: Vec<u64>,
}

/// The dense id of arena index `index` (`index + 1`, 0 past `u32`).
fn dense(index: usize) -> u32 {
    u32::try_from(index + 1).unwrap_or(0)
}

/// `table[id - 1]`, or `id` itself when the table is empty (a scene without a model).
fn step_id_in(table: &[u64], id: u32) -> u64 {
    if table.is_empty() || id == 0 {
        return u64::from(id);
    }
    table.get(id as usize - 1).copied().unwrap_or(0)
}

impl SceneIds {
    /// The ids of `model`'s faces, tessellated items, edges and vertices.
    pub fn of(model: &cadre_brep::Model) -> SceneIds {
        SceneIds {
            face_step_ids: model
                .faces
                .iter()
                .map(|f| f.step_id)
                .chain(model.meshes.iter().map(|m| m.step_id))
                .collect(),
            brep_faces: model.faces.len(),
            edge_step_ids: model.edges.iter().map(|e| e.step_id).collect(),
            vertex_step_ids: model.vertices.iter().map(|v| v.step_id).collect(),
        }
    }

    /// The face id of B-Rep face `face`.
    pub fn face_id(face: cadre_brep::FaceId) -> u32 {
        dense(face.index())
    }

    /// The face id of the tessellated item `mesh` (after the B-Rep faces).
    pub fn mesh_face_id(&self, mesh: cadre_brep::MeshId) -> u32 {
        dense(self.brep_faces + mesh.index())
    }

    /// The edge id of `edge`.
    pub fn edge_id(edge: cadre_brep::EdgeId) -> u32 {
        dense(edge.index())
    }

    /// The vertex id of `vertex`.
    pub fn vertex_id(vertex: cadre_brep::VertexId) -> u32 {
        dense(vertex.index())
    }

    /// The B-Rep face of face id `id`, if it is one.
    pub fn brep_face(&self, id: u32) -> Option<cadre_brep::FaceId> {
        let k = (id as usize).checked_sub(1)?;
        (k < self.brep_faces).then_some(cadre_brep::FaceId(k as u32))
    }

    /// The tessellated item of face id `id`, if it is one.
    pub fn tessellated(&self, id: u32) -> Option<cadre_brep::MeshId> {
        let k = (id as usize).checked_sub(1)?.checked_sub(self.brep_faces)?;
        (k + self.brep_faces < self.face_step_ids.len()).then_some(cadre_brep::MeshId(k as u32))
    }

    /// The edge of edge id `id`.
    pub fn edge(&self, id: u32) -> Option<cadre_brep::EdgeId> {
        let k = (id as usize).checked_sub(1)?;
        (k < self.edge_step_ids.len()).then_some(cadre_brep::EdgeId(k as u32))
    }

    /// The vertex of vertex id `id`.
    pub fn vertex(&self, id: u32) -> Option<cadre_brep::VertexId> {
        let k = (id as usize).checked_sub(1)?;
        (k < self.vertex_step_ids.len()).then_some(cadre_brep::VertexId(k as u32))
    }

    /// The STEP id of face id `id` (0 for none).
    pub fn face_step_id(&self, id: u32) -> u64 {
        step_id_in(&self.face_step_ids, id)
    }

    /// The STEP id of edge id `id` (0 for none).
    pub fn edge_step_id(&self, id: u32) -> u64 {
        step_id_in(&self.edge_step_ids, id)
    }

    /// The STEP id of vertex id `id` (0 for none).
    pub fn vertex_step_id(&self, id: u32) -> u64 {
        step_id_in(&self.vertex_step_ids, id)
    }
}

impl Default for Scene {
    /// An empty scene in millimetres.
    fn default() -> Self {
        Self::new("mm")
    }
}

/// One mesh: a vertex buffer shared by one or more primitives (one per material).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneMesh {
    /// Name (written to glTF; informative only).
    pub name: String,
    /// Vertex positions, in [`Scene::unit_name`] units, mesh-local coordinates.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position, or empty when the mesh has no normals (the
    /// flattening writers then use face normals; glTF omits the attribute).
    pub normals: Vec<[f32; 3]>,
    /// Parameters (u, v) of each vertex on its B-Rep face's exact surface (unwrapped across
    /// seams), one per position, or empty (meshes from the file). The renderer keeps them in
    /// its visibility buffer; the file writers do not write them.
    pub surface_uv: Vec<[f32; 2]>,
    /// Segments of wire bodies (edges and curves standing alone, as in wireframe models),
    /// mesh-local; the renderer draws them, the file writers do not write them yet.
    pub lines: Vec<[[f32; 3]; 2]>,
    /// Triangle sets sharing [`SceneMesh::positions`].
    pub primitives: Vec<Primitive>,
    /// The B-Rep edges bounding this mesh's faces, once each (seams left out), as polylines
    /// through the samples every face's mesh shares: what the renderer draws as edges and
    /// picks by id. Empty for meshes from the file (the renderer then finds feature edges).
    pub edges: Vec<SceneEdge>,
    /// The B-Rep vertices at the ends of [`SceneMesh::edges`], once each, for picking.
    pub vertices: Vec<SceneVertex>,
}

/// A B-Rep edge of a [`SceneMesh`], as a polyline.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneEdge {
    /// Edge id ([`SceneIds`]: the model's edge index + 1; its STEP id through
    /// [`SceneIds::edge_step_id`]), 0 for none.
    pub id: u32,
    /// Points from the edge's start to its end, mesh-local.
    pub points: Vec<[f32; 3]>,
}

/// A B-Rep vertex of a [`SceneMesh`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneVertex {
    /// Vertex id ([`SceneIds`]: the model's vertex index + 1; its STEP id through
    /// [`SceneIds::vertex_step_id`]), 0 for none.
    pub id: u32,
    /// Position, mesh-local.
    pub position: [f32; 3],
}

/// Triangles of one mesh with one material.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Primitive {
    /// Triangle list: three indices into [`SceneMesh::positions`] per triangle, counter-clockwise
    /// seen from outside (outward normal by the right-hand rule).
    pub indices: Vec<u32>,
    /// Index into [`Scene::materials`], or `None` for a default material.
    pub material: Option<usize>,
    /// Per triangle: the face id of the B-Rep face (or tessellated item) it comes from
    /// ([`SceneIds`]; 0 = none). Either empty (no ids) or exactly `indices.len() / 3` long.
    ///
    /// The glTF writer stores these as a per-vertex attribute, which assumes every vertex
    /// belongs to a single face (vertices are duplicated along face boundaries by the mesher);
    /// when a vertex is used by triangles with different ids, the first triangle (in primitive
    /// then index order) wins.
    pub face_ids: Vec<u32>,
}

/// A PBR metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name (written to glTF and MTL).
    pub name: String,
    /// Linear RGBA base colour, each in [0, 1]; alpha < 1 means blended transparency.
    pub base_color: [f32; 4],
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness in [0, 1].
    pub roughness: f32,
}

impl Default for Material {
    /// Opaque light grey, dielectric, fairly rough.
    fn default() -> Self {
        Self {
            name: String::new(),
            base_color: [0.8, 0.8, 0.8, 1.0],
            metallic: 0.0,
            roughness: 0.5,
        }
    }
}

/// A node of the scene tree (an assembly occurrence or a part occurrence).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneNode {
    /// Name (written to glTF nodes and OBJ objects).
    pub name: String,
    /// Placement relative to the parent node (or to the scene for roots), in
    /// [`Scene::unit_name`] units. Mirrors (negative determinant) are allowed.
    pub transform: DAffine3,
    /// Index into [`Scene::meshes`] of the mesh placed at this node.
    pub mesh: Option<usize>,
    /// Child node indices.
    pub children: Vec<usize>,
}

impl Default for SceneNode {
    /// An unnamed identity node without mesh or children.
    fn default() -> Self {
        Self {
            name: String::new(),
            transform: DAffine3::IDENTITY,
            mesh: None,
            children: Vec::new(),
        }
    }
}

/// An inconsistency in a [`Scene`] found by [`Scene::validate`] (which every writer runs first).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// A root index is not a node.
    #[error("root {root} is not a node (scene has {count} nodes)")]
    RootIndex {
        /// The bad index.
        root: usize,
        /// Number of nodes.
        count: usize,
    },
    /// A child index is not a node.
    #[error("node {node}: child {child} is not a node (scene has {count} nodes)")]
    ChildIndex {
        /// Parent node.
        node: usize,
        /// The bad index.
        child: usize,
        /// Number of nodes.
        count: usize,
    },
    /// A node's mesh index is not a mesh.
    #[error("node {node}: mesh {mesh} is not a mesh (scene has {count} meshes)")]
    MeshIndex {
        /// The node.
        node: usize,
        /// The bad index.
        mesh: usize,
        /// Number of meshes.
        count: usize,
    },
    /// A node transform has a NaN or infinite coefficient.
    #[error("node {node}: transform is not finite")]
    NonFiniteTransform {
        /// The node.
        node: usize,
    },
    /// The normal count is neither 0 nor the position count.
    #[error("mesh {mesh}: {normals} normals for {positions} positions")]
    NormalCount {
        /// The mesh.
        mesh: usize,
        /// Number of normals.
        normals: usize,
        /// Number of positions.
        positions: usize,
    },
    /// A position or normal has a NaN or infinite coordinate.
    #[error("mesh {mesh}: vertex {vertex} has a non-finite position or normal")]
    NonFiniteVertex {
        /// The mesh.
        mesh: usize,
        /// The vertex.
        vertex: usize,
    },
    /// The mesh has more vertices than 32-bit indices can address.
    #[error("mesh {mesh}: {positions} vertices exceed the 32-bit index range")]
    TooManyVertices {
        /// The mesh.
        mesh: usize,
        /// Number of positions.
        positions: usize,
    },
    /// The index count is not a multiple of 3.
    #[error("mesh {mesh} primitive {primitive}: {len} indices is not a whole number of triangles")]
    IndexCount {
        /// The mesh.
        mesh: usize,
        /// The primitive.
        primitive: usize,
        /// Number of indices.
        len: usize,
    },
    /// An index is not a vertex.
    #[error("mesh {mesh} primitive {primitive}: index {index} out of range ({count} vertices)")]
    VertexIndex {
        /// The mesh.
        mesh: usize,
        /// The primitive.
        primitive: usize,
        /// The bad index.
        index: u32,
        /// Number of positions.
        count: usize,
    },
    /// A material index is not a material.
    #[error(
        "mesh {mesh} primitive {primitive}: material {material} is not a material \
         (scene has {count} materials)"
    )]
    MaterialIndex {
        /// The mesh.
        mesh: usize,
        /// The primitive.
        primitive: usize,
        /// The bad index.
        material: usize,
        /// Number of materials.
        count: usize,
    },
    /// The face id count is neither 0 nor the triangle count.
    #[error("mesh {mesh} primitive {primitive}: {face_ids} face ids for {triangles} triangles")]
    FaceIdCount {
        /// The mesh.
        mesh: usize,
        /// The primitive.
        primitive: usize,
        /// Number of face ids.
        face_ids: usize,
        /// Number of triangles.
        triangles: usize,
    },
    /// A material has a NaN or infinite factor.
    #[error("material {material}: colour or factor is not finite")]
    NonFiniteMaterial {
        /// The material.
        material: usize,
    },
    /// The node graph needs more than [`MAX_NODE_VISITS`] visits (shared sub-trees nested
    /// too often).
    #[error("node graph expands to more than {limit} node instances")]
    TooManyNodeVisits {
        /// [`MAX_NODE_VISITS`].
        limit: usize,
    },
}

impl Scene {
    /// An empty scene whose geometry is in `unit_name` units.
    pub fn new(unit_name: impl Into<String>) -> Self {
        Self {
            meshes: Vec::new(),
            materials: Vec::new(),
            nodes: Vec::new(),
            roots: Vec::new(),
            unit_name: unit_name.into(),
            ids: SceneIds::default(),
        }
    }

    /// Size of one [`Scene::unit_name`] unit in metres, for the names `mm`, `cm`, `m`, `um`,
    /// `in` and `ft` (and their spelled-out forms, case-insensitive); `None` otherwise.
    pub fn metres_per_unit(&self) -> Option<f64> {
        let unit = self.unit_name.trim().to_ascii_lowercase();
        Some(match unit.as_str() {
            "mm" | "millimetre" | "millimeter" | "millimetres" | "millimeters" => 1e-3,
            "cm" | "centimetre" | "centimeter" | "centimetres" | "centimeters" => 1e-2,
            "m" | "metre" | "meter" | "metres" | "meters" => 1.0,
            "um" | "µm" | "micron" | "microns" | "micrometre" | "micrometer" | "micrometres"
            | "micrometers" => 1e-6,
            "in" | "inch" | "inches" => 0.0254,
            "ft" | "foot" | "feet" => 0.3048,
            _ => return None,
        })
    }

    /// Checks every index, count and value the writers rely on; writers call it first, so
    /// a scene that passes can be written without panics.
    pub fn validate(&self) -> Result<(), SceneError> {
        let node_count = self.nodes.len();
        for &root in &self.roots {
            if root >= node_count {
                return Err(SceneError::RootIndex {
                    root,
                    count: node_count,
                });
            }
        }
        for (n, node) in self.nodes.iter().enumerate() {
            if let Some(&child) = node.children.iter().find(|&&c| c >= node_count) {
                return Err(SceneError::ChildIndex {
                    node: n,
                    child,
                    count: node_count,
                });
            }
            if let Some(mesh) = node.mesh
                && mesh >= self.meshes.len()
            {
                return Err(SceneError::MeshIndex {
                    node: n,
                    mesh,
                    count: self.meshes.len(),
                });
            }
            if !node.transform.is_finite() {
                return Err(SceneError::NonFiniteTransform { node: n });
            }
        }
        for (m, mat) in self.materials.iter().enumerate() {
            if !(mat.base_color.iter().all(|c| c.is_finite())
                && mat.metallic.is_finite()
                && mat.roughness.is_finite())
            {
                return Err(SceneError::NonFiniteMaterial { material: m });
            }
        }
        for (m, mesh) in self.meshes.iter().enumerate() {
            self.validate_mesh(m, mesh)?;
        }
        let mut visits = 0usize;
        for _ in self.walk() {
            visits += 1;
            if visits > MAX_NODE_VISITS {
                return Err(SceneError::TooManyNodeVisits {
                    limit: MAX_NODE_VISITS,
                });
            }
        }
        Ok(())
    }

    fn validate_mesh(&self, m: usize, mesh: &SceneMesh) -> Result<(), SceneError> {
        let count = mesh.positions.len();
        if u32::try_from(count).is_err() {
            return Err(SceneError::TooManyVertices {
                mesh: m,
                positions: count,
            });
        }
        if !mesh.normals.is_empty() && mesh.normals.len() != count {
            return Err(SceneError::NormalCount {
                mesh: m,
                normals: mesh.normals.len(),
                positions: count,
            });
        }
        let finite = |p: &[f32; 3]| p.iter().all(|c| c.is_finite());
        if let Some(vertex) = mesh.positions.iter().position(|p| !finite(p)) {
            return Err(SceneError::NonFiniteVertex { mesh: m, vertex });
        }
        if let Some(vertex) = mesh.normals.iter().position(|p| !finite(p)) {
            return Err(SceneError::NonFiniteVertex { mesh: m, vertex });
        }
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if prim.indices.len() % 3 != 0 {
                return Err(SceneError::IndexCount {
                    mesh: m,
                    primitive: p,
                    len: prim.indices.len(),
                });
            }
            if let Some(&index) = prim.indices.iter().find(|&&i| i as usize >= count) {
                return Err(SceneError::VertexIndex {
                    mesh: m,
                    primitive: p,
                    index,
                    count,
                });
            }
            if let Some(material) = prim.material
                && material >= self.materials.len()
            {
                return Err(SceneError::MaterialIndex {
                    mesh: m,
                    primitive: p,
                    material,
                    count: self.materials.len(),
                });
            }
            let triangles = prim.indices.len() / 3;
            if !prim.face_ids.is_empty() && prim.face_ids.len() != triangles {
                return Err(SceneError::FaceIdCount {
                    mesh: m,
                    primitive: p,
                    face_ids: prim.face_ids.len(),
                    triangles,
                });
            }
        }
        Ok(())
    }

    /// Every placed mesh: `(node index, world transform)` for each node with a mesh, once per
    /// path from a root (a node reachable along two paths is two instances), depth first in
    /// root and child order.
    ///
    /// Never panics or loops: out-of-range indices are skipped, a node that is its own
    /// ancestor is skipped (with its subtree) where it recurs, and nothing deeper than
    /// [`MAX_DEPTH`] is followed. World transforms are in [`Scene::unit_name`] units.
    pub fn instances(&self) -> Instances<'_> {
        Instances { walk: self.walk() }
    }

    /// Total number of triangles of all [`Scene::instances`] (what STL writes).
    pub fn instance_triangle_count(&self) -> u64 {
        self.instances()
            .filter_map(|(n, _)| self.nodes[n].mesh.and_then(|m| self.meshes.get(m)))
            .map(|mesh| {
                mesh.primitives
                    .iter()
                    .map(|p| (p.indices.len() / 3) as u64)
                    .sum::<u64>()
            })
            .sum()
    }

    /// Depth-first pre-order walk of the node graph from the roots.
    pub(crate) fn walk(&self) -> Walk<'_> {
        let stack = self
            .roots
            .iter()
            .rev()
            .map(|&node| Pending {
                node,
                parent: None,
                parent_world: DAffine3::IDENTITY,
                depth: 0,
            })
            .collect();
        Walk {
            scene: self,
            stack,
            path: Vec::new(),
            next_visit: 0,
        }
    }
}

/// One node reached by [`Walk`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Visit {
    /// Index into [`Scene::nodes`].
    pub node: usize,
    /// Visit number (0, 1, ...) of the parent visit; `None` for roots.
    pub parent: Option<usize>,
    /// Accumulated transform from the scene root.
    pub world: DAffine3,
}

#[derive(Clone, Copy, Debug)]
struct Pending {
    node: usize,
    parent: Option<usize>,
    parent_world: DAffine3,
    depth: usize,
}

/// Depth-first pre-order traversal guarded against bad indices, cycles and depth.
#[derive(Clone, Debug)]
pub(crate) struct Walk<'a> {
    scene: &'a Scene,
    stack: Vec<Pending>,
    /// Nodes of the current root-to-node path (ancestors of the next pending entry).
    path: Vec<usize>,
    next_visit: usize,
}

impl Iterator for Walk<'_> {
    type Item = Visit;

    fn next(&mut self) -> Option<Visit> {
        while let Some(p) = self.stack.pop() {
            // Pre-order: the ancestors of an entry at depth d are the first d path entries.
            self.path.truncate(p.depth);
            let Some(node) = self.scene.nodes.get(p.node) else {
                continue;
            };
            if p.depth >= MAX_DEPTH || self.path.contains(&p.node) {
                continue;
            }
            let world = p.parent_world * node.transform;
            let visit = self.next_visit;
            self.next_visit += 1;
            self.path.push(p.node);
            for &child in node.children.iter().rev() {
                self.stack.push(Pending {
                    node: child,
                    parent: Some(visit),
                    parent_world: world,
                    depth: p.depth + 1,
                });
            }
            return Some(Visit {
                node: p.node,
                parent: p.parent,
                world,
            });
        }
        None
    }
}

/// Iterator of [`Scene::instances`]: `(node index, world transform)` of every placed mesh.
#[derive(Clone, Debug)]
pub struct Instances<'a> {
    walk: Walk<'a>,
}

impl Iterator for Instances<'_> {
    type Item = (usize, DAffine3);

    fn next(&mut self) -> Option<(usize, DAffine3)> {
        let scene = self.walk.scene;
        self.walk.by_ref().find_map(|v| {
            scene.nodes[v.node]
                .mesh
                .filter(|&m| m < scene.meshes.len())
                .map(|_| (v.node, v.world))
        })
    }
}

/// Whether `t` mirrors (negative determinant of its linear part).
pub(crate) fn is_mirror(t: &DAffine3) -> bool {
    t.matrix3.determinant() < 0.0
}

/// The point `p` transformed by `t`, computed in `f64`.
pub(crate) fn transform_point(t: &DAffine3, p: [f32; 3]) -> DVec3 {
    t.transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
}

/// The normal `n` transformed by the inverse transpose of `t`'s linear part, normalised
/// (zero if degenerate).
pub(crate) fn transform_normal(normal_matrix: &glam::DMat3, n: [f32; 3]) -> DVec3 {
    (*normal_matrix * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)).normalize_or_zero()
}

/// The matrix that maps normals under `t` (inverse transpose of the linear part; identity
/// when singular).
pub(crate) fn normal_matrix(t: &DAffine3) -> glam::DMat3 {
    let m = t.matrix3;
    if m.determinant() == 0.0 {
        glam::DMat3::IDENTITY
    } else {
        m.inverse().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(children: Vec<usize>, mesh: Option<usize>) -> SceneNode {
        SceneNode {
            name: String::new(),
            transform: DAffine3::from_translation(DVec3::X),
            mesh,
            children,
        }
    }

    fn scene_with(nodes: Vec<SceneNode>, roots: Vec<usize>) -> Scene {
        Scene {
            meshes: vec![SceneMesh::default()],
            nodes,
            roots,
            ..Scene::default()
        }
    }

    #[test]
    fn self_child_is_skipped() {
        let s = scene_with(
            vec![node(vec![0, 1], Some(0)), node(vec![], Some(0))],
            vec![0],
        );
        let inst: Vec<_> = s.instances().collect();
        assert_eq!(inst.len(), 2);
        assert_eq!(inst[0].0, 0);
        assert_eq!(inst[1].0, 1);
        assert_eq!(inst[1].1.translation, DVec3::new(2.0, 0.0, 0.0));
        assert!(s.validate().is_ok());
    }

    #[test]
    fn cycle_of_two_terminates() {
        let s = scene_with(
            vec![node(vec![1], Some(0)), node(vec![0], Some(0))],
            vec![0, 1],
        );
        let inst: Vec<_> = s.instances().map(|i| i.0).collect();
        assert_eq!(inst, vec![0, 1, 1, 0]);
    }

    #[test]
    fn depth_is_capped() {
        // A chain of distinct nodes longer than MAX_DEPTH: only the first MAX_DEPTH are
        // visited; a 300-level chain (negative control) is visited whole.
        let chain = |n: usize| {
            let nodes: Vec<_> = (0..n)
                .map(|i| node(if i + 1 < n { vec![i + 1] } else { vec![] }, Some(0)))
                .collect();
            scene_with(nodes, vec![0])
        };
        assert_eq!(chain(MAX_DEPTH + 50).instances().count(), MAX_DEPTH);
        assert_eq!(chain(300).instances().count(), 300);
    }

    #[test]
    fn bad_indices_do_not_panic() {
        let s = scene_with(vec![node(vec![7], Some(3))], vec![0, 9]);
        assert_eq!(s.instances().count(), 0);
        assert!(matches!(
            s.validate(),
            Err(SceneError::RootIndex { root: 9, .. })
        ));
    }

    #[test]
    fn shared_subtree_explosion_is_rejected() {
        // 30 levels, each node having the next one twice: 2^30 paths.
        let nodes: Vec<_> = (0..30)
            .map(|i| {
                node(
                    if i + 1 < 30 {
                        vec![i + 1, i + 1]
                    } else {
                        vec![]
                    },
                    None,
                )
            })
            .collect();
        let s = scene_with(nodes, vec![0]);
        assert!(matches!(
            s.validate(),
            Err(SceneError::TooManyNodeVisits { .. })
        ));
    }

    #[test]
    fn validate_catches_mesh_errors() {
        let mut s = scene_with(vec![node(vec![], Some(0))], vec![0]);
        s.meshes[0].positions = vec![[0.0; 3]; 3];
        s.meshes[0].primitives.push(Primitive {
            indices: vec![0, 1, 3],
            ..Primitive::default()
        });
        assert!(matches!(
            s.validate(),
            Err(SceneError::VertexIndex { index: 3, .. })
        ));
        s.meshes[0].primitives[0].indices = vec![0, 1];
        assert!(matches!(s.validate(), Err(SceneError::IndexCount { .. })));
        s.meshes[0].primitives[0].indices = vec![0, 1, 2];
        s.meshes[0].primitives[0].face_ids = vec![1, 2];
        assert!(matches!(s.validate(), Err(SceneError::FaceIdCount { .. })));
        s.meshes[0].primitives[0].face_ids = vec![1];
        s.meshes[0].primitives[0].material = Some(0);
        assert!(matches!(
            s.validate(),
            Err(SceneError::MaterialIndex { .. })
        ));
        s.meshes[0].primitives[0].material = None;
        s.meshes[0].positions[1][2] = f32::NAN;
        assert!(matches!(
            s.validate(),
            Err(SceneError::NonFiniteVertex { vertex: 1, .. })
        ));
        s.meshes[0].positions[1][2] = 0.0;
        assert_eq!(s.validate(), Ok(()));
    }

    #[test]
    fn units() {
        assert_eq!(Scene::new("mm").metres_per_unit(), Some(1e-3));
        assert_eq!(Scene::new("Inch").metres_per_unit(), Some(0.0254));
        assert_eq!(Scene::new("parsec").metres_per_unit(), None);
    }
}
