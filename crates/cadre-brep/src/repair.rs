//! Vertex repair: a vertex written away from the curves of its edges is moved to the point
//! where those curves meet.
//!
//! Edge ranges come from projecting the vertices onto the curves, so a vertex far from its
//! curves makes each edge stop at its own foot point: edges cross or stop short of each other
//! and trims fold. bug25013_25013face.stp has a vertex 0.09 mm from the pole where its two
//! meridian edges meet, on a sphere of radius 0.5: both meridians ran past the pole and the
//! face's mesh folded over it (area 0.8 % high, triangles 7.8× the deflection off the
//! sphere). Moving the vertex is what OCCT's shape healing does for such vertices
//! (`ShapeFix_Wire::FixVertexToEdge`-like); here it happens only when the curves have a common
//! point near the vertex, so sound files are untouched.

use rayon::prelude::*;

use crate::{CurveId, EdgeId, Model, VertexId};
use cadre_geom::{Accuracy, Vec3};

/// A vertex farther than this many times the accuracy from one of its curves is repaired.
const OFF_CURVE_FACTOR: f64 = 1e3;
/// How far (in multiples of the vertex's worst distance to its curves) the meeting point of
/// the curves may lie from the vertex: farther away, the curves meet somewhere unrelated.
const REACH: f64 = 3.0;
/// Rounds of alternating projection when looking for the curves' common point.
const MAX_ROUNDS: usize = 100;

/// One vertex moved by [`Model::snap_vertices_to_curves`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexMove {
    /// The vertex.
    pub vertex: VertexId,
    /// Where the file put it.
    pub from: Vec3,
    /// Where its curves meet.
    pub to: Vec3,
    /// Its distance from the farthest of its curves before the move.
    pub off_curve: f64,
}

impl Model {
    /// Moves every vertex that lies off the curves of its edges (by more than a thousand times
    /// `acc.distance`) to the point where those curves meet, when they meet within three times
    /// that distance of it. Returns the moves made, for reporting.
    pub fn snap_vertices_to_curves(&mut self, acc: Accuracy) -> Vec<VertexMove> {
        // How far each vertex lies from the ends of its edges' ranges: the ranges are the
        // vertices' projections, worked out (and cached) anyway, so sound files cost one
        // curve evaluation per edge end here.
        let mut off = vec![0.0f64; self.vertices.len()];
        let mut curves: Vec<Vec<CurveId>> = vec![Vec::new(); self.vertices.len()];
        for (i, edge) in self.edges.iter().enumerate() {
            let Some(c) = edge.curve else { continue };
            let range = self.edge_range(EdgeId(i as u32), acc);
            let curve = &self.curves[c.index()];
            for v in [edge.start, edge.end] {
                let p = self.vertices[v.index()].point;
                let d = range.map_or(0.0, |(t0, t1)| {
                    (curve.eval(t0) - p)
                        .length()
                        .min((curve.eval(t1) - p).length())
                });
                if d.is_finite() {
                    off[v.index()] = off[v.index()].max(d);
                }
                let list = &mut curves[v.index()];
                if !list.contains(&c) {
                    list.push(c);
                }
            }
        }
        let model = &*self;
        let moves: Vec<VertexMove> = curves
            .par_iter()
            .enumerate()
            .filter(|&(i, _)| off[i] > threshold(model.vertices[i].point, acc))
            .filter_map(|(i, cs)| {
                let from = model.vertices[i].point;
                let (to, off_curve) = meeting_point(model, cs, from, acc)?;
                Some(VertexMove {
                    vertex: VertexId(i as u32),
                    from,
                    to,
                    off_curve,
                })
            })
            .collect();
        if moves.is_empty() {
            return moves;
        }
        for m in &moves {
            self.vertices[m.vertex.index()].point = m.to;
        }
        let moved: std::collections::HashSet<VertexId> = moves.iter().map(|m| m.vertex).collect();
        for i in 0..self.edges.len() {
            let e = &self.edges[i];
            if moved.contains(&e.start) || moved.contains(&e.end) {
                self.refresh_edge_range(EdgeId(i as u32));
            }
        }
        moves
    }
}

/// Distance from its curves beyond which a vertex at `p` is repaired.
fn threshold(p: Vec3, acc: Accuracy) -> f64 {
    let scale = 1.0 + p.abs().max_element();
    OFF_CURVE_FACTOR * acc.distance.max(1e-12 * scale)
}

/// The point nearest `p` on the curve `c`, or `None` where projection fails.
fn foot(
    model: &Model,
    c: CurveId,
    p: Vec3,
    hint: Option<f64>,
    acc: Accuracy,
) -> Option<(f64, Vec3)> {
    let curve = &model.curves[c.index()];
    let t = curve.project(p, hint, acc)?;
    let q = curve.eval(t);
    q.is_finite().then_some((t, q))
}

/// Where the curves `cs` meet near `p`, with `p`'s distance from the farthest curve, when `p`
/// is off a curve by more than the repair threshold and the curves have a common point close
/// enough; `None` otherwise (nothing to repair, or nothing to repair it with).
fn meeting_point(model: &Model, cs: &[CurveId], p: Vec3, acc: Accuracy) -> Option<(Vec3, f64)> {
    if cs.is_empty() || !p.is_finite() {
        return None;
    }
    let scale = 1.0 + p.abs().max_element();
    let mut feet: Vec<(f64, Vec3)> = cs
        .iter()
        .map(|&c| foot(model, c, p, None, acc))
        .collect::<Option<_>>()?;
    let off = feet.iter().map(|f| (f.1 - p).length()).fold(0.0, f64::max);
    if off <= threshold(p, acc) {
        return None;
    }
    // Alternating projection: the mean of the feet moves towards the curves' common point
    // (linearly for curves crossing at an angle; curves that do not meet stall with a spread).
    let tight = acc.distance.max(1e-12 * scale) * 10.0;
    let mut q = p;
    for _ in 0..MAX_ROUNDS {
        let mean = feet.iter().fold(Vec3::ZERO, |s, f| s + f.1) / feet.len() as f64;
        let step = (mean - q).length();
        q = mean;
        let next: Option<Vec<(f64, Vec3)>> = cs
            .iter()
            .zip(&feet)
            .map(|(&c, f)| foot(model, c, q, Some(f.0), acc))
            .collect();
        feet = next?;
        if step <= tight * 0.1 {
            break;
        }
    }
    let spread = feet.iter().map(|f| (f.1 - q).length()).fold(0.0, f64::max);
    (spread <= tight && (q - p).length() <= REACH * off).then_some((q, off))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Edge, Vertex};
    use cadre_geom::Curve3;

    /// Two edges on lines through the origin meeting at a vertex written 0.1 off both.
    fn corner(vertex: Vec3) -> Model {
        let mut model = Model::default();
        model.curves.push(Curve3::Line {
            origin: Vec3::ZERO,
            direction: Vec3::X,
        });
        model.curves.push(Curve3::Line {
            origin: Vec3::ZERO,
            direction: Vec3::Y,
        });
        for p in [Vec3::new(-1.0, 0.0, 0.0), vertex, Vec3::new(0.0, -1.0, 0.0)] {
            model.vertices.push(Vertex {
                point: p,
                step_id: 0,
            });
        }
        for (k, (a, b)) in [(0, 1), (1, 2)].into_iter().enumerate() {
            model.edges.push(Edge {
                curve: Some(CurveId(k as u32)),
                start: VertexId(a),
                end: VertexId(b),
                same_sense: true,
                pcurves: Vec::new(),
                step_id: k as u64 + 1,
            });
        }
        model
    }

    #[test]
    fn a_vertex_off_its_curves_moves_to_where_they_meet() {
        let mut model = corner(Vec3::new(0.05, 0.1, 0.0));
        let moves = model.snap_vertices_to_curves(Accuracy::default());
        assert_eq!(moves.len(), 1, "{moves:?}");
        assert_eq!(moves[0].vertex, VertexId(1));
        assert!(
            model.vertices[1].point.length() < 1e-6,
            "{:?}",
            model.vertices[1]
        );
        assert!((moves[0].off_curve - 0.1).abs() < 1e-12);
        // The end vertices lie on their single curve: untouched.
        assert_eq!(model.vertices[0].point, Vec3::new(-1.0, 0.0, 0.0));
    }

    #[test]
    fn cached_edge_ranges_follow_a_moved_vertex() {
        let acc = Accuracy::default();
        let mut model = corner(Vec3::new(0.05, 0.1, 0.0));
        let e0 = crate::EdgeId(0);
        assert_eq!(model.edge_range(e0, acc), Some((-1.0, 0.05)));
        model.snap_vertices_to_curves(acc);
        let (t0, t1) = model.edge_range(e0, acc).unwrap();
        assert_eq!(t0, -1.0);
        assert!(t1.abs() < 1e-6, "{t1}");
        // An edge added after the cache was filled is still answered.
        model.edges.push(model.edges[0].clone());
        assert_eq!(model.edge_range(crate::EdgeId(2), acc), Some((t0, t1)));
    }

    #[test]
    fn a_vertex_on_its_curves_stays() {
        let mut model = corner(Vec3::new(1e-6, -1e-6, 0.0));
        assert!(
            model
                .snap_vertices_to_curves(Accuracy::default())
                .is_empty()
        );
        assert_eq!(model.vertices[1].point, Vec3::new(1e-6, -1e-6, 0.0));
    }

    #[test]
    fn curves_that_do_not_meet_near_the_vertex_leave_it() {
        let mut model = corner(Vec3::new(0.05, 0.1, 0.0));
        // Lift the second line 0.3 above the first: no common point.
        model.curves[1] = Curve3::Line {
            origin: Vec3::new(0.0, 0.0, 0.3),
            direction: Vec3::Y,
        };
        let moves = model.snap_vertices_to_curves(Accuracy::default());
        // Only the far end of the lifted line (its single curve) moves; the corner stays.
        assert_eq!(moves.len(), 1, "{moves:?}");
        assert_eq!(moves[0].vertex, VertexId(2));
        assert_eq!(model.vertices[1].point, Vec3::new(0.05, 0.1, 0.0));
    }
}
