//! Fallback triangulation for trim loops the strict build ([`super::cdt::build`]) rejects:
//! crossing segments, a point on another loop's segment, distinct points at one (u, v).
//!
//! Real CAD data has all of these (loops touching at a point, nearly tangent edges whose
//! chords cross in (u, v), slightly overlapping holes), and a face must not be lost for it.
//! Here coincident points are merged, the segments are cut where they cross, touch or
//! overlap ([`super::arrange`]; spade's own splitting insertion can loop forever on such
//! trims), the pieces go in as constraints (one still conflicting by a rounding is left
//! out), and inside/outside is decided by the winding number of each triangle's centroid
//! against the original loops, which needs no constraint parity and so survives left-out or
//! split constraints. Finally every edge
//! between an inside and an outside triangle is made a constraint, so that refinement,
//! which never crosses or splits constraints, keeps the region as classified.

use std::collections::HashSet;

use cadre_geom::{Surface, Vec2};
use spade::handles::FixedVertexHandle;
use spade::{Point2, Triangulation};

use super::arrange::{PointGrid, arrange};
use super::cdt::{Cdt, Vert};
use super::domain::{Prepared, edge_key};
use super::metric::Metric;
use super::refine::sample;
use super::{FaceMeshError, Points};

/// How segments that cross each other are resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Both segments are cut at their crossing, where a new vertex goes in: the boundary
    /// stays in the mesh, only a few points are added on it.
    Split,
    /// The later segment is left out: no new points, but the triangles may straddle it.
    /// The fallback should the triangulation with split points fail (spade has had
    /// assertion failures on nearly degenerate constraint sets).
    Skip,
}

/// Points closer than this fraction of the domain's extent (in the triangulation plane) are
/// one point. Far below any meaningful sampling of a trim, and well above the rounding of
/// the (u, v) → plane scaling that makes distinct (u, v) collide there.
const MERGE_TOL: f64 = 1e-12;

/// The repaired triangulation and what the repair did.
#[derive(Debug)]
pub(crate) struct Repaired {
    /// The triangulation; vertex ids index the (extended) point arrays.
    pub cdt: Cdt,
    /// Inside flag of every face, by face index.
    pub inside: Vec<bool>,
    /// Boundary points merged into an earlier point at the same (u, v) (their keys are not
    /// in the mesh).
    pub merged: usize,
    /// Pieces of boundary segments left out because they cross a piece already in
    /// (uncut crossings in [`Mode::Skip`] or past the crossing budget, roundings).
    pub skipped: usize,
    /// Points created where crossing segments were split.
    pub split_points: usize,
}

/// Builds the fallback triangulation of `prep`. `pts` holds the boundary points (ids
/// `0..prep.points.len()`) followed by the interior grid points; the split points are
/// appended to it, with `key: None` and their position and normal evaluated on `surface`.
///
/// # Errors
///
/// [`FaceMeshError::Triangulation`] when spade rejects a coordinate.
pub(crate) fn build(
    surface: &Surface,
    prep: &Prepared,
    metric: &Metric,
    pts: &mut Points,
    mode: Mode,
) -> Result<Repaired, FaceMeshError> {
    let nb = prep.points.len();
    let total = pts.len();
    let winding = Winding::new(&prep.segments);

    let plane: Vec<Point2<f64>> = pts.uv.iter().map(|&uv| metric.to_plane(uv)).collect();
    let mut grid = PointGrid::new(merge_tol(&plane[..nb]), total);
    let rep = merge_map(&plane, nb, &mut grid, |i| winding.sign(pts.uv[i]) > 0);
    let merged = (0..nb).filter(|&i| rep[i] != i as u32).count();

    // Each crossing adds one point; the budget is far above what real data needs and keeps
    // a pathological trim from adding a point per pair of its segments.
    let segs = constraint_segments(prep, &rep);
    let max_crossings = match mode {
        Mode::Split => 4 * segs.len() + 1024,
        Mode::Skip => 0,
    };
    let arr = arrange(&plane, &segs, &mut grid, total as u32, max_crossings);
    if !arr.complete || arr.uncut > 0 {
        tracing::debug!(
            uncut = arr.uncut,
            complete = arr.complete,
            "trim crossings left uncut"
        );
    }
    for &p in &arr.crossings {
        let uv = metric.plane_to_uv(p);
        let (xyz, n) = sample(surface, uv);
        pts.push(uv, xyz, n, None);
    }

    let verts: Vec<Vert> = (0..total)
        .filter(|&i| rep[i] == i as u32)
        .map(|i| Vert {
            pos: plane[i],
            id: i as u32,
        })
        .chain(arr.crossings.iter().enumerate().map(|(k, &pos)| Vert {
            pos,
            id: (total + k) as u32,
        }))
        .collect();
    let mut cdt = Cdt::bulk_load_cdt(verts, Vec::new())
        .map_err(|e| FaceMeshError::Triangulation(format!("{e:?}")))?;
    let skipped = add_pieces(&mut cdt, &arr.pieces, pts.len());

    let inside = classify(&mut cdt, pts, &winding);
    Ok(Repaired {
        cdt,
        inside,
        merged,
        skipped,
        split_points: arr.crossings.len(),
    })
}

/// The distinct loop segments between merged points, as point ids, without the ones merged
/// to a single point.
fn constraint_segments(prep: &Prepared, rep: &[u32]) -> Vec<[u32; 2]> {
    let mut seen = HashSet::with_capacity(prep.edges.len());
    prep.edges
        .iter()
        .map(|&[a, b]| [rep[a as usize], rep[b as usize]])
        .filter(|&[a, b]| a != b && a != u32::MAX && b != u32::MAX && seen.insert(edge_key(a, b)))
        .collect()
}

/// Adds the `pieces` (point ids below `n`) as constraints with spade's non-splitting
/// insertion, which leaves a piece out when it would cross a constraint already in (by a
/// rounding of the crossing points, or an uncut crossing). Returns how many were left out.
fn add_pieces(cdt: &mut Cdt, pieces: &[[u32; 2]], n: usize) -> usize {
    let mut handle: Vec<Option<FixedVertexHandle>> = vec![None; n];
    for v in cdt.vertices() {
        handle[v.data().id as usize] = Some(v.fix());
    }
    let mut skipped = 0;
    for &[a, b] in pieces {
        let (Some(ha), Some(hb)) = (handle[a as usize], handle[b as usize]) else {
            // Spade merged the point into another at the same position: the merge and the
            // snapping of crossings leave none such, but the piece is then left out.
            skipped += 1;
            continue;
        };
        if cdt.try_add_constraint(ha, hb).is_empty() {
            skipped += 1;
        }
    }
    skipped
}

/// The distance below which points of the triangulation plane are one point (see
/// [`MERGE_TOL`]), from the boundary points' extent.
fn merge_tol(boundary: &[Point2<f64>]) -> f64 {
    let (mut lo, mut hi) = (
        Point2::new(f64::INFINITY, f64::INFINITY),
        Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in boundary {
        lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let ext = (hi.x - lo.x).max(hi.y - lo.y);
    if ext.is_finite() && ext > 0.0 {
        (MERGE_TOL * ext).max(f64::MIN_POSITIVE)
    } else {
        f64::MIN_POSITIVE
    }
}

/// Maps every point to the point it is merged into (itself when it is kept), and puts the
/// kept ones in `grid`. Boundary points (`0..nb`) merge into the first one within the
/// tolerance; interior points near an earlier point, or not `keep_interior`, map to
/// `u32::MAX` (dropped: they carry no key).
fn merge_map(
    plane: &[Point2<f64>],
    nb: usize,
    grid: &mut PointGrid,
    keep_interior: impl Fn(usize) -> bool,
) -> Vec<u32> {
    let mut rep = vec![u32::MAX; plane.len()];
    for (i, &p) in plane.iter().enumerate() {
        if i >= nb && !keep_interior(i) {
            continue;
        }
        match grid.find(p) {
            Some(j) if i < nb => rep[i] = j,
            Some(_) => {}
            None => {
                rep[i] = i as u32;
                grid.insert(p, i as u32);
            }
        }
    }
    rep
}

/// Inside flags from the winding number of each triangle's centroid (positive winding, the
/// loops' overall orientation taken as counter-clockwise), then the edges between inside
/// and outside made constraints. Falls back to a non-zero winding where no triangle has a
/// positive one.
fn classify(cdt: &mut Cdt, pts: &Points, winding: &Winding) -> Vec<bool> {
    let mut w = vec![0i32; cdt.num_all_faces()];
    for f in cdt.inner_faces() {
        let c = f
            .vertices()
            .iter()
            .map(|v| pts.uv[v.data().id as usize])
            .sum::<Vec2>()
            / 3.0;
        w[f.fix().index()] = winding.sign(c);
    }
    let mut inside: Vec<bool> = w.iter().map(|&w| w > 0).collect();
    if !inside.iter().any(|&b| b) {
        inside = w.iter().map(|&w| w != 0).collect();
    }

    let mut fence = Vec::new();
    for e in cdt.undirected_edges() {
        let d = e.as_directed();
        if !d.is_constraint_edge()
            && inside[d.face().fix().index()] != inside[d.rev().face().fix().index()]
        {
            fence.push([d.from().fix(), d.to().fix()]);
        }
    }
    // Constraining an existing edge only marks it (no flips), so the faces and their
    // indices stay as classified.
    for [a, b] in fence {
        cdt.add_constraint(a, b);
    }
    inside
}

/// Winding numbers of points with respect to the loop segments, with the segments bucketed
/// into horizontal bands so that a query scans only the segments in its band (faces can
/// have 10^5 boundary segments and as many triangles).
pub(crate) struct Winding<'a> {
    segs: &'a [[Vec2; 2]],
    /// Lower v of the bands.
    y0: f64,
    /// Bands per unit v.
    scale: f64,
    /// Number of bands.
    bands: usize,
    /// Start of each band's segment list in `items` (`bands + 1` entries).
    start: Vec<u32>,
    /// Segment indices, band by band.
    items: Vec<u32>,
    /// +1 when the loops are counter-clockwise overall, −1 when they are all reversed.
    orient: i32,
}

impl<'a> Winding<'a> {
    /// Buckets `segs` (directed, face on the left).
    pub fn new(segs: &'a [[Vec2; 2]]) -> Winding<'a> {
        let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut lo = Vec2::splat(f64::INFINITY);
        for &[p, q] in segs {
            y0 = y0.min(p.y.min(q.y));
            y1 = y1.max(p.y.max(q.y));
            lo = lo.min(p).min(q);
        }
        // Shoelace relative to the box corner keeps the sum well conditioned.
        let area: f64 = segs.iter().map(|&[p, q]| (p - lo).perp_dot(q - lo)).sum();
        let orient = if area < 0.0 { -1 } else { 1 };
        let mut w = Winding {
            segs,
            y0,
            scale: 0.0,
            bands: 1,
            start: Vec::new(),
            items: Vec::new(),
            orient,
        };
        let span = y1 - y0;
        // One band per segment at most; fewer when long segments would be copied into too
        // many bands (memory stays within a small multiple of the segment count).
        let mut bands = segs.len().clamp(1, 1 << 16);
        if span.is_finite() && span > 0.0 {
            loop {
                w.bands = bands;
                w.scale = bands as f64 / span;
                let entries: usize = segs
                    .iter()
                    .filter(|s| s[0].y != s[1].y)
                    .map(|&[p, q]| w.band(p.y.max(q.y)) - w.band(p.y.min(q.y)) + 1)
                    .sum();
                if entries <= 8 * segs.len() + 4096 || bands == 1 {
                    break;
                }
                bands /= 2;
            }
        } else {
            w.bands = 1;
        }
        let mut count = vec![0u32; w.bands + 1];
        for &[p, q] in segs.iter().filter(|s| s[0].y != s[1].y) {
            for b in w.band(p.y.min(q.y))..=w.band(p.y.max(q.y)) {
                count[b + 1] += 1;
            }
        }
        for b in 0..w.bands {
            count[b + 1] += count[b];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[w.bands] as usize];
        for (i, &[p, q]) in segs.iter().enumerate() {
            // Horizontal segments never cross a horizontal ray (half-open rule below).
            if p.y == q.y {
                continue;
            }
            for b in w.band(p.y.min(q.y))..=w.band(p.y.max(q.y)) {
                items[fill[b] as usize] = i as u32;
                fill[b] += 1;
            }
        }
        w.start = count;
        w.items = items;
        w
    }

    /// The band holding v = `y` (clamped to the first and last).
    fn band(&self, y: f64) -> usize {
        let t = (y - self.y0) * self.scale;
        if t >= 0.0 {
            (t as usize).min(self.bands - 1)
        } else {
            0
        }
    }

    /// Winding number of `c`, positive inside counter-clockwise loops (after the overall
    /// orientation is normalised).
    pub fn sign(&self, c: Vec2) -> i32 {
        if self.start.is_empty() {
            return 0;
        }
        let b = self.band(c.y);
        let mut wn = 0;
        for &i in &self.items[self.start[b] as usize..self.start[b + 1] as usize] {
            let [p, q] = self.segs[i as usize];
            let left = (q - p).perp_dot(c - p);
            if p.y <= c.y {
                if q.y > c.y && left > 0.0 {
                    wn += 1;
                }
            } else if q.y <= c.y && left < 0.0 {
                wn -= 1;
            }
        }
        wn * self.orient
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sq(x0: f64, y0: f64, s: f64, ccw: bool) -> Vec<[Vec2; 2]> {
        let mut c = [
            Vec2::new(x0, y0),
            Vec2::new(x0 + s, y0),
            Vec2::new(x0 + s, y0 + s),
            Vec2::new(x0, y0 + s),
        ];
        if !ccw {
            c.reverse();
        }
        (0..4).map(|i| [c[i], c[(i + 1) % 4]]).collect()
    }

    #[test]
    fn winding_of_nested_and_overlapping_loops() {
        let mut segs = sq(0.0, 0.0, 10.0, true);
        segs.extend(sq(2.0, 2.0, 2.0, false));
        segs.extend(sq(5.0, 5.0, 10.0, true));
        let w = Winding::new(&segs);
        assert_eq!(w.sign(Vec2::new(1.0, 1.0)), 1);
        assert_eq!(w.sign(Vec2::new(3.0, 3.0)), 0);
        assert_eq!(w.sign(Vec2::new(7.0, 7.0)), 2);
        assert_eq!(w.sign(Vec2::new(12.0, 12.0)), 1);
        assert_eq!(w.sign(Vec2::new(12.0, 1.0)), 0);
        assert_eq!(w.sign(Vec2::new(-1.0, 5.0)), 0);
        // All loops reversed: the same numbers.
        let rev: Vec<[Vec2; 2]> = segs.iter().map(|&[p, q]| [q, p]).collect();
        let w = Winding::new(&rev);
        assert_eq!(w.sign(Vec2::new(1.0, 1.0)), 1);
        assert_eq!(w.sign(Vec2::new(7.0, 7.0)), 2);
    }

    #[test]
    fn winding_with_many_segments_matches_brute_force() {
        // A star polygon with many spikes: long and short segments in every band.
        let n = 2000;
        let pts: Vec<Vec2> = (0..n)
            .map(|i| {
                let t = i as f64 * std::f64::consts::TAU / n as f64;
                let r = if i % 2 == 0 { 10.0 } else { 3.0 };
                Vec2::new(r * t.cos(), r * t.sin())
            })
            .collect();
        let segs: Vec<[Vec2; 2]> = (0..n).map(|i| [pts[i], pts[(i + 1) % n]]).collect();
        let w = Winding::new(&segs);
        let brute = Winding {
            bands: 1,
            scale: 0.0,
            start: vec![0, segs.len() as u32],
            items: (0..segs.len() as u32).collect(),
            ..Winding::new(&segs)
        };
        for k in 0..500 {
            let c = Vec2::new(
                ((k * 37) % 200) as f64 / 9.0 - 11.0,
                ((k * 91) % 200) as f64 / 9.0 - 11.0,
            );
            assert_eq!(w.sign(c), brute.sign(c), "{c:?}");
        }
    }
}
