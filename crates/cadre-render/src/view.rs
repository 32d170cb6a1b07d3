//! What a viewer changes between frames without touching the geometry: which instances are
//! shown and in which colour, what is hovered and selected, where the model is cut.

use glam::DVec3;

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

/// Something a user can point at: a B-Rep face, edge or vertex of one instance (by the
/// scene's dense model id, the ids the visibility and pick buffers hold:
/// [`crate::RenderScene::face`] gives the model entity, the model its STEP id), or a whole
/// instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pick {
    /// A face of an instance.
    Face {
        /// Instance number (scene instance order).
        instance: u32,
        /// Face id (the model's face index + 1).
        face: u32,
    },
    /// An edge of an instance.
    Edge {
        /// Instance number.
        instance: u32,
        /// Edge id (the model's edge index + 1).
        edge: u32,
    },
    /// A vertex of an instance.
    Vertex {
        /// Instance number.
        instance: u32,
        /// Vertex id (the model's vertex index + 1).
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
    /// Section planes: the first [`MAX_SECTIONS`] cut the model (the rest are ignored), each
    /// removing the half-space on its normal's side; closed solids show hatched caps where
    /// they are cut.
    pub sections: Vec<SectionPlane>,
    /// What of the scene's line set is shown (all of it by default).
    pub lines: crate::LineView,
}

/// Most section planes a frame applies; [`ViewState::sections`] past these are ignored.
pub const MAX_SECTIONS: usize = 3;

/// A section plane in world coordinates (model units): it keeps the points `p` with
/// `normal · p <= offset` and cuts away the half-space `normal · p > offset`, the side its
/// normal points to (so the normal points from the kept part towards the viewer who looks
/// into the cut).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionPlane {
    /// Unit normal, world; a normal that is not unit is normalised with its offset, a zero
    /// or non-finite one makes the plane inactive.
    pub normal: DVec3,
    /// Signed distance of the plane from the world origin along `normal`.
    pub offset: f64,
}

impl SectionPlane {
    /// The plane through `point` with `normal` (normalised), cutting away the side `normal`
    /// points to.
    pub fn through(point: DVec3, normal: DVec3) -> SectionPlane {
        let normal = normal.normalize_or_zero();
        SectionPlane {
            normal,
            offset: normal.dot(point),
        }
    }

    /// Unit normal and offset, `None` for a plane without a usable normal.
    pub(crate) fn normalised(self) -> Option<(DVec3, f64)> {
        let len = self.normal.length();
        (len.is_finite() && len > 1e-300 && self.offset.is_finite())
            .then(|| (self.normal / len, self.offset / len))
    }

    /// Whether `p` is kept (on or behind the plane).
    pub fn keeps(self, p: DVec3) -> bool {
        self.normalised().is_none_or(|(n, d)| n.dot(p) <= d)
    }
}

/// Flag in the material channel of the visibility buffer's ids ([`crate::Renderer::render_ids`])
/// marking a section cap: the pixel shows the inside of a closed solid cut by a plane, at the
/// plane's depth. Bits 28–29 hold the plane's index, the bits below the material.
pub const SECTION_CAP: u32 = 1 << 31;

/// Flag in the material channel of a pixel's ids (not a section cap's) marking a crack the
/// crack pass filled, set in the inspection view only ([`crate::CrackOptions::highlight`]):
/// the shade pass paints it magenta.
pub const CRACK_FILLED: u32 = 1 << 30;

/// The same for a real gap in the model narrower than the gap tolerance, closed by the crack
/// pass ([`crate::CrackOptions::gap_tolerance`]): painted orange.
pub const GAP_CLOSED: u32 = 1 << 29;

/// The index (into [`ViewState::sections`]) of the plane whose cap `ids` (one pixel of the
/// visibility buffer) shows, or `None` when it shows a face or the background.
pub fn section_cap(ids: [u32; 4]) -> Option<usize> {
    (ids[1] != 0 && ids[2] & SECTION_CAP != 0).then_some(((ids[2] >> 28) & 3) as usize)
}

/// Most selected items the shaders highlight (the rest stay selected, unhighlighted).
pub const MAX_HIGHLIGHTED: usize = 1024;
