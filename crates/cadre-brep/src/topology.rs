//! Topological entities. Orientation flags are kept exactly as the file gives them and
//! composed on use, never "fixed" by reversing geometry.

use crate::{CurveId, EdgeId, FaceId, PcurveId, ShellId, SurfaceId, VertexId};
use cadre_geom::Vec3;

/// A vertex: a point in the model's length unit (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Position.
    pub point: Vec3,
    /// STEP instance id of the `VERTEX_POINT`, for messages (0 for vertices made by the reader).
    pub step_id: u64,
}

/// An edge: a bounded piece of a curve between two vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// The 3D curve, `None` for a degenerate edge (a pole of a sphere, a cone apex).
    pub curve: Option<CurveId>,
    /// Start vertex (the edge's own orientation).
    pub start: VertexId,
    /// End vertex.
    pub end: VertexId,
    /// Whether the edge runs in the curve's parameter direction (STEP `same_sense`).
    pub same_sense: bool,
    /// Parameter-space curves of this edge on the surfaces it bounds, as given by the file
    /// (`SURFACE_CURVE`/`SEAM_CURVE` associated geometry, `PCURVE`s). A seam edge has two on the
    /// same surface. They are parameterised like the 3D curve.
    pub pcurves: Vec<(SurfaceId, PcurveId)>,
    /// STEP instance id of the `EDGE_CURVE`, for messages.
    pub step_id: u64,
}

/// An edge used in a loop, possibly reversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OrientedEdge {
    /// The edge.
    pub edge: EdgeId,
    /// Whether the loop uses the edge in its own direction (STEP `ORIENTED_EDGE.orientation`).
    pub forward: bool,
}

/// What a loop is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopKind {
    /// A cycle of oriented edges (`EDGE_LOOP`).
    Edges(Vec<OrientedEdge>),
    /// A single vertex (`VERTEX_LOOP`), e.g. the apex of a cone face.
    Vertex(VertexId),
    /// A closed polygon of points (`POLY_LOOP`, faceted B-Reps).
    Poly(Vec<Vec3>),
}

/// A face boundary (`FACE_BOUND` / `FACE_OUTER_BOUND`).
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// The loop's content.
    pub kind: LoopKind,
    /// Whether the bound uses the loop in its own direction (STEP `FACE_BOUND.orientation`).
    pub orientation: bool,
    /// Whether the file marked it as the outer bound.
    pub outer: bool,
}

/// A face: a region of a surface bounded by loops.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// Support surface.
    pub surface: SurfaceId,
    /// Whether the face normal agrees with the surface normal (STEP `same_sense`).
    pub same_sense: bool,
    /// Boundaries; may be empty for an unbounded surface face (then the surface's own domain).
    pub loops: Vec<Loop>,
    /// STEP instance id of the face, for messages and picking reports.
    pub step_id: u64,
}

/// A connected set of faces (`CLOSED_SHELL`, `OPEN_SHELL`, `CONNECTED_FACE_SET`).
#[derive(Clone, Debug, PartialEq)]
pub struct Shell {
    /// Faces with the orientation the shell uses them in (`false`: reversed, from an
    /// `ORIENTED_FACE` or `ORIENTED_CLOSED_SHELL`).
    pub faces: Vec<(FaceId, bool)>,
    /// Whether the file declared it closed.
    pub closed: bool,
    /// STEP instance id.
    pub step_id: u64,
}

/// A solid: an outer shell and possibly voids (`BREP_WITH_VOIDS`).
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// The outer boundary.
    pub outer: ShellId,
    /// Inner boundaries (cavities).
    pub voids: Vec<ShellId>,
    /// STEP instance id.
    pub step_id: u64,
}

impl Solid {
    /// Outer shell then voids.
    pub fn shells(&self) -> impl Iterator<Item = ShellId> + '_ {
        std::iter::once(self.outer).chain(self.voids.iter().copied())
    }
}

/// An edge curve used alone (wireframe geometry, `GEOMETRIC_CURVE_SET`).
#[derive(Clone, Debug, PartialEq)]
pub struct Wire {
    /// The curve.
    pub curve: CurveId,
    /// Parameter range, `None` for the curve's own domain.
    pub range: Option<(f64, f64)>,
}

/// Helper so callers can name a face with its orientation.
pub type OrientedFace = (FaceId, bool);
