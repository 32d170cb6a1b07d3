//! STEP instance ids of a model's faces, edges and vertices, and the parts that own them: for
//! the command line and tools that name entities by the file's ids. The renderer and the viewer
//! key entities by the model's dense ids instead (the STEP id of each is on the entity itself).

use std::collections::HashMap;

use crate::{Body, EdgeId, FaceId, LoopKind, Model, PartId, VertexId};

/// A picked entity of the B-Rep model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Entity {
    /// A face.
    Face(FaceId),
    /// An edge.
    Edge(EdgeId),
    /// A vertex.
    Vertex(VertexId),
}

impl From<FaceId> for Entity {
    fn from(id: FaceId) -> Self {
        Entity::Face(id)
    }
}

impl From<EdgeId> for Entity {
    fn from(id: EdgeId) -> Self {
        Entity::Edge(id)
    }
}

impl From<VertexId> for Entity {
    fn from(id: VertexId) -> Self {
        Entity::Vertex(id)
    }
}

/// STEP instance id → face, edge and vertex ids of one model, and the part owning each face,
/// edge and vertex. Build it once per model ([`StepIndex::new`]); lookups are hash lookups.
///
/// Where the file's id is shared by several entities (made by repairs) the first one wins;
/// entities made by the reader (STEP id 0) are not indexed.
#[derive(Clone, Debug, Default)]
pub struct StepIndex {
    faces: HashMap<u64, FaceId>,
    edges: HashMap<u64, EdgeId>,
    vertices: HashMap<u64, VertexId>,
    face_parts: Vec<Option<PartId>>,
    edge_parts: Vec<Option<PartId>>,
    vertex_parts: Vec<Option<PartId>>,
}

impl StepIndex {
    /// Indexes every face, edge and vertex of `model` by STEP id, and records which part owns
    /// each (the first part, in arena order, whose bodies reach it).
    pub fn new(model: &Model) -> Self {
        fn index<I: Copy>(ids: impl Iterator<Item = (u64, I)>) -> HashMap<u64, I> {
            let mut map = HashMap::new();
            for (step, id) in ids.filter(|(step, _)| *step != 0) {
                map.entry(step).or_insert(id);
            }
            map
        }
        let mut index = StepIndex {
            faces: index(
                model
                    .faces
                    .iter()
                    .enumerate()
                    .map(|(i, f)| (f.step_id, FaceId(i as u32))),
            ),
            edges: index(
                model
                    .edges
                    .iter()
                    .enumerate()
                    .map(|(i, e)| (e.step_id, EdgeId(i as u32))),
            ),
            vertices: index(
                model
                    .vertices
                    .iter()
                    .enumerate()
                    .map(|(i, v)| (v.step_id, VertexId(i as u32))),
            ),
            face_parts: vec![None; model.faces.len()],
            edge_parts: vec![None; model.edges.len()],
            vertex_parts: vec![None; model.vertices.len()],
        };
        for (i, part) in model.parts.iter().enumerate() {
            let part_id = PartId(i as u32);
            for body in &part.bodies {
                match body {
                    Body::Solid(s) => {
                        let Some(solid) = model.solids.get(s.index()) else {
                            continue;
                        };
                        for shell in solid.shells() {
                            index.own_shell(model, shell.index(), part_id);
                        }
                    }
                    Body::Shell(s) => index.own_shell(model, s.index(), part_id),
                    Body::Face(f) => index.own_face(model, *f, part_id),
                    Body::Edge(e) => index.own_edge(model, *e, part_id),
                    Body::Mesh(_) | Body::Wire(_) | Body::Point(_) => {}
                }
            }
        }
        index
    }

    fn own_shell(&mut self, model: &Model, shell: usize, part: PartId) {
        if let Some(shell) = model.shells.get(shell) {
            for &(face, _) in &shell.faces {
                self.own_face(model, face, part);
            }
        }
    }

    fn own_face(&mut self, model: &Model, face: FaceId, part: PartId) {
        match self.face_parts.get_mut(face.index()) {
            Some(slot @ None) => *slot = Some(part),
            _ => return,
        }
        let Some(f) = model.faces.get(face.index()) else {
            return;
        };
        for l in &f.loops {
            match &l.kind {
                LoopKind::Edges(edges) => {
                    for oe in edges {
                        self.own_edge(model, oe.edge, part);
                    }
                }
                LoopKind::Vertex(v) => self.own_vertex(*v, part),
                LoopKind::Poly(_) => {}
            }
        }
    }

    fn own_edge(&mut self, model: &Model, edge: EdgeId, part: PartId) {
        if let Some(slot @ None) = self.edge_parts.get_mut(edge.index()) {
            *slot = Some(part);
            if let Some(e) = model.edges.get(edge.index()) {
                self.own_vertex(e.start, part);
                self.own_vertex(e.end, part);
            }
        }
    }

    fn own_vertex(&mut self, vertex: VertexId, part: PartId) {
        if let Some(slot @ None) = self.vertex_parts.get_mut(vertex.index()) {
            *slot = Some(part);
        }
    }

    /// The face written as STEP instance `step_id`.
    pub fn face(&self, step_id: u64) -> Option<FaceId> {
        self.faces.get(&step_id).copied()
    }

    /// The edge written as STEP instance `step_id` (an `EDGE_CURVE`).
    pub fn edge(&self, step_id: u64) -> Option<EdgeId> {
        self.edges.get(&step_id).copied()
    }

    /// The vertex written as STEP instance `step_id` (a `VERTEX_POINT`).
    pub fn vertex(&self, step_id: u64) -> Option<VertexId> {
        self.vertices.get(&step_id).copied()
    }

    /// Whatever STEP instance `step_id` is: a face, else an edge, else a vertex.
    pub fn entity(&self, step_id: u64) -> Option<Entity> {
        self.face(step_id)
            .map(Entity::Face)
            .or_else(|| self.edge(step_id).map(Entity::Edge))
            .or_else(|| self.vertex(step_id).map(Entity::Vertex))
    }

    /// The part owning `entity`, when some part's bodies reach it.
    pub fn part_of(&self, entity: impl Into<Entity>) -> Option<PartId> {
        match entity.into() {
            Entity::Face(f) => self.face_parts.get(f.index()).copied().flatten(),
            Entity::Edge(e) => self.edge_parts.get(e.index()).copied().flatten(),
            Entity::Vertex(v) => self.vertex_parts.get(v.index()).copied().flatten(),
        }
    }

    /// The display name of the part owning `entity` (see [`StepIndex::part_of`]).
    pub fn part_name<'m>(&self, model: &'m Model, entity: impl Into<Entity>) -> Option<&'m str> {
        let part = self.part_of(entity)?;
        model.parts.get(part.index()).map(|p| p.name.as_str())
    }
}
