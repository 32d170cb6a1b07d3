//! What a viewer changes between frames without touching the geometry: which instances are
//! shown and in which colour, what is hovered and selected.

/// How one instance (a placed part) is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceStyle {
    /// Whether it is drawn at all (hidden parts are neither drawn nor picked).
    pub visible: bool,
    /// A colour replacing the part's own materials: linear RGB and opacity (below 1 the
    /// part is drawn see-through, blended over the opaque image).
    pub colour: Option<[f32; 4]>,
}

impl Default for InstanceStyle {
    fn default() -> Self {
        InstanceStyle {
            visible: true,
            colour: None,
        }
    }
}

/// Something a user can point at: a B-Rep face, edge or vertex of one instance (by STEP
/// entity id, the ids the visibility and pick buffers hold), or a whole instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pick {
    /// A face of an instance.
    Face {
        /// Instance number (scene instance order).
        instance: u32,
        /// STEP id of the face.
        face: u32,
    },
    /// An edge of an instance.
    Edge {
        /// Instance number.
        instance: u32,
        /// STEP id of the edge.
        edge: u32,
    },
    /// A vertex of an instance.
    Vertex {
        /// Instance number.
        instance: u32,
        /// STEP id of the vertex.
        vertex: u32,
    },
    /// A whole instance (a part of the assembly).
    Part {
        /// Instance number.
        instance: u32,
    },
}

impl Pick {
    /// The instance it belongs to.
    pub fn instance(self) -> u32 {
        match self {
            Pick::Face { instance, .. }
            | Pick::Edge { instance, .. }
            | Pick::Vertex { instance, .. }
            | Pick::Part { instance } => instance,
        }
    }

    /// As the shaders read it: kind (1 face, 2 edge, 3 vertex, 4 part), instance + 1, id, 0.
    pub(crate) fn to_gpu(self) -> [u32; 4] {
        match self {
            Pick::Face { instance, face } => [1, instance + 1, face, 0],
            Pick::Edge { instance, edge } => [2, instance + 1, edge, 0],
            Pick::Vertex { instance, vertex } => [3, instance + 1, vertex, 0],
            Pick::Part { instance } => [4, instance + 1, 0, 0],
        }
    }
}

/// The per-frame state of a view.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewState {
    /// Per instance (scene instance order); instances past the end get the default style.
    pub instances: Vec<InstanceStyle>,
    /// What the cursor is over (drawn tinted).
    pub hover: Option<Pick>,
    /// The selection (drawn in the selection colour).
    pub selection: Vec<Pick>,
}

/// Most selected items the shaders highlight (the rest stay selected, unhighlighted).
pub const MAX_HIGHLIGHTED: usize = 1024;
