//! The minimum distance between two picked entities (faces, edges, vertices, of the same
//! part or of two), rather than between the points where they were clicked.
//!
//! Each entity is first a cloud of its tessellation's points placed in the world (a face's
//! mesh points, an edge's shared samples, a vertex); the nearest pair of the two clouds
//! (every pair for small clouds, else a stride of each and then the full neighbourhood of
//! the best coarse pair) is then refined by alternating projections onto the exact geometry:
//! a point onto the other entity's surface or curve, that foot back onto the first, until
//! the distance stops falling. A foot that leaves a face (outside its trim, tested in the
//! face mesh's (u, v) triangles) or an edge's range is not taken: the minimum then lies on
//! the face's boundary, and each edge of its loops is measured the same way (exactly, by
//! projection onto the edge's curve) — a plane's mesh has only its corners, so the nearest
//! samples alone can be far from the nearest point of a long edge.

use super::{DVec3, Pick};
use crate::document::Document;
use cadre_geom::{Accuracy, Vec3};

/// Most point pairs compared in one pass (beyond, each cloud is strided first).
const MAX_PAIRS: usize = 4_000_000;
/// Alternating-projection rounds.
const ROUNDS: usize = 32;

/// One entity's points in the world and how to project onto its exact geometry.
struct Entity<'d> {
    doc: &'d Document,
    /// World → part coordinates and back.
    world: glam::DAffine3,
    kind: Kind,
    points: Vec<DVec3>,
}

enum Kind {
    Face(cadre_brep::FaceId),
    Edge(cadre_brep::EdgeId),
    Vertex,
}

fn v(p: Vec3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

fn g(p: DVec3) -> Vec3 {
    Vec3::new(p.x, p.y, p.z)
}

impl<'d> Entity<'d> {
    fn new(doc: &'d Document, pick: Pick) -> Option<Entity<'d>> {
        let world = doc.instances.get(pick.instance() as usize)?.world;
        let (kind, local): (Kind, Vec<DVec3>) = match pick {
            Pick::Face { face, .. } => {
                let f = doc.face(face)?;
                let mesh = doc.mesh.faces.get(f.index())?.as_ref()?;
                (
                    Kind::Face(f),
                    mesh.points.iter().map(|p| v(p.xyz)).collect(),
                )
            }
            Pick::Edge { edge, .. } => {
                let e = doc.edge(edge)?;
                use cadre_brep::trim::EdgeSamples;
                let samples = doc.mesh.edges.samples(e);
                (Kind::Edge(e), samples.iter().map(|s| v(s.xyz)).collect())
            }
            Pick::Vertex { vertex, .. } => {
                let id = doc.vertex(vertex)?;
                (
                    Kind::Vertex,
                    vec![v(doc.model.vertices.get(id.index())?.point)],
                )
            }
            Pick::Part { .. } => return None,
        };
        let points: Vec<DVec3> = local.iter().map(|&p| world.transform_point3(p)).collect();
        (!points.is_empty()).then_some(Entity {
            doc,
            world,
            kind,
            points,
        })
    }

    /// The edges bounding a face, as entities of their own (none for an edge or a vertex).
    fn boundary(&self) -> Vec<Entity<'d>> {
        let Kind::Face(f) = self.kind else {
            return Vec::new();
        };
        let Some(face) = self.doc.model.faces.get(f.index()) else {
            return Vec::new();
        };
        let mut edges: Vec<cadre_brep::EdgeId> = face
            .loops
            .iter()
            .filter_map(|lp| match &lp.kind {
                cadre_brep::LoopKind::Edges(edges) => Some(edges.iter().map(|oe| oe.edge)),
                _ => None,
            })
            .flatten()
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges
            .into_iter()
            .filter_map(|e| {
                use cadre_brep::trim::EdgeSamples;
                let points: Vec<DVec3> = self
                    .doc
                    .mesh
                    .edges
                    .samples(e)
                    .iter()
                    .map(|s| self.world.transform_point3(v(s.xyz)))
                    .collect();
                (!points.is_empty()).then_some(Entity {
                    doc: self.doc,
                    world: self.world,
                    kind: Kind::Edge(e),
                    points,
                })
            })
            .collect()
    }

    /// The entity's point nearest `p` by its exact geometry, if the foot stays on it.
    fn foot(&self, p: DVec3) -> Option<DVec3> {
        let model = &self.doc.model;
        let local = g(self.world.inverse().transform_point3(p));
        let acc = Accuracy::default();
        let foot = match self.kind {
            Kind::Vertex => return self.points.first().copied(),
            Kind::Face(f) => {
                let face = model.faces.get(f.index())?;
                let surface = model.surfaces.get(face.surface.index())?;
                let (u, w) = surface.project(local, None, acc)?;
                if !self.inside_face(f, (u, w)) {
                    return None;
                }
                surface.eval(u, w)
            }
            Kind::Edge(e) => {
                let edge = model.edges.get(e.index())?;
                let curve = model.curves.get(edge.curve?.index())?;
                let (t0, t1) = model.edge_range(e, acc)?;
                let t = curve.project(local, None, acc)?;
                let (lo, hi) = (t0.min(t1), t0.max(t1));
                if t < lo - 1e-9 * (1.0 + lo.abs()) || t > hi + 1e-9 * (1.0 + hi.abs()) {
                    return None;
                }
                curve.eval(t)
            }
        };
        Some(self.world.transform_point3(v(foot)))
    }

    /// Whether (u, v) lies in one of the face mesh's (u, v) triangles.
    fn inside_face(&self, f: cadre_brep::FaceId, (u, w): (f64, f64)) -> bool {
        let Some(Some(mesh)) = self.doc.mesh.faces.get(f.index()) else {
            return false;
        };
        let q = glam::DVec2::new(u, w);
        mesh.triangles.iter().any(|t| {
            let [a, b, c] = t.map(|i| {
                let p = mesh.points[i as usize].uv;
                glam::DVec2::new(p.x, p.y)
            });
            let side = |p: glam::DVec2, q1: glam::DVec2, r: glam::DVec2| (q1 - p).perp_dot(r - p);
            let (d1, d2, d3) = (side(a, b, q), side(b, c, q), side(c, a, q));
            let neg = d1 < -1e-12 || d2 < -1e-12 || d3 < -1e-12;
            let pos = d1 > 1e-12 || d2 > 1e-12 || d3 > 1e-12;
            !(neg && pos)
        })
    }
}

/// The nearest pair of two clouds.
fn nearest_pair(a: &[DVec3], b: &[DVec3]) -> (usize, usize, f64) {
    let stride = |n: usize, m: usize| {
        let pairs = n.saturating_mul(m);
        if pairs <= MAX_PAIRS {
            1
        } else {
            ((pairs as f64 / MAX_PAIRS as f64).sqrt().ceil() as usize).max(1)
        }
    };
    let s = stride(a.len(), b.len());
    let mut best = (0, 0, f64::INFINITY);
    for (i, p) in a.iter().enumerate().step_by(s) {
        for (j, q) in b.iter().enumerate().step_by(s) {
            let d = p.distance_squared(*q);
            if d < best.2 {
                best = (i, j, d);
            }
        }
    }
    if s > 1 {
        // Every point of each cloud against the other's best point, twice over.
        for _ in 0..2 {
            let (i, j, _) = best;
            for (k, p) in a.iter().enumerate() {
                let d = p.distance_squared(b[j]);
                if d < best.2 {
                    best = (k, j, d);
                }
            }
            let i = if best.0 != i { best.0 } else { i };
            for (k, q) in b.iter().enumerate() {
                let d = a[i].distance_squared(*q);
                if d < best.2 {
                    best = (i, k, d);
                }
            }
        }
    }
    (best.0, best.1, best.2.sqrt())
}

/// The minimum distance between picked entities `a` and `b` and the two points that reach
/// it; `None` when either has no geometry to measure (a whole part, a face without mesh).
pub fn min_distance(doc: &Document, a: Pick, b: Pick) -> Option<(f64, DVec3, DVec3)> {
    let ea = Entity::new(doc, a)?;
    let eb = Entity::new(doc, b)?;
    let (mut best, left) = refine(&ea, &eb);
    if left {
        // The minimum is on a face's boundary: each of its edges against the other entity
        // (and against the other face's edges, where both are faces).
        let (ba, bb) = (ea.boundary(), eb.boundary());
        let mut closer = |found: (f64, DVec3, DVec3)| {
            if found.0 < best.0 {
                best = found;
            }
        };
        for edge in &ba {
            closer(refine(edge, &eb).0);
            for other in &bb {
                closer(refine(edge, other).0);
            }
        }
        for edge in &bb {
            closer(refine(&ea, edge).0);
        }
    }
    Some(best)
}

/// The nearest pair of `ea` and `eb`'s samples, refined by alternating projections; and
/// whether a projection left either entity (the minimum may then be on a face's boundary).
fn refine(ea: &Entity<'_>, eb: &Entity<'_>) -> ((f64, DVec3, DVec3), bool) {
    let (i, j, d) = nearest_pair(&ea.points, &eb.points);
    let (mut pa, mut pb, mut best) = (ea.points[i], eb.points[j], d);
    for _ in 0..ROUNDS {
        let Some(qb) = eb.foot(pa) else {
            return ((best, pa, pb), true);
        };
        let Some(qa) = ea.foot(qb) else {
            if pa.distance(qb) < best {
                pb = qb;
                best = pa.distance(qb);
            }
            return ((best, pa, pb), true);
        };
        let d = qa.distance(qb);
        if d >= best - 1e-12 * (1.0 + best) {
            if d < best {
                (pa, pb, best) = (qa, qb, d);
            }
            break;
        }
        (pa, pb, best) = (qa, qb, d);
    }
    ((best, pa, pb), false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The bundled PMI block: 60 × 40 × 10 mm, one instance.
    fn block() -> Document {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pmi/block-pmi.step");
        Document::load(&path, &|_| {}).expect("the example loads")
    }

    fn face(doc: &Document, step_id: u64) -> Pick {
        let k = doc
            .model
            .faces
            .iter()
            .position(|f| f.step_id == step_id)
            .expect("face");
        Pick::Face {
            instance: 0,
            face: k as u32 + 1,
        }
    }

    #[test]
    fn minimum_distances_between_faces_edges_and_vertices_are_exact() {
        let doc = block();
        let (left, right, top, bottom) = (
            face(&doc, 147),
            face(&doc, 157),
            face(&doc, 117),
            face(&doc, 107),
        );
        let d = |a, b| min_distance(&doc, a, b).expect("measurable").0;
        assert!((d(left, right) - 60.0).abs() < 1e-9, "{}", d(left, right));
        assert!((d(top, bottom) - 10.0).abs() < 1e-9, "{}", d(top, bottom));
        // Faces that touch are 0 apart.
        assert!(d(top, left).abs() < 1e-9);
        // The origin vertex against the top and the right faces.
        let origin = doc
            .model
            .vertices
            .iter()
            .position(|v| v.point == Vec3::ZERO)
            .expect("vertex at the origin");
        let vertex = Pick::Vertex {
            instance: 0,
            vertex: origin as u32 + 1,
        };
        assert!((d(vertex, top) - 10.0).abs() < 1e-9);
        assert!((d(vertex, right) - 60.0).abs() < 1e-9);
        // An edge of the top face against the bottom face.
        let edge = doc
            .model
            .edges
            .iter()
            .position(|e| {
                [e.start, e.end]
                    .iter()
                    .all(|v| doc.model.vertices[v.index()].point.z == 10.0)
            })
            .expect("a top edge");
        let edge = Pick::Edge {
            instance: 0,
            edge: edge as u32 + 1,
        };
        assert!((d(edge, bottom) - 10.0).abs() < 1e-9);
        // A whole part has no entity geometry: no minimum distance.
        assert!(min_distance(&doc, Pick::Part { instance: 0 }, top).is_none());
    }

    #[test]
    fn a_minimum_on_a_faces_boundary_is_exact() {
        // The pins of the bundled assembly: one along z at (20, 0, 0), one along y from
        // (0, 30, 0). The first pin's top vertex, (25, 0, 10), is nearest the second pin's
        // end cap (the disc of radius 5 about (0, 40, 0) in y = 40) at the disc's rim.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pin-assembly.step");
        let doc = Document::load(&path, &|_| {}).expect("the example loads");
        let instance = |along_y: bool| {
            doc.instances
                .iter()
                .position(|i| (i.world.transform_vector3(DVec3::Z).y > 0.5) == along_y)
                .expect("a pin") as u32
        };
        let (first, second) = (instance(false), instance(true));
        let top = doc
            .model
            .faces
            .iter()
            .position(|f| f.step_id == 67)
            .expect("the top face") as u32;
        let vertex = doc
            .model
            .vertices
            .iter()
            .position(|v| v.point == Vec3::new(5.0, 0.0, 10.0))
            .expect("the top vertex") as u32;
        let p = DVec3::new(25.0, 0.0, 10.0);
        let centre = DVec3::new(0.0, 40.0, 0.0);
        let across = DVec3::new(p.x, 0.0, p.z).normalize();
        let expected = p.distance(centre + 5.0 * across);
        let (d, a, b) = min_distance(
            &doc,
            Pick::Vertex {
                instance: first,
                vertex: vertex + 1,
            },
            Pick::Face {
                instance: second,
                face: top + 1,
            },
        )
        .expect("measurable");
        assert!(a.distance(p) < 1e-9, "{a}");
        assert!((d - expected).abs() < 1e-9, "{d} against {expected}");
        assert!(b.distance(centre + 5.0 * across) < 1e-9, "{b}");
    }

    #[test]
    fn the_distance_tool_measures_the_entities_not_the_clicks() {
        // Negative control: the clicked points are 59.2 mm apart, the faces 10 mm.
        let doc = block();
        let picked = |pick, point| super::super::Picked { pick, point };
        let a = picked(face(&doc, 117), DVec3::new(5.0, 5.0, 10.0));
        let b = picked(face(&doc, 107), DVec3::new(55.0, 35.0, 0.0));
        assert!((a.point.distance(b.point) - 3500f64.sqrt()).abs() < 1e-9);
        let m =
            super::super::measure(&doc, super::super::Tool::Distance, &[a, b]).expect("measured");
        assert!((m.value - 10.0).abs() < 1e-9, "{}", m.value);
        assert!(
            m.text.starts_with("Minimum distance 10.0000 mm"),
            "{}",
            m.text
        );
        assert_eq!(m.points.len(), 2);
    }
}
