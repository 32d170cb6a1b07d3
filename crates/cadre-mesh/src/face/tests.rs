//! End-to-end tests of [`triangulate_face`] on analytic surfaces: exact areas, chordal
//! deviation measured against the true surface, welding at seams and poles, orientation,
//! and rejection of bad input.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use cadre_geom::{BSplineSurface, Frame, Surface, Vec2, Vec3};
use proptest::prelude::*;

use super::*;

/// A weld key derived from the exact bits of a position, so that points meant to coincide
/// (seams, poles) get the same key when the test computes identical positions for them.
fn key_of(p: Vec3) -> u64 {
    let h = |x: f64| (x + 0.0).to_bits();
    h(p.x) ^ h(p.y).rotate_left(21) ^ h(p.z).rotate_left(42)
}

/// Points of the segment `a → b` split into `n` parts, without `b`.
fn side(a: Vec2, b: Vec2, n: usize, out: &mut Vec<Vec2>) {
    out.extend((0..n).map(|i| a + (b - a) * (i as f64 / n as f64)));
}

/// A loop through the corners `c`, side `i` split into `n[i]` segments, with positions
/// from `pos` and keys from those positions.
fn polygon(c: &[Vec2], n: &[usize], pos: impl Fn(Vec2) -> Vec3) -> Vec<BoundaryPoint> {
    let mut uv = Vec::new();
    for i in 0..c.len() {
        side(c[i], c[(i + 1) % c.len()], n[i], &mut uv);
    }
    uv.into_iter()
        .map(|uv| {
            // Sides walked in opposite directions round differently: snap before evaluating
            // so that the two sides of a seam get bit-identical positions.
            let snap = |x: f64| (x * 1e12).round() / 1e12;
            let xyz = pos(v2(snap(uv.x), snap(uv.y)));
            BoundaryPoint {
                uv,
                xyz,
                key: key_of(xyz),
            }
        })
        .collect()
}

fn v2(u: f64, v: f64) -> Vec2 {
    Vec2::new(u, v)
}

fn params(deflection: f64) -> MeshParams {
    MeshParams {
        deflection,
        angle: 0.5,
        max_face_points: 2_000_000,
    }
}

fn corners(m: &FaceMesh, t: &[u32; 3]) -> [Vec3; 3] {
    t.map(|i| m.points[i as usize].xyz)
}

fn area(m: &FaceMesh) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = corners(m, t);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// Largest `dist(p)` over a dense barycentric sample of every triangle.
fn max_deviation(m: &FaceMesh, dist: impl Fn(Vec3) -> f64) -> f64 {
    const K: usize = 8;
    let mut worst: f64 = 0.0;
    for t in &m.triangles {
        let [a, b, c] = corners(m, t);
        for i in 0..=K {
            for j in 0..=K - i {
                let (s, r) = (i as f64 / K as f64, j as f64 / K as f64);
                worst = worst.max(dist(a + (b - a) * s + (c - a) * r));
            }
        }
    }
    worst
}

/// Checks structure every mesh must have: valid indices, unit normals, boundary points
/// kept with their keys, no triangle with two welded corners, every triangle facing the
/// side of its corner normals.
fn check_common(m: &FaceMesh, d: &FaceDomain) {
    assert!(!m.repaired, "clean loops went through the repair");
    let by_key: HashMap<u64, Vec3> = m
        .points
        .iter()
        .filter_map(|p| p.key.map(|k| (k, p.xyz)))
        .collect();
    for p in d.loops.iter().flatten() {
        assert_eq!(by_key.get(&p.key), Some(&p.xyz), "boundary point lost");
    }
    for p in &m.points {
        assert!(
            (p.normal.length() - 1.0).abs() < 1e-9,
            "normal {:?}",
            p.normal
        );
    }
    for t in &m.triangles {
        assert!(t.iter().all(|&i| (i as usize) < m.points.len()));
        let k = t.map(|i| m.points[i as usize].key);
        for i in 0..3 {
            assert!(
                k[i].is_none() || k[i] != k[(i + 1) % 3],
                "welded triangle kept"
            );
        }
        let [a, b, c] = corners(m, t);
        let n = (b - a).cross(c - a);
        assert!(n.length() > 0.0, "zero-area triangle");
        let avg: Vec3 = t.iter().map(|&i| m.points[i as usize].normal).sum();
        assert!(n.dot(avg) > 0.0, "triangle faces away from its normals");
    }
}

/// Welds the mesh by key (boundary) and index (interior) and counts each undirected edge.
fn welded_edge_counts(m: &FaceMesh) -> HashMap<(u64, u64), usize> {
    let weld = |i: u32| m.points[i as usize].key.unwrap_or((1 << 63) | i as u64);
    let mut counts = HashMap::new();
    for t in &m.triangles {
        for i in 0..3 {
            let (a, b) = (weld(t[i]), weld(t[(i + 1) % 3]));
            *counts.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    counts
}

/// A tilted plane (shared with `repair_tests`).
pub(super) fn plane() -> Surface {
    Surface::Plane {
        frame: Frame::from_axis(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 1.0, 1.0),
            Some(Vec3::X),
        )
        .unwrap(),
    }
}

fn square_with_hole() -> FaceDomain {
    let s = plane();
    let pos = |uv: Vec2| s.eval(uv.x, uv.y);
    let outer = [v2(0.0, 0.0), v2(10.0, 0.0), v2(10.0, 10.0), v2(0.0, 10.0)];
    // The hole runs clockwise.
    let hole = [v2(3.0, 4.0), v2(3.0, 7.0), v2(6.0, 7.0), v2(6.0, 4.0)];
    FaceDomain {
        loops: vec![
            polygon(&outer, &[4, 4, 4, 4], pos),
            polygon(&hole, &[3, 3, 3, 3], pos),
        ],
    }
}

#[test]
fn plane_square_with_hole() {
    let s = plane();
    let d = square_with_hole();
    for reversed in [false, true] {
        let m = triangulate_face(&s, reversed, &d, &params(0.01)).unwrap();
        check_common(&m, &d);
        assert!(!m.truncated);
        assert!((area(&m) - 91.0).abs() < 1e-9, "area {}", area(&m));
        // Only the boundary: a plane needs no interior points.
        assert_eq!(m.points.len(), 28);
        assert!(m.points.iter().all(|p| p.key.is_some()));
        let z = Frame::from_axis(Vec3::ZERO, Vec3::ONE, None).unwrap().z;
        let want = if reversed { -z } else { z };
        for p in &m.points {
            assert!((p.normal - want).length() < 1e-12);
        }
        for t in &m.triangles {
            let c = t.iter().map(|&i| m.points[i as usize].uv).sum::<Vec2>() / 3.0;
            assert!(
                !(c.x > 3.0 && c.x < 6.0 && c.y > 4.0 && c.y < 7.0),
                "in hole"
            );
        }
        // Every boundary segment is a mesh edge used once; inner edges twice.
        let counts = welded_edge_counts(&m);
        assert_eq!(counts.values().filter(|&&c| c == 1).count(), 28);
        assert!(counts.values().all(|&c| c == 1 || c == 2));
    }
}

/// Cylinder of radius 5 about z (shared with `repair_tests`).
pub(super) fn cylinder() -> Surface {
    Surface::Cylinder {
        frame: Frame::WORLD,
        radius: 5.0,
    }
}

/// Half a cylinder of radius 5 and height 10, the arcs split finely enough for `defl`.
fn cylinder_patch(defl: f64) -> FaceDomain {
    let s = cylinder();
    let step = 2.0 * (1.0 - defl / 5.0f64).acos();
    let n = (PI / step).ceil() as usize;
    let c = [v2(0.0, 0.0), v2(PI, 0.0), v2(PI, 10.0), v2(0.0, 10.0)];
    FaceDomain {
        loops: vec![polygon(&c, &[n, 3, n, 3], |uv| s.eval(uv.x, uv.y))],
    }
}

#[test]
fn cylinder_patch_within_deflection() {
    let s = cylinder();
    for (defl, area_tol) in [(0.01, 2e-3), (0.001, 3e-4)] {
        let d = cylinder_patch(defl);
        let m = triangulate_face(&s, false, &d, &params(defl)).unwrap();
        check_common(&m, &d);
        let dev = max_deviation(&m, |p| (Vec2::new(p.x, p.y).length() - 5.0).abs());
        assert!(dev <= defl * 1.001, "deviation {dev} > {defl}");
        let exact = 50.0 * PI;
        let rel = (area(&m) - exact).abs() / exact;
        assert!(rel < area_tol, "area {} vs {exact}", area(&m));
        // A cylinder needs no interior points when its arcs are fine enough.
        let boundary = d.loops[0].len();
        assert!(
            m.points.len() <= boundary + boundary / 10,
            "{}",
            m.points.len()
        );
        for p in &m.points {
            let radial = Vec3::new(p.xyz.x, p.xyz.y, 0.0).normalize();
            assert!((p.normal - radial).length() < 1e-9);
        }
    }
}

/// bug29478.stp: edges written 16× the deflection off their face's surface. Refinement cannot
/// move boundary points, so it must measure triangles from the surface points of their
/// corners; measuring from the stray corners it chased the gap with thousands of slivers and
/// the area grew 0.27 %.
#[test]
fn boundary_off_the_surface_is_not_chased_by_refinement() {
    let s = cylinder();
    let defl = 0.01;
    let mut d = cylinder_patch(defl);
    let on_surface = d.loops[0].len();
    // Push the arcs' inner points 10 deflections outwards, as a sloppy edge curve would.
    for p in &mut d.loops[0] {
        if p.uv.x > 1e-9 && p.uv.x < PI - 1e-9 {
            p.xyz += Vec3::new(p.xyz.x, p.xyz.y, 0.0).normalize() * 10.0 * defl;
        }
    }
    let m = triangulate_face(&s, false, &d, &params(defl)).unwrap();
    assert!(
        m.points.len() <= on_surface + on_surface / 10,
        "{} points for {on_surface} boundary points",
        m.points.len()
    );
    let dev = crate::deviation::sampled_deviation(&s, &m);
    assert!(dev.boundary_gap > 9.0 * defl, "{dev:?}");
    assert!(dev.distance > 5.0 * defl, "{dev:?}");
    assert!(dev.interpolation <= defl * 1.001, "{dev:?}");
}

/// trj5_k1-al-214.stp: a degree-1 B-spline strip folds at every knot. Normals across a fold
/// differ at any distance, so the angle test must not chase it (it gave one face 17,142
/// triangles); the folds' chords are tested where they cross them.
#[test]
fn creases_of_a_folded_strip_are_not_refined_away() {
    let spans = 8;
    let net = vec![
        (0..=spans)
            .map(|j| Vec3::new(0.0, j as f64, (j % 2) as f64))
            .collect(),
        (0..=spans)
            .map(|j| Vec3::new(2.0, j as f64, (j % 2) as f64))
            .collect(),
    ];
    let mut v_knots = vec![0.0];
    v_knots.extend((0..=spans).map(f64::from));
    v_knots.push(spans as f64);
    let s = Surface::BSpline(Box::new(
        BSplineSurface::try_new(1, 1, vec![0.0, 0.0, 1.0, 1.0], v_knots, net, None).unwrap(),
    ));
    let c = [v2(0.0, 0.0), v2(1.0, 0.0), v2(1.0, 8.0), v2(0.0, 8.0)];
    let d = FaceDomain {
        loops: vec![polygon(&c, &[1, 8, 1, 8], |uv| s.eval(uv.x, uv.y))],
    };
    let m = triangulate_face(&s, false, &d, &params(0.01)).unwrap();
    check_common(&m, &d);
    assert!(m.points.len() <= 40, "{} points", m.points.len());
    let dev = crate::deviation::sampled_deviation(&s, &m);
    assert!(dev.distance <= 0.01, "{dev:?}");
    // Each span is a flat 2 × √2 parallelogram.
    let exact = 8.0 * 2.0 * 2f64.sqrt();
    assert!((area(&m) - exact).abs() < 1e-9 * exact, "{}", area(&m));
}

#[test]
fn reversed_face_flips_triangles_and_normals() {
    let s = cylinder();
    let d = cylinder_patch(0.01);
    let fwd = triangulate_face(&s, false, &d, &params(0.01)).unwrap();
    let rev = triangulate_face(&s, true, &d, &params(0.01)).unwrap();
    check_common(&rev, &d);
    assert_eq!(fwd.points.len(), rev.points.len());
    assert_eq!(fwd.triangles.len(), rev.triangles.len());
    for (f, r) in fwd.triangles.iter().zip(&rev.triangles) {
        assert_eq!([f[0], f[2], f[1]], *r);
    }
    for p in &rev.points {
        let radial = Vec3::new(p.xyz.x, p.xyz.y, 0.0).normalize();
        assert!(p.normal.dot(radial) < -0.999_999);
    }
    for t in &rev.triangles {
        let [a, b, c] = corners(&rev, t);
        let centre = (a + b + c) / 3.0;
        let radial = Vec3::new(centre.x, centre.y, 0.0);
        assert!(
            (b - a).cross(c - a).dot(radial) < 0.0,
            "reversed triangle faces out"
        );
    }
}

/// The upper hemisphere of radius `r` as one rectangle in (u, v): equator at the bottom,
/// the seam on both sides (u = 0 and u = 2π weld), the pole as the whole top side.
fn hemisphere(r: f64, defl: f64, pole_segments: Option<usize>) -> (Surface, FaceDomain) {
    let s = Surface::Sphere {
        frame: Frame::WORLD,
        radius: r,
    };
    let step = 2.0 * (1.0 - defl / r).acos();
    let nu = (TAU / step).ceil() as usize;
    let nv = (FRAC_PI_2 / step).ceil() as usize;
    let c = [
        v2(0.0, 0.0),
        v2(TAU, 0.0),
        v2(TAU, FRAC_PI_2),
        v2(0.0, FRAC_PI_2),
    ];
    let pos = |uv: Vec2| {
        if uv.y >= FRAC_PI_2 - 1e-12 {
            Vec3::new(0.0, 0.0, r)
        } else {
            // Evaluate the seam at u = 0 so both sides get bit-identical positions.
            s.eval(if uv.x >= TAU - 1e-12 { 0.0 } else { uv.x }, uv.y)
        }
    };
    let lp = polygon(&c, &[nu, nv, pole_segments.unwrap_or(nu), nv], pos);
    (s, FaceDomain { loops: vec![lp] })
}

#[test]
fn hemisphere_with_pole_and_seam() {
    // The pole line sampled like the equator, and as one segment (a degenerate edge).
    for pole_segments in [None, Some(1)] {
        hemisphere_case(pole_segments);
    }
}

fn hemisphere_case(pole_segments: Option<usize>) {
    let r = 10.0;
    let defl = 0.01;
    let (s, d) = hemisphere(r, defl, pole_segments);
    let m = triangulate_face(&s, false, &d, &params(defl)).unwrap();
    check_common(&m, &d);
    assert!(!m.truncated);
    let exact = TAU * r * r;
    let rel = (area(&m) - exact).abs() / exact;
    assert!(rel < 2e-3, "area {} vs {exact}", area(&m));
    let dev = max_deviation(&m, |p| (p.length() - r).abs());
    assert!(dev <= defl * 1.05, "deviation {dev}");
    // Outward normals; at the pole +z.
    for p in &m.points {
        assert!(p.normal.dot(p.xyz.normalize()) > 0.999_999, "{:?}", p);
    }
    // Welded by key, the mesh is a disc: the equator edges once, every other edge twice
    // (the seam's two sides and the pole's fan included).
    let counts = welded_edge_counts(&m);
    let equator = d.loops[0].iter().filter(|p| p.uv.y == 0.0).count() - 1;
    assert_eq!(counts.values().filter(|&&c| c == 1).count(), equator);
    assert!(
        counts.values().all(|&c| c == 1 || c == 2),
        "non-manifold edge"
    );
    // Interior points are spread, not piled up at the pole: the cap within 0.1 rad of it
    // (0.5 % of the area) holds the pole ring and little else.
    let interior = m.points.iter().filter(|p| p.key.is_none()).count();
    let near_pole = m
        .points
        .iter()
        .filter(|p| p.key.is_none() && p.uv.y > FRAC_PI_2 - 0.1)
        .count();
    assert!(
        near_pole * 10 < interior,
        "{near_pole} of {interior} near the pole"
    );
}

#[test]
fn closed_torus_is_watertight() {
    let s = Surface::Torus {
        frame: Frame::WORLD,
        major_radius: 4.0,
        minor_radius: 1.0,
    };
    let defl = 0.005;
    // Boundary circles split finely enough: the outer equator (radius 5) and the meridian.
    let nu = (TAU / (2.0 * (1.0 - defl / 5.0f64).acos())).ceil() as usize;
    let nv = (TAU / (2.0 * (1.0 - defl).acos())).ceil() as usize;
    let c = [v2(0.0, 0.0), v2(TAU, 0.0), v2(TAU, TAU), v2(0.0, TAU)];
    let pos = |uv: Vec2| {
        let w = |x: f64| if x >= TAU - 1e-12 { 0.0 } else { x };
        s.eval(w(uv.x), w(uv.y))
    };
    let d = FaceDomain {
        loops: vec![polygon(&c, &[nu, nv, nu, nv], pos)],
    };
    let m = triangulate_face(&s, false, &d, &params(defl)).unwrap();
    check_common(&m, &d);
    let counts = welded_edge_counts(&m);
    assert!(
        counts.values().all(|&c| c == 2),
        "open or non-manifold torus"
    );
    let exact = 4.0 * PI * PI * 4.0 * 1.0;
    assert!((area(&m) - exact).abs() / exact < 2e-3);
    let dev = max_deviation(&m, |p| {
        let q = Vec2::new(p.x, p.y).length() - 4.0;
        (Vec2::new(q, p.z).length() - 1.0).abs()
    });
    assert!(dev <= defl * 1.05, "deviation {dev}");
}

#[test]
fn paraboloid_bezier_within_deflection() {
    // z = x² + y² over [0, 1]² as a biquadratic Bézier patch.
    let xs = [0.0, 0.5, 1.0];
    let zs = [0.0, 0.0, 1.0];
    let net = (0..3)
        .map(|i| {
            (0..3)
                .map(|j| Vec3::new(xs[i], xs[j], zs[i] + zs[j]))
                .collect()
        })
        .collect();
    let s = Surface::BSpline(Box::new(BSplineSurface::bezier(net, None).unwrap()));
    let defl = 0.001;
    let c = [v2(0.0, 0.0), v2(1.0, 0.0), v2(1.0, 1.0), v2(0.0, 1.0)];
    let d = FaceDomain {
        loops: vec![polygon(&c, &[20, 20, 20, 20], |uv| s.eval(uv.x, uv.y))],
    };
    let m = triangulate_face(&s, false, &d, &params(defl)).unwrap();
    check_common(&m, &d);
    assert!(m.points.len() > 80, "no interior points on a curved patch");
    let dev = max_deviation(&m, |p| {
        let gap = (p.z - (p.x * p.x + p.y * p.y)).abs();
        // Vertical gap to normal distance (first order).
        gap / (1.0 + 4.0 * (p.x * p.x + p.y * p.y)).sqrt()
    });
    assert!(dev <= defl * 1.1, "deviation {dev}");
    for p in &m.points {
        assert!(p.normal.z > 0.0);
    }
}

#[test]
fn point_budget_truncates() {
    let (s, d) = hemisphere(10.0, 0.01, None);
    let mut p = params(1e-5);
    p.max_face_points = 3000;
    let m = triangulate_face(&s, false, &d, &p).unwrap();
    assert!(m.truncated);
    assert!(m.points.len() <= 3000);
    check_common(&m, &d);
}

#[test]
fn bad_input_is_an_error_or_repaired() {
    let s = plane();
    let bp = |u: f64, v: f64| BoundaryPoint {
        uv: v2(u, v),
        xyz: Vec3::new(u, v, 0.0),
        key: key_of(Vec3::new(u, v, 0.0)),
    };
    let p = params(0.01);
    let mut nan = vec![bp(0.0, 0.0), bp(1.0, 0.0), bp(1.0, 1.0)];
    nan[1].uv.x = f64::NAN;
    let mut inf = vec![bp(0.0, 0.0), bp(1.0, 0.0), bp(1.0, 1.0)];
    inf[2].xyz.z = f64::INFINITY;
    let cases: Vec<(Vec<Vec<BoundaryPoint>>, FaceMeshError)> = vec![
        (vec![nan], FaceMeshError::NonFinite),
        (vec![inf], FaceMeshError::NonFinite),
        (vec![], FaceMeshError::EmptyDomain),
        (
            vec![vec![bp(0.0, 0.0), bp(1.0, 0.0)]],
            FaceMeshError::EmptyDomain,
        ),
        (
            vec![vec![bp(0.0, 0.0), bp(1.0, 1.0), bp(2.0, 2.0)]],
            FaceMeshError::EmptyDomain,
        ),
    ];
    for (loops, want) in cases {
        let d = FaceDomain { loops };
        assert_eq!(triangulate_face(&s, false, &d, &p).unwrap_err(), want);
    }
    // A bow tie crosses itself; a hole crossing the outer loop crosses it: both are
    // repaired, not rejected (see `repair_tests`).
    let bow = vec![bp(0.0, 0.0), bp(2.0, 1.0), bp(2.0, 0.0), bp(0.0, 1.5)];
    let outer = vec![bp(0.0, 0.0), bp(2.0, 0.0), bp(2.0, 2.0), bp(0.0, 2.0)];
    let hole = vec![bp(1.0, 1.0), bp(1.0, 3.0), bp(1.5, 3.0), bp(1.5, 1.0)];
    for loops in [vec![bow], vec![outer, hole]] {
        let d = FaceDomain { loops };
        for s in [&s, &cylinder()] {
            let m = triangulate_face(s, false, &d, &p).unwrap();
            assert!(m.repaired);
            assert!(!m.triangles.is_empty());
        }
    }
}

#[test]
fn duplicate_points_and_slits_are_tolerated() {
    let s = plane();
    let pos = |uv: Vec2| s.eval(uv.x, uv.y);
    let bp = |u: f64, v: f64| {
        let xyz = pos(v2(u, v));
        BoundaryPoint {
            uv: v2(u, v),
            xyz,
            key: key_of(xyz),
        }
    };
    // Repeated points, the closing point repeated, and a slit (an edge used both ways).
    let outer = vec![
        bp(0.0, 0.0),
        bp(2.0, 0.0),
        bp(2.0, 0.0),
        bp(2.0, 2.0),
        bp(0.0, 2.0),
        bp(0.0, 0.0),
    ];
    let slit = vec![bp(0.5, 1.0), bp(1.5, 1.0)];
    let d = FaceDomain {
        loops: vec![outer, slit],
    };
    let m = triangulate_face(&s, false, &d, &params(0.01)).unwrap();
    check_common(&m, &d);
    assert!((area(&m) - 4.0).abs() < 1e-12);
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Convex polygons on a plane: exact area, every boundary point used, n − 2 triangles.
    #[test]
    fn convex_polygons_on_a_plane(
        angles in prop::collection::btree_set(0u32..3600, 3..40),
        rx in 0.1f64..100.0,
        ry in 0.1f64..100.0,
        cx in -1e3f64..1e3,
        cy in -1e3f64..1e3,
    ) {
        let s = plane();
        let uv: Vec<Vec2> = angles
            .iter()
            .map(|&a| {
                let t = a as f64 * TAU / 3600.0;
                v2(cx + rx * t.cos(), cy + ry * t.sin())
            })
            .collect();
        let n = uv.len();
        let shoelace: f64 = (0..n).map(|i| uv[i].perp_dot(uv[(i + 1) % n])).sum::<f64>() / 2.0;
        prop_assume!(shoelace > 1e-6 * rx * ry);
        let lp: Vec<BoundaryPoint> = uv
            .iter()
            .enumerate()
            .map(|(i, &uv)| BoundaryPoint { uv, xyz: s.eval(uv.x, uv.y), key: i as u64 })
            .collect();
        let d = FaceDomain { loops: vec![lp] };
        let m = triangulate_face(&s, false, &d, &params(0.01)).unwrap();
        prop_assert!((area(&m) - shoelace).abs() <= 1e-9 * shoelace.max(1.0));
        prop_assert_eq!(m.points.len(), n);
        prop_assert_eq!(m.triangles.len(), n - 2);
        let mut used = vec![false; n];
        for t in &m.triangles {
            for &i in t {
                used[m.points[i as usize].key.unwrap() as usize] = true;
            }
        }
        prop_assert!(used.iter().all(|&u| u));
        check_common(&m, &d);
    }

    /// Arbitrary point soups (self-intersecting, duplicated, collinear) on a curved surface
    /// never panic; when accepted, the mesh is well formed.
    #[test]
    fn random_loops_never_panic(
        pts in prop::collection::vec((0u8..6, 0u8..6), 0..12),
        holes in prop::collection::vec((0u8..6, 0u8..6), 0..6),
    ) {
        let s = cylinder();
        let mk = |p: &[(u8, u8)]| -> Vec<BoundaryPoint> {
            p.iter()
                .map(|&(a, b)| {
                    let uv = v2(a as f64 * 0.5, b as f64);
                    let xyz = s.eval(uv.x, uv.y);
                    BoundaryPoint { uv, xyz, key: key_of(xyz) }
                })
                .collect()
        };
        let d = FaceDomain { loops: vec![mk(&pts), mk(&holes)] };
        if let Ok(m) = triangulate_face(&s, false, &d, &params(0.01)) {
            for t in &m.triangles {
                prop_assert!(t.iter().all(|&i| (i as usize) < m.points.len()));
            }
            for p in &m.points {
                prop_assert!(p.xyz.is_finite() && (p.normal.length() - 1.0).abs() < 1e-9);
            }
        }
    }
}
