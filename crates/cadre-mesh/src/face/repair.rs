//! Fallback triangulation for trim loops the strict build ([`super::cdt::build`]) rejects:
//! crossing segments, a point on another loop's segment, distinct points at one (u, v).
//!
//! Real CAD data has all of these (loops touching at a point, nearly tangent edges whose
//! chords cross in (u, v), slightly overlapping holes), and a face must not be lost for it.
//! Here coincident points are merged, the constraints are added one at a time (a crossing
//! one is split at the intersection, or left out), and inside/outside is decided by the
//! winding number of each triangle's centroid against the original loops, which needs no
//! constraint parity and so survives left-out or split constraints. Finally every edge
//! between an inside and an outside triangle is made a constraint, so that refinement,
//! which never crosses or splits constraints, keeps the region as classified.

use std::cell::Cell;
use std::collections::{HashMap, HashSet};

use cadre_geom::{Surface, Vec2};
use spade::handles::FixedVertexHandle;
use spade::{Point2, Triangulation};

use super::cdt::{Cdt, Vert};
use super::domain::{Prepared, edge_key};
use super::metric::Metric;
use super::refine::sample;
use super::{FaceMeshError, Points};

/// How constraints that cross already added ones are resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Both constraints are split at their intersection, where a new vertex goes in: the
    /// boundary stays in the mesh, only a few points are added on it.
    Split,
    /// The later constraint is left out: no new points, but the triangles may straddle it.
    /// Used when splitting failed (spade has had assertion failures on nearly collinear
    /// crossings).
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
    /// Boundary segments left out (only in [`Mode::Skip`], or once the split budget ran out).
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
    let rep = merge_map(&plane, nb, |i| winding.sign(pts.uv[i]) > 0);
    let merged = (0..nb).filter(|&i| rep[i] != i as u32).count();

    let verts: Vec<Vert> = (0..total)
        .filter(|&i| rep[i] == i as u32)
        .map(|i| Vert {
            pos: plane[i],
            id: i as u32,
        })
        .collect();
    let mut cdt = Cdt::bulk_load_cdt(verts, Vec::new())
        .map_err(|e| FaceMeshError::Triangulation(format!("{e:?}")))?;
    let mut handle: Vec<Option<FixedVertexHandle>> = vec![None; total];
    for v in cdt.vertices() {
        handle[v.data().id as usize] = Some(v.fix());
    }
    // The merge leaves distinct positions only, so spade keeps every vertex; should it still
    // have dropped one, the point goes to whichever vertex sits at its position.
    let handle_of = |cdt: &Cdt, i: usize| -> Option<FixedVertexHandle> {
        let r = rep[i] as usize;
        if r >= total {
            return None;
        }
        handle[r].or_else(|| match cdt.locate(plane[r]) {
            spade::PositionInTriangulation::OnVertex(v) => Some(v),
            _ => None,
        })
    };

    // Constraints that fit go in first, so that splits only happen where segments really
    // cross, not in whatever order the loops list them.
    let mut seen = HashSet::with_capacity(prep.edges.len());
    let mut conflicts = Vec::new();
    for &[a, b] in &prep.edges {
        let (Some(ha), Some(hb)) = (handle_of(&cdt, a as usize), handle_of(&cdt, b as usize))
        else {
            continue;
        };
        if ha == hb || !seen.insert(edge_key(ha.index() as u32, hb.index() as u32)) {
            continue;
        }
        if cdt.try_add_constraint(ha, hb).is_empty() {
            conflicts.push([ha, hb]);
        }
    }

    let mut skipped = 0;
    let next_id = Cell::new(total as u32);
    if mode == Mode::Split {
        // Each crossing adds one point, so this is far above what real data needs; the hard
        // cap inside the constructor stops a split cascade (rounding making spade split the
        // same crossing over and over) by a panic, which the caller turns into a retry in
        // [`Mode::Skip`].
        let budget = 4 * prep.edges.len() + 1024;
        let cap = (16 * prep.edges.len() + 4096) as u32 + total as u32;
        let ctor = |p: Point2<f64>| {
            let id = next_id.get();
            assert!(id < cap, "too many split points in the trim repair");
            next_id.set(id + 1);
            Vert { pos: p, id }
        };
        let along = VerticesAlong::new(&cdt);
        for &[ha, hb] in &conflicts {
            // A segment through other vertices goes in piece by piece between them: spade's
            // splitting walk can loop forever on a constraint through a vertex or along
            // another constraint (random_polygons_always_mesh found one: star and hole
            // sharing lattice points, zero-length and overlapping sides).
            let mut pieces = vec![ha];
            pieces.extend(along.strictly_between(&cdt, ha, hb));
            pieces.push(hb);
            for w in pieces.windows(2) {
                let (p, q) = (w[0], w[1]);
                if p == q || !cdt.try_add_constraint(p, q).is_empty() {
                    continue;
                }
                if (next_id.get() as usize - total) > budget {
                    skipped += 1;
                } else {
                    cdt.add_constraint_and_split(p, q, &ctor);
                }
            }
        }
    } else {
        skipped = conflicts.len();
    }

    // Split points get consecutive ids after the existing points (the constructor's ids
    // have gaps where spade used an existing vertex instead of the new one).
    let mut created: Vec<(u32, FixedVertexHandle)> = cdt
        .vertices()
        .filter(|v| v.data().id as usize >= total)
        .map(|v| (v.data().id, v.fix()))
        .collect();
    created.sort_unstable_by_key(|c| c.0);
    let split_points = created.len();
    for (k, &(_, h)) in created.iter().enumerate() {
        let uv = metric.plane_to_uv(cdt.vertex(h).position());
        let (xyz, n) = sample(surface, uv);
        pts.push(uv, xyz, n, None);
        cdt.vertex_data_mut(h).id = (total + k) as u32;
    }

    let inside = classify(&mut cdt, pts, &winding);
    Ok(Repaired {
        cdt,
        inside,
        merged,
        skipped,
        split_points,
    })
}

/// Maps every point to the point it is merged into (itself when it is kept). Boundary
/// points (`0..nb`) merge into the first one within the tolerance; interior points near an
/// earlier point, or not `keep_interior`, map to `u32::MAX` (dropped: they carry no key).
fn merge_map(plane: &[Point2<f64>], nb: usize, keep_interior: impl Fn(usize) -> bool) -> Vec<u32> {
    let (mut lo, mut hi) = (
        Point2::new(f64::INFINITY, f64::INFINITY),
        Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in &plane[..nb] {
        lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let ext = (hi.x - lo.x).max(hi.y - lo.y);
    let tol = if ext.is_finite() && ext > 0.0 {
        (MERGE_TOL * ext).max(f64::MIN_POSITIVE)
    } else {
        f64::MIN_POSITIVE
    };
    // Cells of the tolerance's size: a point within the tolerance (per coordinate) of
    // another is in one of the 3 × 3 cells around it. The casts saturate, which only makes
    // far-out cells shared, never misses a neighbour.
    let cell = |p: Point2<f64>| ((p.x / tol).floor() as i64, (p.y / tol).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<u32>> = HashMap::with_capacity(plane.len());
    let mut rep = vec![u32::MAX; plane.len()];
    for (i, &p) in plane.iter().enumerate() {
        if i >= nb && !keep_interior(i) {
            continue;
        }
        let (cx, cy) = cell(p);
        let mut found = None;
        'search: for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                let key = (cx.saturating_add(dx), cy.saturating_add(dy));
                for &j in grid.get(&key).into_iter().flatten() {
                    let q = plane[j as usize];
                    if (q.x - p.x).abs() <= tol && (q.y - p.y).abs() <= tol {
                        found = Some(j);
                        break 'search;
                    }
                }
            }
        }
        match found {
            Some(j) if i < nb => rep[i] = j,
            Some(_) => {}
            None => {
                rep[i] = i as u32;
                grid.entry((cx, cy)).or_default().push(i as u32);
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

/// The triangulation's vertices sorted by x, to find those lying on a segment.
struct VerticesAlong {
    by_x: Vec<(f64, f64, FixedVertexHandle)>,
}

impl VerticesAlong {
    fn new(cdt: &Cdt) -> VerticesAlong {
        let mut by_x: Vec<(f64, f64, FixedVertexHandle)> = cdt
            .vertices()
            .map(|v| (v.position().x, v.position().y, v.fix()))
            .collect();
        by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
        VerticesAlong { by_x }
    }

    /// Vertices on the open segment `a`–`b` (collinear to rounding), in order from `a`.
    fn strictly_between(
        &self,
        cdt: &Cdt,
        a: FixedVertexHandle,
        b: FixedVertexHandle,
    ) -> Vec<FixedVertexHandle> {
        let (pa, pb) = (cdt.vertex(a).position(), cdt.vertex(b).position());
        let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
        let len2 = dx * dx + dy * dy;
        if len2.is_nan() || len2 <= 0.0 {
            return Vec::new();
        }
        let (lo, hi) = (pa.x.min(pb.x), pa.x.max(pb.x));
        let first = self.by_x.partition_point(|v| v.0 < lo);
        let mut on: Vec<(f64, FixedVertexHandle)> = self.by_x[first..]
            .iter()
            .take_while(|v| v.0 <= hi)
            .filter(|v| v.2 != a && v.2 != b)
            .filter_map(|&(x, y, h)| {
                let (ex, ey) = (x - pa.x, y - pa.y);
                let cross = dx * ey - dy * ex;
                let t = (dx * ex + dy * ey) / len2;
                let tolerance = 1e-12 * len2.sqrt() * (ex * ex + ey * ey).sqrt();
                (cross.abs() <= tolerance && t > 1e-12 && t < 1.0 - 1e-12).then_some((t, h))
            })
            .collect();
        on.sort_by(|p, q| p.0.total_cmp(&q.0));
        on.into_iter().map(|(_, h)| h).collect()
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
