//! Boundary-only triangulation of a face whose single trim loop crosses itself in (u, v),
//! for faces thin enough to need no interior point.
//!
//! A sliver between two nearly coincident edges (a blend strip 0.04 mm wide between two
//! arcs, a plane annulus between two circles a rounding apart, a B-spline band between two
//! tangentially touching edges) has chords of one edge crossing chords of the other. The
//! repair ([`super::repair`]) splits the crossing chords at new points that the neighbouring
//! faces lack, which opened the solid there (trj6_b1-ec-214.stp faces #18929, #19527 and
//! #6387: 221 open edges with the projection fix of `cadre_geom`'s valley walk, 0 with
//! this). A strip triangulation needs no valid polygon: it uses every boundary segment
//! exactly once, whatever the crossings, so the face welds to its
//! neighbours; where the chains cross a triangle folds over, by less than the deflection.
//! The strip is zipped from one tip of the lens to the other (the loop's two farthest
//! points), each triangle spanning it.
//! It is taken only when every triangle is within the deflection of the surface and the
//! folded triangles cover no more than a deflection-wide strip along the boundary.

use cadre_geom::{Surface, Vec2, Vec3};

use super::domain::Prepared;
use super::metric::{Metric, StepTol};
use super::refine::{normal_gap, sample};
use super::{FaceMesh, Points, output};
use crate::strip::{height, zip_strip};

/// Largest loop clipped: the ear search is quadratic in the points, and slivers have a few
/// hundred at most.
const MAX_POINTS: usize = 1_000;

/// Triangulates the single loop of `prep` from its boundary points alone (ids
/// `0..prep.points.len()` of `pts`), or `None` when the domain is not one simple cycle or
/// the result is not within the tolerances.
pub(crate) fn triangulate(
    surface: &Surface,
    reversed: bool,
    prep: &Prepared,
    pts: &Points,
    metric: &Metric,
    tol: &StepTol,
) -> Option<FaceMesh> {
    let cycle = single_cycle(prep)?;
    let plane: Vec<Vec2> = cycle
        .iter()
        .map(|&i| {
            let p = metric.to_plane(pts.uv[i as usize]);
            Vec2::new(p.x, p.y)
        })
        .collect();
    // The face lies on the left of its loop; a loop that winds the other way as a whole is
    // not a sliver of this kind.
    if signed_area(&plane) <= 0.0 {
        return None;
    }
    let xyz: Vec<Vec3> = cycle.iter().map(|&i| pts.xyz[i as usize]).collect();
    let ears = zip_strip(&xyz);
    let upright: Vec<bool> = ears
        .iter()
        .map(|t| cross(plane[t[0]], plane[t[1]], plane[t[2]]) >= 0.0)
        .collect();
    let triangles: Vec<[usize; 3]> = ears.iter().map(|t| t.map(|k| cycle[k] as usize)).collect();
    let perimeter: f64 = (0..cycle.len())
        .map(|k| {
            let (a, b) = (cycle[k], cycle[(k + 1) % cycle.len()]);
            (pts.xyz[a as usize] - pts.xyz[b as usize]).length()
        })
        .sum();
    if !within_tolerance(surface, pts, &triangles, &upright, perimeter, tol) {
        return None;
    }
    let ids: Vec<usize> = (0..prep.points.len()).collect();
    Some(output::assemble_ids(
        surface, reversed, &ids, &triangles, pts, false, false,
    ))
}

/// The boundary points in loop order, when the constraint segments form one cycle through
/// all of them (every point on exactly two segments, no slit).
fn single_cycle(prep: &Prepared) -> Option<Vec<u32>> {
    let n = prep.points.len();
    if !(3..=MAX_POINTS).contains(&n) || prep.edges.len() != n || !prep.even_edges.is_empty() {
        return None;
    }
    let mut next = vec![[u32::MAX; 2]; n];
    for &[a, b] in &prep.edges {
        for (x, y) in [(a, b), (b, a)] {
            let slot = next.get_mut(x as usize)?;
            if slot[0] == u32::MAX {
                slot[0] = y;
            } else if slot[1] == u32::MAX {
                slot[1] = y;
            } else {
                return None;
            }
        }
    }
    // The loop direction is the one the segments were written in: follow the first
    // segment's direction.
    let [a0, b0] = prep.edges[0];
    let mut cycle = Vec::with_capacity(n);
    let (mut prev, mut at) = (a0, b0);
    cycle.push(a0);
    while at != a0 {
        if cycle.len() >= n {
            return None;
        }
        cycle.push(at);
        let [x, y] = next[at as usize];
        let to = if x == prev { y } else { x };
        if to == u32::MAX {
            return None;
        }
        (prev, at) = (at, to);
    }
    (cycle.len() == n).then_some(cycle)
}

/// Twice the signed area of a closed polygon.
fn signed_area(p: &[Vec2]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - a.y * b.x
        })
        .sum()
}

/// `(b − a) × (c − a)`.
fn cross(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Every triangle within the deflection of the surface at its centroid and edge midpoints
/// (measured along the normal, from the corners' feet on the surface, as refinement does),
/// every folded one (clockwise in the plane) no higher than the deflection, and all of them
/// together no larger than a deflection-wide strip along the boundary.
fn within_tolerance(
    surface: &Surface,
    pts: &Points,
    tris: &[[usize; 3]],
    upright: &[bool],
    perimeter: f64,
    tol: &StepTol,
) -> bool {
    let deflection = tol.deflection();
    let mut folded = 0.0;
    for (t, &up) in tris.iter().zip(upright) {
        let uv = t.map(|i| pts.uv[i]);
        let on = t.map(|i| pts.on_surface(i as u32));
        for w in [
            [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ] {
            let q_uv = uv[0] * w[0] + uv[1] * w[1] + uv[2] * w[2];
            let chord: Vec3 = on[0] * w[0] + on[1] * w[1] + on[2] * w[2];
            let (s, n) = sample(surface, q_uv);
            let gap = normal_gap(s, n, chord);
            if gap.is_nan() || gap > deflection {
                return false;
            }
        }
        let xyz = t.map(|i| pts.xyz[i]);
        if !up {
            // A fold where two chains cross is as thin as the sliver; a fat one means the
            // loop really crosses itself and the face is not a sliver.
            let h = height(xyz[0], xyz[1], xyz[2]);
            if h.is_nan() || h > deflection {
                return false;
            }
            folded += 0.5 * (xyz[1] - xyz[0]).cross(xyz[2] - xyz[0]).length();
        }
    }
    folded <= deflection * perimeter
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use cadre_geom::{Surface, Vec2};

    use super::super::tests::plane;
    use super::super::{BoundaryPoint, FaceDomain, FaceMesh, cdt, domain, triangulate_face};
    use crate::MeshParams;

    /// A plane annulus sliver as trj6_b1-ec-214.stp face #18929 has: a quarter arc of
    /// radius 17.001 out (20 chords, counter-clockwise) and of radius 17 back (13 chords),
    /// 0.001 apart, so each chord of one arc crosses the other (sagitta 0.013).
    fn annulus_sliver(s: &Surface) -> FaceDomain {
        let arc = |r: f64, n: usize, rev: bool, key0: u64| -> Vec<BoundaryPoint> {
            (0..n)
                .map(|i| {
                    let k = if rev { n - i } else { i };
                    let a = std::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
                    let uv = Vec2::new(r * a.cos(), r * a.sin());
                    BoundaryPoint {
                        uv,
                        xyz: s.eval(uv.x, uv.y),
                        key: key0 + i as u64,
                    }
                })
                .collect()
        };
        let mut l = arc(17.001, 20, false, 100);
        l.extend(arc(17.0, 13, true, 200));
        FaceDomain { loops: vec![l] }
    }

    fn mesh(deflection: f64) -> (FaceDomain, FaceMesh) {
        let s = plane();
        let d = annulus_sliver(&s);
        let params = MeshParams {
            deflection,
            angle: 0.5,
            max_face_points: 10_000,
        };
        let m = triangulate_face(&s, false, &d, &params).unwrap();
        (d, m)
    }

    /// The sliver welds: only its boundary points, every loop side one triangle's edge and
    /// every other edge two triangles', signed area that of the loop.
    #[test]
    fn crossing_sliver_uses_its_boundary_alone() {
        // The loop really conflicts: the strict triangulation rejects it.
        let (d, m) = mesh(0.05);
        let prep = domain::prepare(&d).unwrap();
        let verts = prep
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| cdt::Vert {
                pos: spade::Point2::new(p.uv.x, p.uv.y),
                id: i as u32,
            })
            .collect();
        let edges = prep
            .edges
            .iter()
            .map(|e| [e[0] as usize, e[1] as usize])
            .collect();
        assert!(cdt::build(verts, edges).is_err());

        assert!(!m.repaired);
        assert_eq!(m.points.len(), 33);
        assert!(m.points.iter().all(|p| p.key.is_some()));
        let mut uses: HashMap<(u64, u64), i32> = HashMap::new();
        let mut signed = 0.0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.points[i as usize].uv);
            signed += 0.5 * (b - a).perp_dot(c - a);
            for k in 0..3 {
                let (p, q) = (t[k] as usize, t[(k + 1) % 3] as usize);
                let (kp, kq) = (m.points[p].key.unwrap(), m.points[q].key.unwrap());
                *uses.entry((kp.min(kq), kp.max(kq))).or_default() += 1;
            }
        }
        let l = &d.loops[0];
        let mut loop_area = 0.0;
        for i in 0..l.len() {
            let (p, q) = (l[i], l[(i + 1) % l.len()]);
            loop_area += 0.5 * p.uv.perp_dot(q.uv);
            assert_eq!(uses.remove(&(p.key.min(q.key), p.key.max(q.key))), Some(1));
        }
        assert!(uses.values().all(|&n| n == 2), "{uses:?}");
        assert!((signed - loop_area).abs() < 1e-9 * loop_area.abs().max(1.0));
    }

    /// Negative control: with a deflection below the folds' height (the chords' sagitta)
    /// the face is not taken for a sliver and goes to the repair, split points and all.
    #[test]
    fn folds_higher_than_the_deflection_are_repaired() {
        let (_, m) = mesh(0.001);
        assert!(m.repaired);
        assert!(m.points.iter().any(|p| p.key.is_none()));
    }
}
