//! Properties and measurements of picked entities, for an interactive viewer's properties
//! panel and measuring tools: exact figures from the B-Rep model, never from a tessellation.
//!
//! The viewer picks faces, edges and vertices by their STEP instance id; a [`StepIndex`] built
//! once per model turns those back into ids. [`face_properties`] and [`edge_properties`] give
//! what a panel shows (surface or curve type, radii, axes, exact edge length), each with
//! [`rows`](FaceProperties::rows) of (label, value) text. [`angle_between_faces`],
//! [`radius_of`] and [`distance`] are the measurements. Lengths are millimetres (the model's
//! unit) and angles radians; the rows show angles in degrees.
//!
//! Nothing here panics on bad input: unknown ids and ids pointing outside the model's arenas
//! give `None`.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt;

use cadre_geom::curve::Curve;
use cadre_geom::{Accuracy, Curve3, Surface, Vec3};

use crate::{Body, Edge, EdgeId, Face, FaceId, LoopKind, Model, PartId, VertexId};

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

/// The kind of a face's support surface (a rectangular trim reports its basis).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceKind {
    /// A plane.
    Plane,
    /// A circular cylinder.
    Cylinder,
    /// A circular cone.
    Cone,
    /// A sphere.
    Sphere,
    /// A torus.
    Torus,
    /// A (rational) B-spline or Bézier surface.
    BSpline,
    /// A surface of revolution.
    Revolution,
    /// A surface of linear extrusion.
    Extrusion,
    /// An offset surface.
    Offset,
}

impl SurfaceKind {
    /// The kind of `surface`, looking through rectangular trims.
    pub fn of(surface: &Surface) -> Self {
        match untrimmed(surface) {
            Surface::Plane { .. } => SurfaceKind::Plane,
            Surface::Cylinder { .. } => SurfaceKind::Cylinder,
            Surface::Cone { .. } => SurfaceKind::Cone,
            Surface::Sphere { .. } => SurfaceKind::Sphere,
            Surface::Torus { .. } => SurfaceKind::Torus,
            Surface::BSpline(_) => SurfaceKind::BSpline,
            Surface::Revolution { .. } => SurfaceKind::Revolution,
            Surface::Extrusion { .. } => SurfaceKind::Extrusion,
            // `untrimmed` never returns a trim.
            Surface::Offset { .. } | Surface::Trimmed { .. } => SurfaceKind::Offset,
        }
    }

    /// The display name: "plane", "cylinder", "cone", "sphere", "torus", "B-spline surface",
    /// "surface of revolution", "extrusion", "offset".
    pub fn name(self) -> &'static str {
        match self {
            SurfaceKind::Plane => "plane",
            SurfaceKind::Cylinder => "cylinder",
            SurfaceKind::Cone => "cone",
            SurfaceKind::Sphere => "sphere",
            SurfaceKind::Torus => "torus",
            SurfaceKind::BSpline => "B-spline surface",
            SurfaceKind::Revolution => "surface of revolution",
            SurfaceKind::Extrusion => "extrusion",
            SurfaceKind::Offset => "offset",
        }
    }
}

impl fmt::Display for SurfaceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A line in space: a point on it and a unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// A point on the axis.
    pub origin: Vec3,
    /// Unit direction.
    pub direction: Vec3,
}

/// A plane: a point on it and its unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane: the origin of the plane's placement (moved by the distance of
    /// an offset plane).
    pub origin: Vec3,
    /// Unit normal, oriented as the face's outward normal.
    pub normal: Vec3,
}

/// What a properties panel shows about a face. Fields that do not apply to the surface kind
/// are `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceProperties {
    /// The face.
    pub face: FaceId,
    /// Its STEP instance id (0 when made by the reader).
    pub step_id: u64,
    /// Support surface kind.
    pub kind: SurfaceKind,
    /// Whether the face's outward normal is opposite to the surface's own normal
    /// (`∂S/∂u × ∂S/∂v`): the face's `same_sense` is false, or its shell uses it reversed.
    pub reversed: bool,
    /// Radius of a cylinder or sphere (also of an offset of one).
    pub radius: Option<f64>,
    /// Semi-angle of a cone, radians.
    pub semi_angle: Option<f64>,
    /// Apex of a cone.
    pub apex: Option<Vec3>,
    /// Major radius of a torus.
    pub major_radius: Option<f64>,
    /// Minor radius of a torus.
    pub minor_radius: Option<f64>,
    /// Centre of a sphere or torus.
    pub centre: Option<Vec3>,
    /// Axis of a cylinder, cone, sphere, torus or surface of revolution.
    pub axis: Option<Axis>,
    /// Plane of a planar face (a plane or an offset of one), normal pointing outward.
    pub plane: Option<Plane>,
    /// Extrusion vector of a surface of linear extrusion.
    pub direction: Option<Vec3>,
    /// Signed distance of an offset surface from its basis.
    pub offset: Option<f64>,
}

impl FaceProperties {
    /// The properties as (label, value) rows for display; lengths in mm, angles in degrees.
    pub fn rows(&self) -> Vec<(String, String)> {
        let mut rows = Rows::default();
        rows.push("Type", self.kind.name().to_string());
        rows.push("STEP id", format!("#{}", self.step_id));
        if let Some(r) = self.radius {
            rows.push("Radius", mm(r));
            rows.push("Diameter", mm(2.0 * r));
        }
        if let Some(a) = self.semi_angle {
            rows.push("Semi-angle", deg(a));
        }
        if let Some(p) = self.apex {
            rows.push("Apex", point(p));
        }
        if let Some(r) = self.major_radius {
            rows.push("Major radius", mm(r));
        }
        if let Some(r) = self.minor_radius {
            rows.push("Minor radius", mm(r));
        }
        if let Some(c) = self.centre {
            rows.push("Centre", point(c));
        }
        if let Some(a) = self.axis {
            rows.push("Axis origin", point(a.origin));
            rows.push("Axis direction", vector(a.direction));
        }
        if let Some(p) = self.plane {
            rows.push("Plane origin", point(p.origin));
            rows.push("Normal", vector(p.normal));
        }
        if let Some(d) = self.direction {
            rows.push("Extrusion", vector(d));
        }
        if let Some(d) = self.offset {
            rows.push("Offset", mm(d));
        }
        rows.0
    }
}

/// The properties of face `face`; `None` for an id outside the model or a face whose surface
/// id is.
pub fn face_properties(model: &Model, face: FaceId) -> Option<FaceProperties> {
    let f = model.faces.get(face.index())?;
    let surface = model.surfaces.get(f.surface.index())?;
    let outward = outward_sign(model, face, f);
    let mut p = FaceProperties {
        face,
        step_id: f.step_id,
        kind: SurfaceKind::of(surface),
        reversed: outward < 0.0,
        radius: None,
        semi_angle: None,
        apex: None,
        major_radius: None,
        minor_radius: None,
        centre: None,
        axis: None,
        plane: None,
        direction: None,
        offset: None,
    };
    let frame_axis = |frame: &cadre_geom::Frame| Axis {
        origin: frame.origin,
        direction: frame.z,
    };
    match untrimmed(surface) {
        Surface::Cylinder { frame, radius } => {
            p.radius = Some(*radius);
            p.axis = Some(frame_axis(frame));
        }
        Surface::Cone {
            frame,
            radius,
            semi_angle,
        } => {
            p.semi_angle = Some(*semi_angle);
            let tan = semi_angle.tan();
            if tan.is_finite() && tan.abs() > 1e-300 {
                p.apex = Some(frame.origin - frame.z * (radius / tan));
            }
            p.axis = Some(frame_axis(frame));
        }
        Surface::Sphere { frame, radius } => {
            p.radius = Some(*radius);
            p.centre = Some(frame.origin);
            p.axis = Some(frame_axis(frame));
        }
        Surface::Torus {
            frame,
            major_radius,
            minor_radius,
        } => {
            p.major_radius = Some(*major_radius);
            p.minor_radius = Some(*minor_radius);
            p.centre = Some(frame.origin);
            p.axis = Some(frame_axis(frame));
        }
        Surface::Revolution {
            axis_origin,
            axis_direction,
            ..
        } => {
            p.axis = axis_direction.try_normalize().map(|direction| Axis {
                origin: *axis_origin,
                direction,
            });
        }
        Surface::Extrusion { direction, .. } => p.direction = Some(*direction),
        Surface::Offset { basis, distance } => {
            p.offset = Some(*distance);
            // An offset of a cylinder or sphere is one, of radius r + d (the surface normal
            // points away from the axis or centre).
            if let Surface::Cylinder { radius, .. } | Surface::Sphere { radius, .. } =
                untrimmed(basis)
            {
                p.radius = Some(radius + distance).filter(|r| *r > 0.0);
            }
        }
        Surface::Plane { .. } | Surface::BSpline(_) | Surface::Trimmed { .. } => {}
    }
    p.plane = planar(surface).map(|(origin, normal)| Plane {
        origin,
        normal: normal * outward,
    });
    Some(p)
}

/// The kind of an edge's curve (a trimmed curve reports its basis).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CurveKind {
    /// A straight line.
    Line,
    /// A circle or circular arc.
    Circle,
    /// An ellipse or elliptic arc.
    Ellipse,
    /// A parabola.
    Parabola,
    /// A hyperbola.
    Hyperbola,
    /// A polyline.
    Polyline,
    /// A (rational) B-spline or Bézier curve.
    BSpline,
    /// A composite curve.
    Composite,
    /// An offset curve.
    Offset,
    /// No curve: a degenerate edge (a sphere's pole, a cone's apex).
    Degenerate,
}

impl CurveKind {
    /// The kind of `curve`, looking through trims.
    pub fn of(curve: &Curve3) -> Self {
        match untrimmed_curve(curve) {
            Curve::Line { .. } => CurveKind::Line,
            Curve::Circle { .. } => CurveKind::Circle,
            Curve::Ellipse { .. } => CurveKind::Ellipse,
            Curve::Parabola { .. } => CurveKind::Parabola,
            Curve::Hyperbola { .. } => CurveKind::Hyperbola,
            Curve::Polyline(_) => CurveKind::Polyline,
            Curve::BSpline(_) => CurveKind::BSpline,
            // `untrimmed_curve` never returns a trim.
            Curve::Composite(_) | Curve::Trimmed { .. } => CurveKind::Composite,
            Curve::Offset { .. } => CurveKind::Offset,
        }
    }

    /// The display name: "line", "circle", "ellipse", "parabola", "hyperbola", "polyline",
    /// "B-spline curve", "composite curve", "offset curve", "degenerate".
    pub fn name(self) -> &'static str {
        match self {
            CurveKind::Line => "line",
            CurveKind::Circle => "circle",
            CurveKind::Ellipse => "ellipse",
            CurveKind::Parabola => "parabola",
            CurveKind::Hyperbola => "hyperbola",
            CurveKind::Polyline => "polyline",
            CurveKind::BSpline => "B-spline curve",
            CurveKind::Composite => "composite curve",
            CurveKind::Offset => "offset curve",
            CurveKind::Degenerate => "degenerate",
        }
    }
}

impl fmt::Display for CurveKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a properties panel shows about an edge. Fields that do not apply to the curve kind
/// are `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeProperties {
    /// The edge.
    pub edge: EdgeId,
    /// Its STEP instance id (0 when made by the reader).
    pub step_id: u64,
    /// Curve kind.
    pub kind: CurveKind,
    /// Exact length ([`curve_length`] over the edge's parameter range); 0 for a degenerate
    /// edge, `None` when the vertices cannot be placed on the curve or it does not evaluate.
    pub length: Option<f64>,
    /// Start vertex position (the edge's own orientation).
    pub start: Vec3,
    /// End vertex position.
    pub end: Vec3,
    /// Whether the edge starts and ends at one vertex.
    pub closed: bool,
    /// Parameter interval on the curve, increasing ([`crate::bounds::edge_range`]).
    pub range: Option<(f64, f64)>,
    /// Radius of a circle.
    pub radius: Option<f64>,
    /// Centre of a circle or ellipse.
    pub centre: Option<Vec3>,
    /// Axis of a circle or ellipse (through the centre, normal to its plane).
    pub axis: Option<Axis>,
    /// Angle swept by a circular or elliptic arc (its parameter range), radians.
    pub arc_angle: Option<f64>,
    /// Semi-axes (along x, along y) of an ellipse.
    pub semi_axes: Option<(f64, f64)>,
    /// Unit direction of a line, in the edge's orientation.
    pub direction: Option<Vec3>,
}

impl EdgeProperties {
    /// The properties as (label, value) rows for display; lengths in mm, angles in degrees.
    pub fn rows(&self) -> Vec<(String, String)> {
        let mut rows = Rows::default();
        rows.push("Type", self.kind.name().to_string());
        rows.push("STEP id", format!("#{}", self.step_id));
        rows.push("Length", self.length.map_or_else(|| "—".to_string(), mm));
        rows.push("Start", point(self.start));
        rows.push("End", point(self.end));
        if let Some(r) = self.radius {
            rows.push("Radius", mm(r));
            rows.push("Diameter", mm(2.0 * r));
        }
        if let Some((a, b)) = self.semi_axes {
            rows.push("Semi-axes", format!("{} × {} mm", num(a), num(b)));
        }
        if let Some(c) = self.centre {
            rows.push("Centre", point(c));
        }
        if let Some(a) = self.axis {
            rows.push("Axis", vector(a.direction));
        }
        if let Some(a) = self.arc_angle {
            rows.push("Arc angle", deg(a));
        }
        if let Some(d) = self.direction {
            rows.push("Direction", vector(d));
        }
        rows.0
    }
}

/// The properties of edge `edge`; `None` for an id outside the model or an edge whose curve
/// or vertex ids are.
pub fn edge_properties(model: &Model, edge: EdgeId) -> Option<EdgeProperties> {
    let e = checked_edge(model, edge)?;
    let start = model.vertices[e.start.index()].point;
    let end = model.vertices[e.end.index()].point;
    let mut p = EdgeProperties {
        edge,
        step_id: e.step_id,
        kind: CurveKind::Degenerate,
        length: None,
        start,
        end,
        closed: e.start == e.end,
        range: None,
        radius: None,
        centre: None,
        axis: None,
        arc_angle: None,
        semi_axes: None,
        direction: None,
    };
    let Some(curve) = e.curve.map(|c| &model.curves[c.index()]) else {
        p.length = Some(0.0);
        return Some(p);
    };
    p.kind = CurveKind::of(curve);
    p.range = crate::bounds::edge_range(model, e, Accuracy::default());
    p.length = p.range.and_then(|(t0, t1)| curve_length(curve, t0, t1));
    let sense = if e.same_sense { 1.0 } else { -1.0 };
    let plane_axis = |frame: &cadre_geom::curve::CurveFrame<Vec3>| {
        frame
            .x
            .cross(frame.y)
            .try_normalize()
            .map(|direction| Axis {
                origin: frame.origin,
                direction,
            })
    };
    let arc = p.range.map(|(t0, t1)| t1 - t0);
    match untrimmed_curve(curve) {
        Curve::Line { direction, .. } => p.direction = direction.try_normalize().map(|d| d * sense),
        Curve::Circle { frame, radius } => {
            p.radius = Some(*radius);
            p.centre = Some(frame.origin);
            p.axis = plane_axis(frame);
            p.arc_angle = arc;
        }
        Curve::Ellipse { frame, a, b } => {
            p.semi_axes = Some((*a, *b));
            p.centre = Some(frame.origin);
            p.axis = plane_axis(frame);
            p.arc_angle = arc;
        }
        _ => {}
    }
    Some(p)
}

/// The length of `curve` between parameters `t0` and `t1` (in either order): adaptive
/// Gauss–Legendre integration (10 points, each interval compared with its two halves) of
/// `|C'(t)|`, split first where the derivative may jump (B-spline knots, polyline and composite
/// joints), to about 1e-9 relative. Recursion depth and total work are bounded; a curve that
/// needs more gets the best estimate reached.
///
/// `None` for non-finite parameters or a curve that does not evaluate finitely there.
pub fn curve_length(curve: &Curve3, t0: f64, t1: f64) -> Option<f64> {
    if !t0.is_finite() || !t1.is_finite() {
        return None;
    }
    let (a, b) = (t0.min(t1), t0.max(t1));
    if a == b {
        return Some(0.0);
    }
    let mut cuts = vec![a, b];
    breakpoints(curve, a, b, &mut cuts, 0);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let speed = |t: f64| curve.derivs(t).d1.length();
    let pieces: Vec<(f64, f64, f64)> = cuts
        .windows(2)
        .map(|w| (w[0], w[1], gauss_legendre(&speed, w[0], w[1])))
        .collect();
    let estimate: f64 = pieces.iter().map(|p| p.2).sum();
    if !estimate.is_finite() {
        return None;
    }
    // A tenth of the target: the two-halves estimate is far better than the one it checks.
    let tol = 1e-10 * estimate.abs().max(f64::MIN_POSITIVE);
    let mut budget = MAX_SPLITS;
    let total: f64 = pieces
        .iter()
        .map(|&(lo, hi, whole)| {
            let share = tol * (hi - lo) / (b - a);
            adapt(&speed, lo, hi, whole, share, MAX_DEPTH, &mut budget)
        })
        .sum();
    total.is_finite().then_some(total)
}

/// Deepest bisection of one interval in [`curve_length`].
const MAX_DEPTH: u32 = 30;
/// Most bisections in one [`curve_length`] (each costs 20 derivative evaluations).
const MAX_SPLITS: usize = 20_000;
/// Most breakpoints collected from knots and joints.
const MAX_BREAKPOINTS: usize = 1_000_000;

/// Abscissae and weights of the 10-point Gauss–Legendre rule on [−1, 1] (positive half).
const GL_X: [f64; 5] = [
    0.148_874_338_981_631_21,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL_W: [f64; 5] = [
    0.295_524_224_714_752_87,
    0.269_266_719_309_996_36,
    0.219_086_362_515_982_04,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_14,
];

/// `∫ f` over `[a, b]` by the 10-point Gauss–Legendre rule.
fn gauss_legendre(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    h * GL_X
        .iter()
        .zip(GL_W)
        .map(|(x, w)| w * (f(m - h * x) + f(m + h * x)))
        .sum::<f64>()
}

/// Adaptive refinement of `whole ≈ ∫ f` over `[a, b]` to `tol`.
fn adapt(
    f: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
    budget: &mut usize,
) -> f64 {
    let m = 0.5 * (a + b);
    if depth == 0 || *budget == 0 || m <= a || m >= b {
        return whole;
    }
    *budget -= 1;
    let left = gauss_legendre(f, a, m);
    let right = gauss_legendre(f, m, b);
    let halves = left + right;
    let err = (halves - whole).abs();
    // A curve that stops evaluating (NaN) ends the refinement there.
    if err <= tol || err.is_nan() {
        return halves;
    }
    adapt(f, a, m, left, 0.5 * tol, depth - 1, budget)
        + adapt(f, m, b, right, 0.5 * tol, depth - 1, budget)
}

/// Parameters strictly inside `(a, b)` where `|C'|` may be discontinuous.
fn breakpoints(curve: &Curve3, a: f64, b: f64, out: &mut Vec<f64>, depth: u32) {
    if depth > 16 || out.len() >= MAX_BREAKPOINTS {
        return;
    }
    let mut push = |t: f64| {
        if t > a && t < b && out.len() < MAX_BREAKPOINTS {
            out.push(t);
        }
    };
    match curve {
        Curve::BSpline(s) => {
            // `domain` is `None` for a malformed spline, which then has no knots to trust.
            let Some((d0, d1)) = curve.domain() else {
                return;
            };
            let (shifts, period) = match curve.period().filter(|p| *p > 0.0) {
                Some(p) if (b - a) / p < 1e3 => (
                    ((a - d0) / p).floor() as i64..=((b - d0) / p).ceil() as i64,
                    p,
                ),
                _ => (0..=0, 0.0),
            };
            for k in shifts {
                let shift = k as f64 * period;
                let mut last = f64::NAN;
                for &knot in &s.knots {
                    if knot != last && (d0..=d1).contains(&knot) {
                        push(knot + shift);
                    }
                    last = knot;
                }
            }
        }
        Curve::Polyline(_) | Curve::Composite(_) => {
            // Counted, not stepped: `t + 1` may round back to `t` far from 0.
            let first = a.floor() + 1.0;
            let count = ((b - first).ceil().max(0.0) as usize).min(MAX_BREAKPOINTS);
            for i in 0..count {
                push(first + i as f64);
            }
        }
        Curve::Trimmed { basis, .. } | Curve::Offset { basis, .. } => {
            breakpoints(basis, a, b, out, depth + 1)
        }
        _ => {}
    }
}

/// The distance between two points.
pub fn distance(a: Vec3, b: Vec3) -> f64 {
    (b - a).length()
}

/// The distance between two vertices; `None` for an id outside the model.
pub fn vertex_distance(model: &Model, a: VertexId, b: VertexId) -> Option<f64> {
    let a = model.vertices.get(a.index())?.point;
    let b = model.vertices.get(b.index())?.point;
    Some(distance(a, b))
}

/// The angle between two planar faces.
///
/// `between_normals` is the angle between their outward normals (0 for parallel faces facing
/// the same way, π for opposite ones); `between_planes` is the angle between the planes
/// themselves, in `[0, π/2]`. Where the faces share an edge, `interior` is the dihedral angle
/// measured through the material of the solid: π − `between_normals` at a convex edge (90° on
/// a box), π + `between_normals` at a concave one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceAngle {
    /// Angle between the outward normals, radians in `[0, π]`.
    pub between_normals: f64,
    /// Angle between the planes, radians in `[0, π/2]`.
    pub between_planes: f64,
    /// Dihedral angle through the material at a shared edge, radians in `(0, 2π)`; `None` when
    /// the faces share no straight edge.
    pub interior: Option<f64>,
    /// Outward unit normal of the first face.
    pub normal_a: Vec3,
    /// Outward unit normal of the second face.
    pub normal_b: Vec3,
    /// The edge the faces share, if any.
    pub shared_edge: Option<EdgeId>,
    /// Distance between the planes when they are parallel (within 1e-9 rad).
    pub distance: Option<f64>,
}

/// The angle between planar faces `a` and `b` (see [`FaceAngle`]); `None` when either is not
/// planar or not in the model.
///
/// Outward normals are the surface normals turned by the face's `same_sense` and by the
/// orientation of the first shell that uses the face.
pub fn angle_between_faces(model: &Model, a: FaceId, b: FaceId) -> Option<FaceAngle> {
    let pa = face_properties(model, a)?.plane?;
    let pb = face_properties(model, b)?.plane?;
    let (na, nb) = (pa.normal, pb.normal);
    let theta = na.cross(nb).length().atan2(na.dot(nb));
    let between_planes = theta.min(PI - theta);
    let parallel = between_planes <= 1e-9;
    let shared = if a == b {
        None
    } else {
        shared_edge(model, a, b)
    };
    let interior = shared.and_then(|(_, d)| {
        if theta <= 1e-12 {
            return Some(PI);
        }
        let side = na.cross(nb).dot(d);
        (side != 0.0).then_some(if side > 0.0 { PI - theta } else { PI + theta })
    });
    Some(FaceAngle {
        between_normals: theta,
        between_planes,
        interior,
        normal_a: na,
        normal_b: nb,
        shared_edge: shared.map(|(e, _)| e),
        distance: parallel.then(|| (pb.origin - pa.origin).dot(na).abs()),
    })
}

/// The radius of a cylindrical or spherical face (or an offset of one) or of a circular edge;
/// `None` for other entities and ids outside the model.
pub fn radius_of(model: &Model, entity: impl Into<Entity>) -> Option<f64> {
    match entity.into() {
        Entity::Face(f) => face_properties(model, f)?.radius,
        Entity::Edge(e) => {
            let e = model.edges.get(e.index())?;
            match untrimmed_curve(model.curves.get(e.curve?.index())?) {
                Curve::Circle { radius, .. } => Some(*radius),
                _ => None,
            }
        }
        Entity::Vertex(_) => None,
    }
}

/// An edge whose curve and vertex ids all lie in the model's arenas.
fn checked_edge(model: &Model, edge: EdgeId) -> Option<&Edge> {
    let e = model.edges.get(edge.index())?;
    let ok = e.curve.is_none_or(|c| c.index() < model.curves.len())
        && e.start.index() < model.vertices.len()
        && e.end.index() < model.vertices.len();
    ok.then_some(e)
}

/// The surface under any rectangular trims.
fn untrimmed(mut s: &Surface) -> &Surface {
    while let Surface::Trimmed { basis, .. } = s {
        s = basis;
    }
    s
}

/// The curve under any trims.
fn untrimmed_curve(mut c: &Curve3) -> &Curve3 {
    while let Curve::Trimmed { basis, .. } = c {
        c = basis;
    }
    c
}

/// A point and the surface normal (`∂S/∂u × ∂S/∂v`, unit) of a planar surface: a plane or an
/// offset of one.
fn planar(surface: &Surface) -> Option<(Vec3, Vec3)> {
    match untrimmed(surface) {
        Surface::Plane { frame } => Some((frame.origin, frame.z)),
        Surface::Offset { basis, distance } => planar(basis).map(|(o, n)| (o + n * *distance, n)),
        _ => None,
    }
}

/// +1 when the face's outward normal agrees with its surface's normal, −1 when not: the
/// face's `same_sense` composed with the orientation of the first shell that uses it.
fn outward_sign(model: &Model, id: FaceId, face: &Face) -> f64 {
    let in_shell = model
        .shells
        .iter()
        .find_map(|s| s.faces.iter().find(|(f, _)| *f == id).map(|&(_, o)| o))
        .unwrap_or(true);
    if face.same_sense == in_shell {
        1.0
    } else {
        -1.0
    }
}

/// An edge bounding both faces, with its direction as face `a` uses it once `a` is oriented
/// outward (the face lies to its left seen from outside): only edges whose end points differ.
fn shared_edge(model: &Model, a: FaceId, b: FaceId) -> Option<(EdgeId, Vec3)> {
    let fa = model.faces.get(a.index())?;
    let fb = model.faces.get(b.index())?;
    let edges_of = |f: &Face| -> Vec<EdgeId> {
        f.loops
            .iter()
            .filter_map(|l| match &l.kind {
                LoopKind::Edges(es) => Some(es.iter().map(|oe| oe.edge)),
                _ => None,
            })
            .flatten()
            .collect()
    };
    let in_b = edges_of(fb);
    // The loops run counter-clockwise about the face's topological normal (the surface
    // normal turned by `same_sense`); a reversed use in the shell turns both.
    let shell_sign = outward_sign(model, a, fa) * if fa.same_sense { 1.0 } else { -1.0 };
    for l in &fa.loops {
        let LoopKind::Edges(es) = &l.kind else {
            continue;
        };
        for oe in es.iter().filter(|oe| in_b.contains(&oe.edge)) {
            let Some(e) = checked_edge(model, oe.edge) else {
                continue;
            };
            let d = model.vertices[e.end.index()].point - model.vertices[e.start.index()].point;
            let Some(d) = d.try_normalize() else {
                continue;
            };
            let used = if oe.forward == l.orientation {
                1.0
            } else {
                -1.0
            };
            return Some((oe.edge, d * used * shell_sign));
        }
    }
    None
}

/// Display rows under construction.
#[derive(Default)]
struct Rows(Vec<(String, String)>);

impl Rows {
    fn push(&mut self, label: &str, value: String) {
        self.0.push((label.to_string(), value));
    }
}

/// A number with up to six decimals, trailing zeros dropped.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        &s
    };
    if s == "-0" { "0".into() } else { s.into() }
}

fn mm(x: f64) -> String {
    format!("{} mm", num(x))
}

fn deg(radians: f64) -> String {
    format!("{}°", num(radians.to_degrees()))
}

fn point(p: Vec3) -> String {
    format!("({}, {}, {}) mm", num(p.x), num(p.y), num(p.z))
}

fn vector(v: Vec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CurveId, Loop, OrientedEdge, Part, Shell, ShellId, SurfaceId, Vertex};
    use cadre_geom::curve::CurveFrame;
    use cadre_geom::{BSplineCurve, Frame};
    use std::f64::consts::{FRAC_PI_2, TAU};

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    fn vertex(model: &mut Model, p: Vec3, step_id: u64) -> VertexId {
        model.vertices.push(Vertex { point: p, step_id });
        VertexId(model.vertices.len() as u32 - 1)
    }

    fn edge(model: &mut Model, curve: Curve3, a: VertexId, b: VertexId, step: u64) -> EdgeId {
        model.curves.push(curve);
        model.edges.push(Edge {
            curve: Some(CurveId(model.curves.len() as u32 - 1)),
            start: a,
            end: b,
            same_sense: true,
            pcurves: Vec::new(),
            step_id: step,
        });
        EdgeId(model.edges.len() as u32 - 1)
    }

    fn line(a: Vec3, b: Vec3) -> Curve3 {
        Curve::Line {
            origin: a,
            direction: b - a,
        }
    }

    fn circle(r: f64) -> Curve3 {
        Curve::Circle {
            frame: Frame::WORLD.into(),
            radius: r,
        }
    }

    #[test]
    fn gauss_legendre_is_exact_to_degree_19() {
        assert!(close(GL_W.iter().sum::<f64>() * 2.0, 2.0, 1e-15));
        let i = gauss_legendre(&|x: f64| x.powi(18) + x.powi(19), -1.0, 1.0);
        assert!(close(i, 2.0 / 19.0, 1e-13), "{i}");
        let i = gauss_legendre(&|x: f64| x.powi(6), 0.0, 2.0);
        assert!(close(i, 128.0 / 7.0, 1e-13), "{i}");
    }

    #[test]
    fn lengths_of_analytic_curves() {
        let c = circle(3.0);
        assert!(close(curve_length(&c, 0.0, TAU).unwrap(), 6.0 * PI, 1e-14));
        assert!(close(curve_length(&c, 2.0, 0.5).unwrap(), 4.5, 1e-14));
        let l = line(Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0));
        assert!(close(curve_length(&l, -1.0, 1.0).unwrap(), 10.0, 1e-14));
        assert_eq!(curve_length(&l, 1.0, 1.0), Some(0.0));
        assert_eq!(curve_length(&l, f64::NAN, 1.0), None);
        // Ellipse a = 2, b = 1: 4·a·E(e²) with E the complete elliptic integral of the second
        // kind, E(0.75) = 1.2110560275684595.
        let e = Curve::Ellipse {
            frame: Frame::WORLD.into(),
            a: 2.0,
            b: 1.0,
        };
        let len = curve_length(&e, 0.0, TAU).unwrap();
        assert!(close(len, 8.0 * 1.211_056_027_568_459_5, 1e-12), "{len}");
    }

    #[test]
    fn polyline_and_kinked_bspline_lengths_split_at_joints() {
        let p = Curve::Polyline(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 2.0, 0.0)]);
        assert!(close(curve_length(&p, 0.0, 2.0).unwrap(), 3.0, 1e-14));
        assert!(close(curve_length(&p, 0.5, 1.5).unwrap(), 1.5, 1e-14));
        // Degree 1 B-spline with a kink at knot 0.3: two straight pieces.
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
        ];
        let s = BSplineCurve::try_new(1, vec![0.0, 0.0, 0.3, 1.0, 1.0], pts, None).unwrap();
        let len = curve_length(&Curve::BSpline(s), 0.0, 1.0).unwrap();
        assert!(close(len, 7.0, 1e-14), "{len}");
    }

    #[test]
    fn cubic_bspline_length_matches_a_fine_polyline() {
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 1.0),
            Vec3::new(4.0, 1.0, 0.0),
            Vec3::new(6.0, 0.0, 2.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
        let c = Curve::BSpline(BSplineCurve::try_new(3, knots, pts, None).unwrap());
        let len = curve_length(&c, 0.0, 1.0).unwrap();
        let n = 200_000;
        let poly: f64 = (0..n)
            .map(|i| (c.eval((i + 1) as f64 / n as f64) - c.eval(i as f64 / n as f64)).length())
            .sum();
        // A polyline of n chords falls short by O(1/n²).
        assert!(len > poly && (len - poly) / len < 1e-8, "{len} vs {poly}");
    }

    /// A unit cube [0, 1]³ with its +x and +y faces (and the edge between them), written with
    /// the +y face reversed by `same_sense` and the +x face's plane normal pointing inward
    /// but the face reversed by its shell, to exercise both flips.
    fn two_faces_of_a_box() -> (Model, FaceId, FaceId, EdgeId) {
        let mut m = Model::default();
        let p = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let v0 = vertex(&mut m, p(1.0, 1.0, 0.0), 10);
        let v1 = vertex(&mut m, p(1.0, 1.0, 1.0), 11);
        let v2 = vertex(&mut m, p(1.0, 0.0, 1.0), 12);
        let v3 = vertex(&mut m, p(1.0, 0.0, 0.0), 13);
        let v4 = vertex(&mut m, p(0.0, 1.0, 1.0), 14);
        let v5 = vertex(&mut m, p(0.0, 1.0, 0.0), 15);
        let shared = edge(&mut m, line(p(1.0, 1.0, 0.0), p(1.0, 1.0, 1.0)), v0, v1, 20);
        let ex1 = edge(&mut m, line(p(1.0, 1.0, 1.0), p(1.0, 0.0, 1.0)), v1, v2, 21);
        let ex2 = edge(&mut m, line(p(1.0, 0.0, 1.0), p(1.0, 0.0, 0.0)), v2, v3, 22);
        let ex3 = edge(&mut m, line(p(1.0, 0.0, 0.0), p(1.0, 1.0, 0.0)), v3, v0, 23);
        let ey1 = edge(&mut m, line(p(1.0, 1.0, 1.0), p(0.0, 1.0, 1.0)), v1, v4, 24);
        let ey2 = edge(&mut m, line(p(0.0, 1.0, 1.0), p(0.0, 1.0, 0.0)), v4, v5, 25);
        let ey3 = edge(&mut m, line(p(0.0, 1.0, 0.0), p(1.0, 1.0, 0.0)), v5, v0, 26);
        // +x face: plane normal −x (inward), face same_sense true, used reversed by the shell.
        // Its loop runs counter-clockwise about −x: v0 → v3 → v2 → v1 → v0.
        let fwd = |edge, forward| OrientedEdge { edge, forward };
        m.surfaces.push(Surface::Plane {
            frame: Frame::from_axis(p(1.0, 0.0, 0.0), -Vec3::X, Some(Vec3::Y)).unwrap(),
        });
        m.faces.push(Face {
            surface: SurfaceId(0),
            same_sense: true,
            loops: vec![Loop {
                kind: LoopKind::Edges(vec![
                    fwd(ex3, false),
                    fwd(ex2, false),
                    fwd(ex1, false),
                    fwd(shared, false),
                ]),
                orientation: true,
                outer: true,
            }],
            step_id: 30,
        });
        // +y face: plane normal −y, same_sense false; loop counter-clockwise about +y:
        // v0 → v5 → v4 → v1 → v0.
        m.surfaces.push(Surface::Plane {
            frame: Frame::from_axis(p(0.0, 1.0, 0.0), -Vec3::Y, Some(Vec3::X)).unwrap(),
        });
        m.faces.push(Face {
            surface: SurfaceId(1),
            same_sense: false,
            loops: vec![Loop {
                kind: LoopKind::Edges(vec![
                    fwd(ey3, false),
                    fwd(ey2, false),
                    fwd(ey1, false),
                    fwd(shared, false),
                ]),
                orientation: true,
                outer: true,
            }],
            step_id: 31,
        });
        m.shells.push(Shell {
            faces: vec![(FaceId(0), false), (FaceId(1), true)],
            closed: false,
            step_id: 40,
        });
        m.parts.push(Part {
            name: "box".into(),
            bodies: vec![Body::Shell(ShellId(0))],
            ..Part::default()
        });
        (m, FaceId(0), FaceId(1), shared)
    }

    #[test]
    fn box_faces_meet_at_a_right_angle_with_outward_normals() {
        let (m, fx, fy, shared) = two_faces_of_a_box();
        let px = face_properties(&m, fx).unwrap();
        assert_eq!(px.kind, SurfaceKind::Plane);
        assert!(px.reversed);
        assert!((px.plane.unwrap().normal - Vec3::X).length() < 1e-15);
        let py = face_properties(&m, fy).unwrap();
        assert!(py.reversed);
        assert!((py.plane.unwrap().normal - Vec3::Y).length() < 1e-15);
        let a = angle_between_faces(&m, fx, fy).unwrap();
        assert!(close(a.between_normals, FRAC_PI_2, 1e-15));
        assert!(close(a.between_planes, FRAC_PI_2, 1e-15));
        assert!(close(a.interior.unwrap(), FRAC_PI_2, 1e-15));
        assert_eq!(a.shared_edge, Some(shared));
        assert_eq!(a.distance, None);
        let same = angle_between_faces(&m, fx, fx).unwrap();
        assert_eq!(same.between_normals, 0.0);
        assert_eq!(same.distance, Some(0.0));
        assert_eq!((same.interior, same.shared_edge), (None, None));
        // Edge rows.
        let e = edge_properties(&m, shared).unwrap();
        assert_eq!(e.kind, CurveKind::Line);
        assert!(close(e.length.unwrap(), 1.0, 1e-14));
        assert_eq!(e.direction, Some(Vec3::Z));
        assert!(e.rows().contains(&("Length".into(), "1 mm".into())));
    }

    #[test]
    fn concave_edge_reports_the_reflex_interior_angle() {
        let (mut m, fx, fy, _) = two_faces_of_a_box();
        // Flip both faces: the same planes bound the complement, so the edge is concave.
        m.shells[0].faces = vec![(FaceId(0), true), (FaceId(1), false)];
        let a = angle_between_faces(&m, fx, fy).unwrap();
        assert!(close(a.between_normals, FRAC_PI_2, 1e-15));
        assert!(close(a.interior.unwrap(), 1.5 * PI, 1e-15));
    }

    #[test]
    fn step_index_and_parts() {
        let (m, fx, fy, shared) = two_faces_of_a_box();
        let idx = StepIndex::new(&m);
        assert_eq!(idx.face(30), Some(fx));
        assert_eq!(idx.face(31), Some(fy));
        assert_eq!(idx.edge(20), Some(shared));
        assert_eq!(idx.vertex(12), Some(VertexId(2)));
        assert_eq!(idx.entity(20), Some(Entity::Edge(shared)));
        assert_eq!(idx.face(20), None);
        assert_eq!(idx.entity(9999), None);
        assert_eq!(idx.part_name(&m, fy), Some("box"));
        assert_eq!(idx.part_name(&m, shared), Some("box"));
        assert_eq!(idx.part_name(&m, VertexId(4)), Some("box"));
        assert_eq!(idx.part_of(FaceId(77)), None);
    }

    #[test]
    fn bad_ids_give_none() {
        let (mut m, fx, _, _) = two_faces_of_a_box();
        assert_eq!(face_properties(&m, FaceId(99)), None);
        assert_eq!(edge_properties(&m, EdgeId(99)), None);
        assert_eq!(radius_of(&m, FaceId(99)), None);
        assert_eq!(radius_of(&m, EdgeId(99)), None);
        assert_eq!(angle_between_faces(&m, fx, FaceId(99)), None);
        assert_eq!(vertex_distance(&m, VertexId(0), VertexId(99)), None);
        m.edges[0].curve = Some(CurveId(1000));
        assert_eq!(edge_properties(&m, EdgeId(0)), None);
        m.edges[1].end = VertexId(1000);
        assert_eq!(edge_properties(&m, EdgeId(1)), None);
        m.faces[0].surface = SurfaceId(1000);
        assert_eq!(face_properties(&m, fx), None);
        // StepIndex survives dangling ids too.
        m.parts[0].bodies.push(Body::Solid(crate::SolidId(5)));
        m.parts[0].bodies.push(Body::Face(FaceId(500)));
        let _ = StepIndex::new(&m);
    }

    #[test]
    fn analytic_face_properties() {
        let mut m = Model::default();
        let frame = Frame::from_axis(Vec3::new(1.0, 2.0, 3.0), Vec3::Z, None).unwrap();
        m.surfaces.push(Surface::Cylinder { frame, radius: 4.0 });
        m.surfaces.push(Surface::Cone {
            frame,
            radius: 2.0,
            semi_angle: PI / 4.0,
        });
        m.surfaces.push(Surface::Torus {
            frame,
            major_radius: 10.0,
            minor_radius: 3.0,
        });
        m.surfaces.push(Surface::Offset {
            basis: Box::new(Surface::Trimmed {
                basis: Box::new(Surface::Sphere { frame, radius: 5.0 }),
                u0: 0.0,
                u1: 1.0,
                v0: 0.0,
                v1: 1.0,
            }),
            distance: 1.5,
        });
        for i in 0..4 {
            m.faces.push(Face {
                surface: SurfaceId(i),
                same_sense: true,
                loops: Vec::new(),
                step_id: 100 + i as u64,
            });
        }
        let cyl = face_properties(&m, FaceId(0)).unwrap();
        assert_eq!((cyl.kind, cyl.radius), (SurfaceKind::Cylinder, Some(4.0)));
        assert_eq!(cyl.axis.unwrap().direction, Vec3::Z);
        assert_eq!(radius_of(&m, FaceId(0)), Some(4.0));
        let rows = cyl.rows();
        assert_eq!(rows[0], ("Type".into(), "cylinder".into()));
        assert!(rows.contains(&("Diameter".into(), "8 mm".into())));
        let cone = face_properties(&m, FaceId(1)).unwrap();
        assert!((cone.apex.unwrap() - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-12);
        assert!(cone.rows().contains(&("Semi-angle".into(), "45°".into())));
        assert_eq!(radius_of(&m, FaceId(1)), None);
        let torus = face_properties(&m, FaceId(2)).unwrap();
        assert_eq!(
            (torus.major_radius, torus.minor_radius),
            (Some(10.0), Some(3.0))
        );
        let off = face_properties(&m, FaceId(3)).unwrap();
        assert_eq!((off.kind, off.radius), (SurfaceKind::Offset, Some(6.5)));
    }

    #[test]
    fn circle_edges() {
        let mut m = Model::default();
        let frame = Frame::from_axis(Vec3::new(0.0, 0.0, 2.0), Vec3::Z, Some(Vec3::X)).unwrap();
        let c = Curve::Circle {
            frame: CurveFrame::from(frame),
            radius: 2.5,
        };
        let a = vertex(&mut m, Vec3::new(2.5, 0.0, 2.0), 1);
        let b = vertex(&mut m, Vec3::new(0.0, 2.5, 2.0), 2);
        let full = edge(&mut m, c.clone(), a, a, 3);
        let quarter = edge(&mut m, c, a, b, 4);
        let p = edge_properties(&m, full).unwrap();
        assert!(p.closed);
        assert!(close(p.length.unwrap(), 5.0 * PI, 1e-12));
        assert_eq!(p.radius, Some(2.5));
        assert_eq!(p.axis.unwrap().direction, Vec3::Z);
        assert!(close(p.arc_angle.unwrap(), TAU, 1e-15));
        let q = edge_properties(&m, quarter).unwrap();
        assert!(close(q.length.unwrap(), 1.25 * PI, 1e-12));
        assert!(q.rows().contains(&("Arc angle".into(), "90°".into())));
        assert_eq!(radius_of(&m, quarter), Some(2.5));
        assert_eq!(radius_of(&m, a), None);
        // A degenerate edge.
        m.edges.push(Edge {
            curve: None,
            start: a,
            end: a,
            same_sense: true,
            pcurves: Vec::new(),
            step_id: 5,
        });
        let d = edge_properties(&m, EdgeId(2)).unwrap();
        assert_eq!((d.kind, d.length), (CurveKind::Degenerate, Some(0.0)));
    }

    #[test]
    fn numbers_format_compactly() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.0000001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(f64::INFINITY), "inf");
        assert_eq!(distance(Vec3::ZERO, Vec3::new(3.0, 4.0, 12.0)), 13.0);
    }
}
