//! Trim loops: each face's boundary as closed, oriented polygons and exact curves in the
//! (u, v) domain of its surface.
//!
//! This is what tessellation and GPU trimming consume. A face's loops come from its oriented
//! edges: every edge point gets its (u, v) from the file's pcurve when that pcurve agrees with
//! the 3D point, else by projecting the point on the surface. Parameters are unwrapped so each
//! loop is continuous across seams; singular points (poles, cone apex) take their free
//! parameter from their neighbours. Loops that go around a periodic surface (a cylinder face
//! bounded by two circles, a hemisphere bounded by its equator) are closed here by seam lines
//! and pole lines, so every [`TrimLoop`] is a closed polygon with the face on its left.
//!
//! Points carry weld [`keys`](TrimKey) so the tessellation can join faces without cracks:
//! edge samples and vertices have keys shared by every face that uses them; seam and pole
//! points have face-local keys shared by both sides of the seam.

mod close;
mod exact;
mod key;
mod uv;

use cadre_geom::{Accuracy, Curve2, Surface, Vec2, Vec3};

use crate::{EdgeId, Face, FaceId, Model};

pub use key::TrimKey;
pub use uv::periods;

/// One point of an edge's shared discretisation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeSample {
    /// Parameter on the edge's 3D curve (0 for an edge without curve).
    pub t: f64,
    /// Position, model units.
    pub xyz: Vec3,
    /// Weld key ([`TrimKey::vertex`] at the ends, [`TrimKey::edge`] inside).
    pub key: u64,
}

/// Source of the edge discretisation a face's loops are built from, so that every face using
/// an edge gets the same points.
pub trait EdgeSamples {
    /// Samples of `edge` from its start vertex to its end vertex (the edge's own direction),
    /// both ends included. Empty when the edge cannot be sampled.
    fn samples(&self, edge: EdgeId) -> &[EdgeSample];
}

/// Tolerances for the points the trim adds itself (seam and pole lines, domain sides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimTolerance {
    /// Largest chordal deviation of a segment from the surface, model units.
    pub deflection: f64,
    /// Largest angle between the surface normals at the ends of a segment, radians.
    pub angle: f64,
    /// Accuracy of point projections.
    pub accuracy: Accuracy,
    /// Whether to keep the exact (u, v) curve of each edge ([`TrimSegment::exact`]); the
    /// tessellation needs only the polylines.
    pub keep_exact: bool,
}

/// A trim polygon point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimPoint {
    /// Parameters, unwrapped (may lie outside the surface's first period).
    pub uv: Vec2,
    /// Exact position, model units (the shared edge sample, not re-evaluated).
    pub xyz: Vec3,
    /// Weld key.
    pub key: u64,
}

/// Where a trim segment comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentSource {
    /// A B-Rep edge, used forward (`true`) or reversed.
    Edge {
        /// The edge.
        edge: EdgeId,
        /// Whether the loop runs along the edge's direction.
        forward: bool,
    },
    /// A seam line added to close a loop that goes around a periodic surface.
    Seam,
    /// A line along a pole (sphere pole, cone apex) or a side of the surface's domain.
    Boundary,
    /// A polygonal boundary of a faceted face (`POLY_LOOP`).
    Polygon,
}

/// The exact (u, v) curve of a segment: `curve(t) + offset` for `t` from `t0` to `t1`.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactTrim {
    /// The curve (a pcurve of the file, or the exact image of the 3D curve).
    pub curve: Curve2,
    /// Parameter at the segment's start.
    pub t0: f64,
    /// Parameter at the segment's end.
    pub t1: f64,
    /// Period shift applied to the curve.
    pub offset: Vec2,
}

/// A piece of a trim loop.
#[derive(Clone, Debug, PartialEq)]
pub struct TrimSegment {
    /// Where it comes from.
    pub source: SegmentSource,
    /// Exact curve when known (pcurves, edges on planes, seam and pole lines).
    pub exact: Option<ExactTrim>,
    /// Polyline, in loop order; the last point is the next segment's first.
    pub points: Vec<TrimPoint>,
}

/// A closed trim loop, the face on its left in (u, v).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrimLoop {
    /// Segments in order.
    pub segments: Vec<TrimSegment>,
}

impl TrimLoop {
    /// The closed polygon: every point once (the closing point is not repeated), consecutive
    /// duplicates (same key) removed.
    pub fn polygon(&self) -> Vec<TrimPoint> {
        let mut out = merge_repeats(self.segments.iter().flat_map(|s| s.points.iter().copied()));
        while out.len() > 1 {
            let (f, l) = (out[0], out[out.len() - 1]);
            if f.key == l.key && (f.uv - l.uv).length() <= repeat_distance(&out) {
                out.pop();
            } else {
                break;
            }
        }
        out
    }

    /// Signed area of the polygon in (u, v): positive counter-clockwise.
    pub fn signed_area(&self) -> f64 {
        polygon_area(&self.polygon())
    }
}

/// Distance in (u, v) under which two consecutive points with the same key are one point:
/// a small fraction of the polygon's extent. Where two edges meet, the file's pcurves and the
/// vertex rarely agree to the last digit (bm2_ec_leverrod-A.stp: 3e-10 apart on a plane),
/// which left a point lying on its neighbour's segment; pole lines and seam copies share a
/// key too but are far apart.
fn repeat_distance(points: &[TrimPoint]) -> f64 {
    repeat_distance_of(points.iter().map(|p| p.uv))
}

/// [`repeat_distance`] of bare (u, v) positions.
fn repeat_distance_of(points: impl Iterator<Item = Vec2>) -> f64 {
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let size = (hi - lo).length();
    if size.is_finite() { 1e-6 * size } else { 0.0 }
}

/// The points in order with consecutive repeats (same key, within [`repeat_distance`]) merged.
pub(crate) fn merge_repeats(points: impl Iterator<Item = TrimPoint>) -> Vec<TrimPoint> {
    merge_repeats_tagged(points.map(|p| (p, ())).collect())
        .into_iter()
        .map(|(p, ())| p)
        .collect()
}

/// [`merge_repeats`] on points carrying a tag (the segment they come from): of two repeats
/// the first is kept, with its tag.
pub(crate) fn merge_repeats_tagged<T>(all: Vec<(TrimPoint, T)>) -> Vec<(TrimPoint, T)> {
    let tol = repeat_distance_of(all.iter().map(|(p, _)| p.uv));
    let mut out: Vec<(TrimPoint, T)> = Vec::with_capacity(all.len());
    for (p, tag) in all {
        if out
            .last()
            .is_some_and(|(q, _)| q.key == p.key && (q.uv - p.uv).length() <= tol)
        {
            continue;
        }
        out.push((p, tag));
    }
    out
}

/// Signed area of a closed (u, v) polygon.
pub fn polygon_area(poly: &[TrimPoint]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i].uv, poly[(i + 1) % n].uv);
            a.x * b.y - a.y * b.x
        })
        .sum::<f64>()
        * 0.5
}

/// A face's trim: closed loops, face on the left of each in (u, v).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceTrim {
    /// The loops; the face is what they enclose by the even-odd rule.
    pub loops: Vec<TrimLoop>,
    /// Whether the face normal is opposite to the surface normal `Su × Sv` (face
    /// `same_sense` false, unless the loops show the file's sense to be wrong; then a note
    /// says so, see [`face_trim`]). The loops are already oriented for (u, v).
    pub reversed: bool,
    /// Repairs made (a loop reversed, …), for reports.
    pub notes: Vec<String>,
}

/// Why a face's trim could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TrimError {
    /// The loops run clockwise about the face normal on a surface open on that side: the
    /// face would be the unbounded rest of its surface.
    #[error("the loops run clockwise about the face normal, which leaves an unbounded region")]
    Clockwise,
    /// The face's surface is unbounded and the face has no boundary.
    #[error("the face has no boundary and its surface is unbounded")]
    Unbounded,
    /// An edge of the face has no discretisation.
    #[error("edge #{0} could not be sampled")]
    EdgeNotSampled(u64),
    /// No point of a loop could be placed on the surface.
    #[error("loop points do not project onto the surface")]
    Projection,
    /// A loop goes around the surface in a way no closing can make a face of.
    #[error("loops go around the surface inconsistently: {0}")]
    Wrapping(String),
}

/// Builds the trim of face `face_id`.
///
/// A face whose loops cannot be closed into a bounded region as the file orients it (a loop
/// that goes around a cone and runs into its open side, loops clockwise about the rest of an
/// open surface) is read again with its sense turned over: files from some writers state the
/// sense of a face wrong while its loops and its neighbours agree with each other (PRO7071.stp:
/// two half cones through their apex; trj6_b1-ec-214.stp: cone patches), and CAD kernels take
/// the bounded side. The trim's notes say so.
pub fn face_trim(
    model: &Model,
    face_id: FaceId,
    edges: &impl EdgeSamples,
    tol: &TrimTolerance,
) -> Result<FaceTrim, TrimError> {
    let face = &model.faces[face_id.index()];
    match oriented_trim(model, face_id, face, edges, tol) {
        Err(e @ (TrimError::Wrapping(_) | TrimError::Unbounded | TrimError::Clockwise))
            if !face.loops.is_empty() =>
        {
            // Which flag is wrong, the face's sense or its bounds' orientation, the neighbours
            // tell: in a consistent shell they use each shared edge the other way round. If
            // they do, the loops are right and the sense is wrong (trj6_b1-ec-214.stp's
            // cones); if they use the edges the same way, the loops are wrong and the sense
            // right (trj9_ap209-mp.stp's planes). A face with no neighbours keeps its loops.
            let loops_right = loops_agree_with_neighbours(model, face_id).unwrap_or(true);
            let turned = if loops_right {
                Face {
                    same_sense: !face.same_sense,
                    ..face.clone()
                }
            } else {
                let mut f = face.clone();
                for l in &mut f.loops {
                    l.orientation = !l.orientation;
                }
                f
            };
            match oriented_trim(model, face_id, &turned, edges, tol) {
                Ok(mut trim) => {
                    let what = if loops_right {
                        "its sense is taken as reversed"
                    } else {
                        "its bounds are taken as reversed (its neighbours use its edges the same \
                         way it does)"
                    };
                    trim.notes.push(format!(
                        "as written the face cannot be bounded ({e}); {what}"
                    ));
                    Ok(trim)
                }
                Err(_) => Err(e),
            }
        }
        other => other,
    }
}

/// Whether the faces sharing edges with `face_id` in its shell use them in the opposite
/// direction, as a consistently oriented shell does (`None`: no shared edge to tell by). Edge
/// directions are taken as the shell uses the faces (bound orientation, oriented faces).
fn loops_agree_with_neighbours(model: &Model, face_id: FaceId) -> Option<bool> {
    let shell = model
        .shells
        .iter()
        .find(|s| s.faces.iter().any(|(f, _)| *f == face_id))?;
    // Per edge, each use's face and direction.
    let mut uses: std::collections::HashMap<EdgeId, Vec<(FaceId, bool)>> =
        std::collections::HashMap::new();
    for &(f, in_shell) in &shell.faces {
        for lp in &model.faces[f.index()].loops {
            if let crate::LoopKind::Edges(oes) = &lp.kind {
                for oe in oes {
                    let dir = oe.forward == lp.orientation;
                    uses.entry(oe.edge).or_default().push((f, dir == in_shell));
                }
            }
        }
    }
    let (mut opposite, mut same) = (0usize, 0usize);
    for mine in uses.values() {
        for &(_, d) in mine.iter().filter(|u| u.0 == face_id) {
            for &(_, e) in mine.iter().filter(|u| u.0 != face_id) {
                if d == e {
                    same += 1;
                } else {
                    opposite += 1;
                }
            }
        }
    }
    (opposite != same).then_some(opposite > same)
}

/// The trim of `face` (the model's face `face_id`, or a copy with its sense turned over).
fn oriented_trim(
    model: &Model,
    face_id: FaceId,
    face: &Face,
    edges: &impl EdgeSamples,
    tol: &TrimTolerance,
) -> Result<FaceTrim, TrimError> {
    let surface = &model.surfaces[face.surface.index()];
    let (chains, vertex_loops) = uv::face_chains(model, face, surface, edges, tol)?;
    let mut notes = Vec::new();
    let mut loops = close::close_loops(surface, face_id, chains, &vertex_loops, tol, &mut notes)?;
    recentre(surface, &mut loops);
    Ok(FaceTrim {
        loops,
        reversed: !face.same_sense,
        notes,
    })
}

/// Shifts all loops by whole periods so the face sits in the middle of the surface's domain:
/// unwrapping starts wherever the first point projects and may leave a face a period off
/// (trj9_io1-sy-214.stp: a half cone at v in [-1, 0] of a B-spline closed on [0, 2]), and
/// surfaces whose evaluation does not wrap (B-splines) are best evaluated inside their domain.
fn recentre(surface: &Surface, loops: &mut [TrimLoop]) {
    let p = periods(surface);
    let ((u0, u1), (v0, v1)) = surface.domain();
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for pt in loops
        .iter()
        .flat_map(|l| l.segments.iter().flat_map(|s| s.points.iter()))
    {
        lo = lo.min(pt.uv);
        hi = hi.max(pt.uv);
    }
    let mut shift = Vec2::ZERO;
    for (k, (d0, d1)) in [(0, (u0, u1)), (1, (v0, v1))] {
        if let Some(period) = p[k]
            && d0.is_finite()
            && d1.is_finite()
            && lo[k].is_finite()
        {
            shift[k] = ((0.5 * (d0 + d1) - 0.5 * (lo[k] + hi[k])) / period).round() * period;
        }
    }
    if shift == Vec2::ZERO {
        return;
    }
    for l in loops.iter_mut() {
        for s in &mut l.segments {
            for pt in &mut s.points {
                pt.uv += shift;
            }
            if let Some(e) = &mut s.exact {
                e.offset += shift;
            }
        }
    }
}

/// The surface a face lies on (convenience for callers holding only ids).
pub fn face_surface(model: &Model, face_id: FaceId) -> &Surface {
    &model.surfaces[model.faces[face_id.index()].surface.index()]
}
