//! Property tests of the quadric primitive: its class survives any affine map; its ray hits
//! lie on it, within its planes, in its box, and are the first ones (against a dense march
//! along the ray); carrying primitive and ray by one map carries the hit.

use cadre_geom::quadric::CutKind;
use cadre_geom::{CutQuadric, HalfSpace, Quadric, QuadricClass};
use glam::{DAffine3, DMat4, DQuat, DVec3, EulerRot};
use proptest::prelude::*;

/// One quadric of every real-surface class, unit-ish sized, with its class.
fn classes() -> Vec<(Quadric, QuadricClass)> {
    use QuadricClass as C;
    vec![
        (Quadric::ellipsoid(1.0, 0.6, 0.8), C::Ellipsoid),
        (
            Quadric::hyperboloid_one_sheet(0.5, 0.7, 0.6),
            C::HyperboloidOneSheet,
        ),
        (
            Quadric::hyperboloid_two_sheets(0.6, 0.5, 0.4),
            C::HyperboloidTwoSheets,
        ),
        (Quadric::cone(0.8, 0.6, 1.0), C::Cone),
        (
            Quadric::elliptic_paraboloid(0.7, 0.9),
            C::EllipticParaboloid,
        ),
        (
            Quadric::hyperbolic_paraboloid(0.8, 0.7),
            C::HyperbolicParaboloid,
        ),
        (Quadric::elliptic_cylinder(0.6, 0.9), C::EllipticCylinder),
        (
            Quadric::hyperbolic_cylinder(0.4, 0.5),
            C::HyperbolicCylinder,
        ),
        (Quadric::parabolic_cylinder(0.3), C::ParabolicCylinder),
        (
            Quadric::intersecting_planes(1.0, 0.7),
            C::IntersectingPlanes,
        ),
        (Quadric::parallel_planes(0.6), C::ParallelPlanes),
    ]
}

/// An affine map from 9 numbers in [0, 1): scales 0.3–3 (one may be negative: a mirror), a
/// rotation and a translation up to 50.
fn affine(x: &[f64]) -> DAffine3 {
    let s = |v: f64| 0.3 + 2.7 * v;
    let mirror = if x[8] < 0.3 { -1.0 } else { 1.0 };
    DAffine3::from_scale_rotation_translation(
        DVec3::new(mirror * s(x[0]), s(x[1]), s(x[2])),
        DQuat::from_euler(EulerRot::XYZ, 6.0 * x[3], 6.0 * x[4], 6.0 * x[5]),
        DVec3::new(x[6] - 0.5, x[7] - 0.5, x[8] - 0.5) * 100.0,
    )
}

/// The primitive in its own frame: class `k`, cut by 2–6 planes forming a box-like cell
/// (a slab along each axis, some tilted) so that every class is bounded.
fn primitive(k: usize, x: &[f64], kind: CutKind) -> CutQuadric {
    let (quadric, _) = classes()[k % classes().len()];
    let count = 6;
    let planes = (0..count)
        .map(|i| {
            let axis = DVec3::AXES[i / 2];
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            let tilt = DVec3::new(x[i] - 0.5, x[i + 1] - 0.5, x[i + 2] - 0.5) * 0.6;
            let normal = (axis + tilt - axis * tilt.dot(axis)) * sign;
            HalfSpace::through(axis * sign * (0.8 + x[i + 3]), normal)
        })
        .collect();
    CutQuadric {
        quadric,
        planes,
        kind,
    }
}

fn numbers() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.0..1.0f64, 24)
}

/// The first ray parameter in (0, end − 10⁻⁶ size) where a march of 4000 steps sees the
/// primitive's boundary crossed: the quadric's sign changing between two samples within the
/// planes (a patch), or the inside of the volume changing.
fn boundary_before(p: &CutQuadric, origin: DVec3, dir: DVec3, end: f64, size: f64) -> Option<f64> {
    let steps = 4000;
    let inside = |t: f64| {
        let q = origin + t * dir;
        (p.quadric.value(q) <= 0.0, p.within_planes(q, 0.0))
    };
    let margin = 1e-6 * size;
    let mut before = inside(0.0);
    for i in 1..=steps {
        let t = end * f64::from(i) / f64::from(steps);
        if t >= end - margin {
            break;
        }
        let now = inside(t);
        let crossed = match p.kind {
            CutKind::Patch => now.0 != before.0 && now.1 && before.1,
            CutKind::Volume => (now.0 && now.1) != (before.0 && before.1),
        };
        if crossed {
            return Some(t);
        }
        before = now;
    }
    None
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn the_class_is_read_from_the_matrix_after_any_affine_map(k in 0usize..11, x in numbers()) {
        let (q, class) = classes()[k];
        let moved = q.transformed_affine(affine(&x)).unwrap();
        prop_assert_eq!(moved.class(), class);
        let scaled = Quadric { matrix: moved.matrix * (1e-3 + 1e3 * x[20]) };
        prop_assert_eq!(scaled.class(), class);
    }

    #[test]
    fn hits_are_on_the_primitive_first_and_in_its_box(
        k in 0usize..11, x in numbers(), volume in any::<bool>()
    ) {
        let kind = if volume { CutKind::Volume } else { CutKind::Patch };
        let m = affine(&x[12..]);
        let Some(p) = primitive(k, &x, kind).transformed(DMat4::from(m)) else {
            return Ok(());
        };
        let Ok(bounds) = p.bounds(1e6) else {
            return Ok(());
        };
        let (lo, hi) = bounds.aabb();
        let size = (hi - lo).max_element();
        // A ray from outside the box towards a point in it.
        let dir = DVec3::new(x[0] - 0.5, x[3] - 0.5, x[6] - 0.5).normalize_or(DVec3::Z);
        let target = lo + (hi - lo) * DVec3::new(x[9], x[10], x[11]);
        let origin = target - dir * 3.0 * size;
        let hit = p.hit(origin, dir, 0.0);
        if let Some(h) = hit {
            let y = bounds.rotation.transpose() * (h.point - bounds.centre);
            let pad = 1e-7 * size;
            prop_assert!(y.cmpge(bounds.lo - pad).all() && y.cmple(bounds.hi + pad).all(), "outside its box");
            prop_assert!(p.within_planes(h.point, 1e-9 * size));
            if h.boundary == cadre_geom::quadric::HitBoundary::Quadric {
                let g = p.quadric.gradient(h.point).length();
                prop_assert!(p.quadric.value(h.point).abs() <= 1e-9 * g * size, "not on the quadric");
            }
        }
        // The dense march: no boundary point of the primitive before the hit (nor any when
        // it reports none).
        let end = hit.map_or(6.0 * size, |h| h.t);
        let early = boundary_before(&p, origin, dir, end, size);
        prop_assert!(early.is_none(), "a boundary at t ≈ {:?} before the hit at {end}", early);
    }

    #[test]
    fn a_map_carries_the_hit(k in 0usize..11, x in numbers()) {
        let p = primitive(k, &x, CutKind::Patch);
        let m = affine(&x[12..]);
        let moved = p.transformed(DMat4::from(m)).unwrap();
        let o = DVec3::new(x[0] - 0.5, x[1] - 0.5, -4.0);
        let d = DVec3::new(x[2] - 0.5, x[3] - 0.5, 1.0);
        let (Some(a), Some(b)) = (p.hit(o, d, 0.0), moved.hit(m.transform_point3(o), m.transform_vector3(d), 0.0)) else {
            return Ok(());
        };
        // Near-tangent rays may legitimately differ; rays crossing cleanly must not.
        let grazing = a.normal.dot(d.normalize()).abs() < 1e-3;
        if !grazing {
            prop_assert!((a.t - b.t).abs() < 1e-8 * (1.0 + a.t.abs()), "{} vs {}", a.t, b.t);
        }
    }
}

#[test]
fn an_unbounded_primitive_and_an_empty_one_are_told_apart() {
    let open = CutQuadric {
        quadric: Quadric::cylinder(1.0),
        planes: vec![HalfSpace::through(DVec3::ZERO, DVec3::Z)],
        kind: CutKind::Patch,
    };
    assert!(matches!(
        open.bounds(1e6),
        Err(cadre_geom::quadric::QuadricBoundsError::Unbounded { axis: 2 })
    ));
}

#[test]
fn the_march_catches_a_hit_reported_behind_the_first() {
    // Negative control of the march: a sphere's back root reported as its hit.
    let sphere = CutQuadric {
        quadric: Quadric::sphere(1.0),
        planes: vec![],
        kind: CutKind::Patch,
    };
    let (o, d) = (DVec3::new(0.1, 0.2, -5.0), DVec3::Z);
    let front = sphere.hit(o, d, 0.0).unwrap();
    assert!(boundary_before(&sphere, o, d, front.t, 2.0).is_none());
    let back = sphere.hit(o, d, front.t + 1e-6).unwrap();
    assert!(boundary_before(&sphere, o, d, back.t, 2.0).is_some());
}
