//! Properties and measurements of picked entities, for an interactive viewer's properties
//! panel and measuring tools: exact figures from the B-Rep model, never from a tessellation.
//!
//! [`face_properties`] and [`edge_properties`] give what a panel shows (surface or curve type,
//! radii, axes, exact edge length); the viewer turns them into text. [`angle_between_faces`],
//! [`radius_of`] and [`distance`] are the measurements. Lengths are millimetres (the model's
//! unit) and angles radians.
//!
//! Nothing here panics on bad input: ids pointing outside the model's arenas give `None`.

mod properties;
pub mod recognise;
#[cfg(test)]
mod tests;

use std::f64::consts::PI;

use cadre_geom::curve::Curve;
use cadre_geom::{Curve3, Surface, Vec3};

pub use properties::{
    Axis, CurveKind, EdgeProperties, FaceProperties, Plane, SurfaceKind, edge_properties,
    face_plane, face_properties,
};

use crate::{Edge, EdgeId, Entity, Face, FaceId, LoopKind, Model, VertexId};

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

/// The radius of a cylindrical or spherical face (or an offset of one) or of a circular edge
/// — B-splines found to be one included ([`recognise`]); `None` for other entities and ids
/// outside the model.
pub fn radius_of(model: &Model, entity: impl Into<Entity>) -> Option<f64> {
    match entity.into() {
        Entity::Face(f) => face_properties(model, f)?.radius,
        Entity::Edge(e) => edge_properties(model, e)?.radius,
        Entity::Vertex(_) => None,
    }
}

/// An edge whose curve and vertex ids all lie in the model's arenas.
pub(crate) fn checked_edge(model: &Model, edge: EdgeId) -> Option<&Edge> {
    let e = model.edges.get(edge.index())?;
    let ok = e.curve.is_none_or(|c| c.index() < model.curves.len())
        && e.start.index() < model.vertices.len()
        && e.end.index() < model.vertices.len();
    ok.then_some(e)
}

/// The surface under any rectangular trims.
pub(crate) fn untrimmed(mut s: &Surface) -> &Surface {
    while let Surface::Trimmed { basis, .. } = s {
        s = basis;
    }
    s
}

/// The curve under any trims.
pub(crate) fn untrimmed_curve(mut c: &Curve3) -> &Curve3 {
    while let Curve::Trimmed { basis, .. } = c {
        c = basis;
    }
    c
}

/// A point and the surface normal (`∂S/∂u × ∂S/∂v`, unit) of a planar surface: a plane or an
/// offset of one.
pub(crate) fn planar(surface: &Surface) -> Option<(Vec3, Vec3)> {
    match untrimmed(surface) {
        Surface::Plane { frame } => Some((frame.origin, frame.z)),
        Surface::Offset { basis, distance } => planar(basis).map(|(o, n)| (o + n * *distance, n)),
        _ => None,
    }
}

/// +1 when the face's outward normal agrees with its surface's normal, −1 when not: the
/// face's `same_sense` composed with the orientation of the first shell that uses it.
pub(crate) fn outward_sign(model: &Model, id: FaceId, face: &Face) -> f64 {
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
