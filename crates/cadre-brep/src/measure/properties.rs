//! What a properties panel shows about a face or an edge: the support surface's or curve's
//! kind and defining figures (radii, axes, apex, exact length), exact from the B-Rep.

use std::fmt;

use cadre_geom::curve::Curve;
use cadre_geom::{Accuracy, Curve3, Surface, Vec3};

use super::{checked_edge, outward_sign, planar, untrimmed, untrimmed_curve};
use crate::{EdgeId, FaceId, Model};

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

    /// Whether the surface is a quadric (plane, cylinder, cone, sphere): what a ray caster
    /// intersects in closed form.
    pub fn is_quadric(self) -> bool {
        matches!(
            self,
            SurfaceKind::Plane | SurfaceKind::Cylinder | SurfaceKind::Cone | SurfaceKind::Sphere
        )
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
    /// For a B-spline face: the shape its points were found to lie on (`cylinder`,
    /// `sphere`) and the farthest a sample lies from it ([`super::recognise`]); the radius,
    /// axis and centre are then that shape's.
    pub recognised: Option<(&'static str, f64)>,
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
        recognised: None,
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
        Surface::BSpline(_) => recognise_face(model, f, surface, &mut p),
        Surface::Plane { .. } | Surface::Trimmed { .. } => {}
    }
    p.plane = outward_plane(surface, outward);
    Some(p)
}

/// The plane of a planar face (a plane or an offset of one), its normal pointing outward;
/// `None` for another face or an id outside the model. What [`face_properties`] gives as
/// `plane`, without the rest (no B-spline recognition): cheap enough for every frame.
pub fn face_plane(model: &Model, face: FaceId) -> Option<Plane> {
    let f = model.faces.get(face.index())?;
    let surface = model.surfaces.get(f.surface.index())?;
    outward_plane(surface, outward_sign(model, face, f))
}

/// `surface`'s plane with its normal turned by `outward` (±1).
fn outward_plane(surface: &Surface, outward: f64) -> Option<Plane> {
    planar(surface).map(|(origin, normal)| Plane {
        origin,
        normal: normal * outward,
    })
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
    /// Exact length ([`Curve::arc_length`] at the default accuracy over the edge's parameter range); 0 for a degenerate
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
    /// For a B-spline edge: `circle` when its points were found on one, and the farthest a
    /// sample lies from it ([`super::recognise`]); the radius, centre, axis and arc angle
    /// are then the circle's.
    pub recognised: Option<(&'static str, f64)>,
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
        recognised: None,
    };
    let Some(curve) = e.curve.map(|c| &model.curves[c.index()]) else {
        p.length = Some(0.0);
        return Some(p);
    };
    p.kind = CurveKind::of(curve);
    p.range = crate::bounds::edge_range(model, e, Accuracy::default());
    p.length = p
        .range
        .and_then(|(t0, t1)| curve.arc_length(t0, t1, Accuracy::default()));
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
        Curve::BSpline(_) => recognise_edge(curve, &mut p),
        _ => {}
    }
    Some(p)
}

/// Samples a recognised shape is checked at, along an edge.
const EDGE_RECOGNITION_SAMPLES: usize = 33;
/// Samples a side, over a face's (u, v) box.
const FACE_RECOGNITION_SAMPLES: usize = 7;
/// A recognised shape holds within this share of the samples' extent (a rational
/// B-spline circle is exact to rounding; a fitted one is not a circle).
const RECOGNITION_REL: f64 = 1e-6;

/// The tolerance of a shape recognised through `points`: [`RECOGNITION_REL`] of their
/// extent.
fn recognition_tolerance(points: impl Iterator<Item = Vec3>) -> f64 {
    RECOGNITION_REL
        * cadre_geom::BoundingBox::from_points(points)
            .diagonal()
            .max(1e-3)
}

/// A B-spline edge whose samples lie on a circle gets the circle's radius, centre, axis
/// and arc angle.
fn recognise_edge(curve: &cadre_geom::Curve3, p: &mut EdgeProperties) {
    let Some((t0, t1)) = p.range else { return };
    let n = EDGE_RECOGNITION_SAMPLES;
    let points: Vec<Vec3> = (0..n)
        .map(|k| curve.eval(t0 + (t1 - t0) * k as f64 / (n - 1) as f64))
        .collect();
    if points.iter().any(|q| !q.is_finite()) {
        return;
    }
    let tolerance = recognition_tolerance(points.iter().copied());
    let Some(c) = super::recognise::circle_through(&points, tolerance) else {
        return;
    };
    // The angle swept: the turns between successive samples seen from the centre.
    let swept: f64 = points
        .windows(2)
        .map(|w| (w[0] - c.centre).angle_between(w[1] - c.centre))
        .sum();
    p.radius = Some(c.radius);
    p.centre = Some(c.centre);
    p.axis = Some(Axis {
        origin: c.centre,
        direction: c.normal,
    });
    p.arc_angle = Some(swept);
    p.recognised = Some(("circle", c.deviation));
}

/// A B-spline face whose samples (over its (u, v) box) lie on a cylinder or a sphere, their
/// normals radial, gets its radius and axis or centre.
fn recognise_face(model: &Model, face: &crate::Face, surface: &Surface, p: &mut FaceProperties) {
    let Some([u0, u1, v0, v1]) =
        crate::bounds::face_uv_box(model, face, surface, Accuracy::default())
    else {
        return;
    };
    let n = FACE_RECOGNITION_SAMPLES;
    let at = |k: usize, a: f64, b: f64| a + (b - a) * k as f64 / (n - 1) as f64;
    let mut samples = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (at(i, u0, u1), at(j, v0, v1));
            let Some(normal) = surface.normal(u, v) else {
                return;
            };
            let point = surface.eval(u, v);
            if !point.is_finite() {
                return;
            }
            samples.push((point, normal));
        }
    }
    let tolerance = recognition_tolerance(samples.iter().map(|s| s.0));
    use super::recognise::RoundSurface;
    match super::recognise::round_surface_through(&samples, tolerance) {
        Some(RoundSurface::Cylinder {
            axis,
            radius,
            deviation,
        }) => {
            p.radius = Some(radius);
            p.axis = Some(axis);
            p.recognised = Some(("cylinder", deviation));
        }
        Some(RoundSurface::Sphere {
            centre,
            radius,
            deviation,
        }) => {
            p.radius = Some(radius);
            p.centre = Some(centre);
            p.recognised = Some(("sphere", deviation));
        }
        None => {}
    }
}
