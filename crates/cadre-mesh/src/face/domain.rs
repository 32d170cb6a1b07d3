//! Validation and clean-up of the trim loops: one vertex per distinct (u, v), one constraint
//! per distinct segment, and the parity weight of each constraint for even-odd classification.

use std::collections::{HashMap, HashSet};

use cadre_geom::Vec2;

use super::{BoundaryPoint, FaceDomain, FaceMeshError};

/// The trim loops reduced to what the triangulator needs.
#[derive(Debug)]
pub(crate) struct Prepared {
    /// Distinct boundary points (first occurrence of each (u, v)); index = vertex id.
    pub points: Vec<BoundaryPoint>,
    /// Distinct undirected constraint segments, as vertex ids.
    pub edges: Vec<[u32; 2]>,
    /// Segments used an even number of times (a slit traversed both ways): they stay
    /// constraints (their points are shared) but do not separate inside from outside.
    pub even_edges: HashSet<(u32, u32)>,
    /// Every loop segment in (u, v), with multiplicity (for scanline inside tests).
    pub segments: Vec<[Vec2; 2]>,
    /// Directed loop segments whose ends weld to one point (pole lines, apexes), face on
    /// their left.
    pub collapsed: Vec<[Vec2; 2]>,
    /// Lower corner of the (u, v) bounding box.
    pub lo: Vec2,
    /// Upper corner of the (u, v) bounding box.
    pub hi: Vec2,
}

/// Orders a vertex pair so that both directions of a segment map to the same key.
pub(crate) fn edge_key(a: u32, b: u32) -> (u32, u32) {
    if a < b { (a, b) } else { (b, a) }
}

/// Bit pattern of a (u, v) for exact duplicate detection (`-0.0` folded onto `0.0`).
fn uv_bits(uv: Vec2) -> (u64, u64) {
    ((uv.x + 0.0).to_bits(), (uv.y + 0.0).to_bits())
}

/// Checks `domain` and builds the deduplicated vertex and constraint lists.
///
/// Degenerate loops (fewer than three points, zero area) are kept: their points are shared
/// with other faces and must appear in the mesh; only a domain with no area at all is an
/// error.
pub(crate) fn prepare(domain: &FaceDomain) -> Result<Prepared, FaceMeshError> {
    let all = || domain.loops.iter().flatten();
    if all().any(|p| !p.uv.is_finite() || !p.xyz.is_finite()) {
        return Err(FaceMeshError::NonFinite);
    }
    let total: usize = domain.loops.iter().map(Vec::len).sum();
    if total < 3 {
        return Err(FaceMeshError::EmptyDomain);
    }

    let mut lo = Vec2::splat(f64::INFINITY);
    let mut hi = Vec2::splat(f64::NEG_INFINITY);
    for p in all() {
        lo = lo.min(p.uv);
        hi = hi.max(p.uv);
    }

    let extent = (hi - lo).max_element();
    let loops: Vec<Vec<BoundaryPoint>> = domain
        .loops
        .iter()
        .map(|lp| separate_coincident(lp, extent))
        .collect();

    let mut ids: HashMap<(u64, u64), u32> = HashMap::with_capacity(total);
    let mut points = Vec::with_capacity(total);
    let mut counts: HashMap<(u32, u32), u32> = HashMap::with_capacity(total);
    let mut edge_order = Vec::with_capacity(total);
    let mut segments = Vec::with_capacity(total);
    let mut collapsed = Vec::new();
    let mut loop_ids: Vec<u32> = Vec::new();
    let mut area2 = 0.0;
    for lp in &loops {
        loop_ids.clear();
        for p in lp {
            let id = *ids.entry(uv_bits(p.uv)).or_insert_with(|| {
                points.push(*p);
                (points.len() - 1) as u32
            });
            // Consecutive repeats are zero-length segments: drop them.
            if loop_ids.last() != Some(&id) {
                loop_ids.push(id);
            }
        }
        while loop_ids.len() > 1 && loop_ids.first() == loop_ids.last() {
            loop_ids.pop();
        }
        // A two-point loop is one segment traversed both ways (a slit): counted twice below.
        let n = loop_ids.len();
        if n < 2 {
            continue;
        }
        // Shoelace relative to the box corner keeps the sum well conditioned.
        let mut a = 0.0;
        for i in 0..n {
            let (ia, ib) = (loop_ids[i], loop_ids[(i + 1) % n]);
            let (pa, pb) = (points[ia as usize].uv - lo, points[ib as usize].uv - lo);
            a += pa.perp_dot(pb);
            segments.push([pa + lo, pb + lo]);
            if points[ia as usize].key == points[ib as usize].key {
                collapsed.push([pa + lo, pb + lo]);
            }
            let key = edge_key(ia, ib);
            let c = counts.entry(key).or_insert(0);
            if *c == 0 {
                edge_order.push([key.0, key.1]);
            }
            *c += 1;
        }
        area2 += a.abs();
    }

    // Written so that a NaN area also counts as empty.
    if points.len() < 3
        || area2.partial_cmp(&(1e-24 * extent * extent)) != Some(std::cmp::Ordering::Greater)
    {
        return Err(FaceMeshError::EmptyDomain);
    }
    let even_edges = counts
        .iter()
        .filter(|&(_, &c)| c % 2 == 0)
        .map(|(&k, _)| k)
        .collect();
    Ok(Prepared {
        points,
        edges: edge_order,
        even_edges,
        segments,
        collapsed,
        lo,
        hi,
    })
}

/// Fraction of the way to the next distinct point a coincident point is moved.
const NUDGE: f64 = 1e-6;

/// The loop with each run of consecutive points at one (u, v) but with different weld keys
/// spread out along the way to the next point: a surface's parameters can map two distinct
/// vertices to one (u, v) (an edge a few micrometres long, both ends clamped onto a corner
/// of the domain: trj7_b1-ec-214.stp face #3627), and merging them would drop the short
/// edge from this face while its neighbour keeps it, leaving the solid open. Each keeps its
/// position and key, so the triangles still weld to the neighbours; only its (u, v) moves,
/// by a millionth of the way on (at least 1e-10 of the domain, at most half the way).
fn separate_coincident(lp: &[BoundaryPoint], extent: f64) -> Vec<BoundaryPoint> {
    let mut out = lp.to_vec();
    let n = out.len();
    let mut i = 0;
    while i < n {
        // The run starting at i: following points at i's (u, v).
        let mut j = i + 1;
        while j < n && uv_bits(lp[j].uv) == uv_bits(lp[i].uv) {
            j += 1;
        }
        let distinct_keys = (i + 1..j).any(|k| lp[k].key != lp[i].key);
        if distinct_keys && let Some(next) = (j..n).chain(0..i).find(|&k| lp[k].uv != lp[i].uv) {
            let to = lp[next].uv - lp[i].uv;
            let d = to.length();
            let step = (NUDGE * d)
                .max(1e-10 * extent)
                .min(0.5 * d / (j - i) as f64);
            let dir = to / d;
            let mut moved = 0.0;
            for k in i + 1..j {
                // Equal keys stay together (a pole line's points).
                if lp[k].key != lp[k - 1].key {
                    moved += step;
                }
                out[k].uv = lp[i].uv + dir * moved;
            }
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::Vec3;

    fn bp(u: f64, v: f64, key: u64) -> BoundaryPoint {
        BoundaryPoint {
            uv: Vec2::new(u, v),
            xyz: Vec3::new(u, v, 0.0),
            key,
        }
    }

    #[test]
    fn duplicates_and_slits() {
        // Square with a repeated corner and a slit (two-point loop) inside.
        let domain = FaceDomain {
            loops: vec![
                vec![
                    bp(0.0, 0.0, 0),
                    bp(1.0, 0.0, 1),
                    bp(1.0, 0.0, 1),
                    bp(1.0, 1.0, 2),
                    bp(0.0, 1.0, 3),
                    bp(0.0, 0.0, 0),
                ],
                vec![bp(0.2, 0.5, 4), bp(0.8, 0.5, 5)],
            ],
        };
        let p = prepare(&domain).unwrap();
        assert_eq!(p.points.len(), 6);
        assert_eq!(p.edges.len(), 5);
        assert_eq!(p.even_edges.len(), 1);
        assert!(p.even_edges.contains(&(4, 5)));
    }

    #[test]
    fn rejects_bad_input() {
        let nan = FaceDomain {
            loops: vec![vec![bp(0.0, 0.0, 0), bp(f64::NAN, 0.0, 1), bp(0.0, 1.0, 2)]],
        };
        assert_eq!(prepare(&nan).unwrap_err(), FaceMeshError::NonFinite);
        let two = FaceDomain {
            loops: vec![vec![bp(0.0, 0.0, 0), bp(1.0, 0.0, 1)]],
        };
        assert_eq!(prepare(&two).unwrap_err(), FaceMeshError::EmptyDomain);
        let flat = FaceDomain {
            loops: vec![vec![bp(0.0, 0.0, 0), bp(1.0, 0.0, 1), bp(2.0, 0.0, 2)]],
        };
        assert_eq!(prepare(&flat).unwrap_err(), FaceMeshError::EmptyDomain);
    }

    #[test]
    fn coincident_points_with_different_keys_are_kept_apart() {
        // A unit square whose corner (1, 0) holds two vertices (keys 1 and 5).
        let domain = FaceDomain {
            loops: vec![vec![
                bp(0.0, 0.0, 0),
                bp(1.0, 0.0, 1),
                bp(1.0, 0.0, 5),
                bp(1.0, 1.0, 2),
                bp(0.0, 1.0, 3),
            ]],
        };
        let p = prepare(&domain).unwrap();
        let keys: Vec<u64> = p.points.iter().map(|b| b.key).collect();
        assert_eq!(keys, [0, 1, 5, 2, 3]);
        // The second moved a millionth of the way towards (1, 1); its position stayed.
        let moved = p.points[2].uv - Vec2::new(1.0, 0.0);
        assert!(
            moved.x.abs() < 1e-15 && moved.y > 0.0 && moved.y < 1e-5,
            "{moved:?}"
        );
        assert_eq!(p.points[2].xyz, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(p.edges.len(), 5);
        // Equal keys at one (u, v) are still one point.
        let repeated = FaceDomain {
            loops: vec![vec![
                bp(0.0, 0.0, 0),
                bp(1.0, 0.0, 1),
                bp(1.0, 0.0, 1),
                bp(1.0, 1.0, 2),
            ]],
        };
        assert_eq!(prepare(&repeated).unwrap().points.len(), 3);
    }
}
