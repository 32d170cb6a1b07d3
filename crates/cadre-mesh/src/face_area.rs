//! Face areas for measuring: the exact area of a trimmed face on its surface, worked out over
//! the face's tessellation in (u, v), and the area of the flat triangles for comparison.
//!
//! The exact area integrates `|∂S/∂u × ∂S/∂v|` over the triangles' (u, v) region, so it is
//! exact up to the trim polygon: where a trim curve is curved in (u, v), the region misses
//! or gains the slivers between the curve and its chords (of the order of the deflection
//! times the boundary length, as for the flat area of a planar face).

use std::collections::{HashMap, HashSet};

use cadre_brep::{FaceId, Model};
use cadre_geom::{Surface, Vec2};

use crate::face::{FaceMesh, MeshPoint};
use crate::periodic::{unwrapped_surface, uv_bounds};

/// The area of face `face` on its exact surface, from its tessellation `mesh`: the integral
/// of `|∂S/∂u × ∂S/∂v|` over each triangle's (u, v) region by a 7-point Gauss rule (exact for
/// integrands of degree 5), in model units squared.
///
/// The triangulator leaves out triangles that collapse in 3D (two corners welded at a pole or
/// a collapsed seam), but their (u, v) region still has area on the surface near a pole; those
/// notches in the mesh boundary (a boundary path `a → c → b` turning inward with `a` and `b`
/// welded together) are integrated as well.
///
/// Falls back to [`mesh_area`] when the face or its surface is not in `model`, a point's
/// (u, v) is not finite, or the surface does not evaluate finitely on the mesh.
pub fn face_area(model: &Model, face: FaceId, mesh: &FaceMesh) -> f64 {
    exact_area(model, face, mesh).unwrap_or_else(|| mesh_area(mesh))
}

/// The total area of the mesh's flat triangles, in model units squared (triangles with a
/// corner index outside `mesh.points` are skipped).
pub fn mesh_area(mesh: &FaceMesh) -> f64 {
    mesh.triangles
        .iter()
        .filter_map(|t| corners(mesh, t))
        .map(|[a, b, c]| 0.5 * (b.xyz - a.xyz).cross(c.xyz - a.xyz).length())
        .sum()
}

/// [`face_area`] when it can be worked out on the surface.
fn exact_area(model: &Model, face: FaceId, mesh: &FaceMesh) -> Option<f64> {
    let f = model.faces.get(face.index())?;
    let surface = model.surfaces.get(f.surface.index())?;
    if mesh.points.iter().any(|p| !p.uv.is_finite()) {
        return None;
    }
    // The triangulation may run past the domain of a closed B-spline surface; evaluate on
    // the same extended surface the mesher used.
    let (lo, hi) = uv_bounds(mesh.points.iter().map(|p| p.uv));
    let extended = unwrapped_surface(surface, lo, hi);
    let surface = extended.as_ref().unwrap_or(surface);

    let rule = triangle_rule();
    let mut total = 0.0;
    for t in &mesh.triangles {
        if let Some([a, b, c]) = corners(mesh, t) {
            total += integrate(surface, &rule, [a.uv, b.uv, c.uv]);
        }
    }
    for [a, c, b] in notches(mesh) {
        total += integrate(surface, &rule, [a, c, b]);
    }
    total.is_finite().then_some(total)
}

/// The three corners of a triangle, `None` when an index is out of range.
fn corners<'m>(mesh: &'m FaceMesh, t: &[u32; 3]) -> Option<[&'m MeshPoint; 3]> {
    let p = |i: u32| mesh.points.get(i as usize);
    Some([p(t[0])?, p(t[1])?, p(t[2])?])
}

/// `∫ |S_u × S_v|` over the (u, v) triangle `uv`.
fn integrate(surface: &Surface, rule: &[([f64; 3], f64); 7], uv: [Vec2; 3]) -> f64 {
    let area = 0.5 * (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
    if area == 0.0 {
        return 0.0;
    }
    area * rule
        .iter()
        .map(|&([l0, l1, l2], w)| {
            let p = uv[0] * l0 + uv[1] * l1 + uv[2] * l2;
            let d = surface.derivs(p.x, p.y);
            w * d.du.cross(d.dv).length()
        })
        .sum::<f64>()
}

/// The 7-point degree-5 rule on a triangle (Radon): barycentric points and weights summing
/// to 1.
fn triangle_rule() -> [([f64; 3], f64); 7] {
    let s = 15f64.sqrt();
    let (a1, b1, w1) = (
        (6.0 - s) / 21.0,
        (9.0 + 2.0 * s) / 21.0,
        (155.0 - s) / 1200.0,
    );
    let (a2, b2, w2) = (
        (6.0 + s) / 21.0,
        (9.0 - 2.0 * s) / 21.0,
        (155.0 + s) / 1200.0,
    );
    let third = 1.0 / 3.0;
    [
        ([third, third, third], 9.0 / 40.0),
        ([b1, a1, a1], w1),
        ([a1, b1, a1], w1),
        ([a1, a1, b1], w1),
        ([b2, a2, a2], w2),
        ([a2, b2, a2], w2),
        ([a2, a2, b2], w2),
    ]
}

/// The (u, v) triangles the triangulator left out because two corners are welded (a pole, a
/// collapsed seam): with every triangle turned counter-clockwise in (u, v), the mesh lies to
/// the left of its boundary edges; a boundary path `a → c → b` turning right with `a` and `b`
/// carrying the same weld key (and `c` another) is such a notch. Where several dropped
/// triangles share an apex, the welded corners between lie on the straight trim segment
/// `a b`, so the one triangle `a c b` covers them all.
fn notches(mesh: &FaceMesh) -> Vec<[Vec2; 3]> {
    let uv = |i: u32| mesh.points[i as usize].uv;
    let mut half_edges = HashSet::new();
    for t in &mesh.triangles {
        if corners(mesh, t).is_none() {
            continue;
        }
        let [a, b, c] = *t;
        let ccw = (uv(b) - uv(a)).perp_dot(uv(c) - uv(a)) >= 0.0;
        let t = if ccw { [a, b, c] } else { [a, c, b] };
        for k in 0..3 {
            half_edges.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let boundary: Vec<(u32, u32)> = half_edges
        .iter()
        .copied()
        .filter(|&(a, b)| !half_edges.contains(&(b, a)))
        .collect();
    let mut outgoing: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in &boundary {
        outgoing.entry(a).or_default().push(b);
    }
    let key = |i: u32| mesh.points[i as usize].key;
    let mut out = Vec::new();
    for &(a, c) in &boundary {
        let Some(ka) = key(a) else {
            continue;
        };
        if key(c) == Some(ka) {
            continue;
        }
        for &b in outgoing.get(&c).into_iter().flatten() {
            let turn = (uv(c) - uv(a)).perp_dot(uv(b) - uv(c));
            if b != a && key(b) == Some(ka) && turn < 0.0 {
                out.push([uv(a), uv(c), uv(b)]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_brep::{Face, SurfaceId};
    use cadre_geom::{Frame, Vec3};
    use std::f64::consts::PI;

    fn point(surface: &Surface, u: f64, v: f64, key: Option<u64>) -> MeshPoint {
        MeshPoint {
            uv: Vec2::new(u, v),
            xyz: surface.eval(u, v),
            normal: Vec3::Z,
            key,
        }
    }

    fn model(surface: Surface) -> Model {
        let mut m = Model::default();
        m.surfaces.push(surface);
        m.faces.push(Face {
            surface: SurfaceId(0),
            same_sense: true,
            loops: Vec::new(),
            step_id: 1,
        });
        m
    }

    /// The rectangle `[0, du] × [0, dv]` of `surface` as two triangles, optionally reversed.
    fn rectangle(surface: &Surface, du: f64, dv: f64, reversed: bool) -> FaceMesh {
        let points = vec![
            point(surface, 0.0, 0.0, None),
            point(surface, du, 0.0, None),
            point(surface, du, dv, None),
            point(surface, 0.0, dv, None),
        ];
        let mut triangles = vec![[0, 1, 2], [0, 2, 3]];
        if reversed {
            triangles = vec![[0, 2, 1], [0, 3, 2]];
        }
        FaceMesh {
            points,
            triangles,
            ..FaceMesh::default()
        }
    }

    #[test]
    fn planar_face_areas_agree() {
        let plane = Surface::Plane {
            frame: Frame::WORLD,
        };
        let m = model(plane.clone());
        let mesh = rectangle(&plane, 2.0, 3.0, true);
        assert!((mesh_area(&mesh) - 6.0).abs() < 1e-14);
        assert!((face_area(&m, FaceId(0), &mesh) - 6.0).abs() < 1e-14);
    }

    #[test]
    fn cylinder_patch_is_exact_where_the_chords_fall_short() {
        let cyl = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 2.0,
        };
        let m = model(cyl.clone());
        let mesh = rectangle(&cyl, PI / 2.0, 5.0, false);
        let exact = 2.0 * PI / 2.0 * 5.0;
        assert!((face_area(&m, FaceId(0), &mesh) - exact).abs() < 1e-12 * exact);
        let flat = mesh_area(&mesh);
        assert!((flat - 2.0 * 2f64.sqrt() * 5.0).abs() < 1e-12 && flat < exact);
    }

    #[test]
    fn a_notch_at_a_pole_is_filled() {
        // A sphere's cap above v = 1.2, written as the triangulator leaves it: the pole edge
        // (u from 0 to 2π at v = π/2) welded into one point, so the triangle on it is gone.
        let r = 3.0;
        let sphere = Surface::Sphere {
            frame: Frame::WORLD,
            radius: r,
        };
        let m = model(sphere.clone());
        let (v0, top) = (1.2, PI / 2.0);
        let tau = 2.0 * PI;
        let mesh = FaceMesh {
            points: vec![
                point(&sphere, 0.0, v0, Some(1)),
                point(&sphere, tau, v0, Some(1)),
                point(&sphere, tau, top, Some(7)),
                point(&sphere, 0.0, top, Some(7)),
                point(&sphere, PI, v0, Some(2)),
            ],
            // Kept: the two triangles on the bottom edge; dropped: [2, 3, 4] (two pole keys).
            triangles: vec![[0, 4, 3], [4, 1, 2]],
            ..FaceMesh::default()
        };
        let exact_over_uv = |v_lo: f64, v_hi: f64| r * r * tau * (v_hi.sin() - v_lo.sin());
        let area = face_area(&m, FaceId(0), &mesh);
        // Exact over the whole (u, v) rectangle up to the 7-point rule's error on these big
        // triangles.
        let want = exact_over_uv(v0, top);
        assert!((area - want).abs() < 1e-3 * want, "{area} vs {want}");
        // Without the notch the same triangles give markedly less.
        let rule = triangle_rule();
        let kept: f64 = mesh
            .triangles
            .iter()
            .map(|t| integrate(&sphere, &rule, t.map(|i| mesh.points[i as usize].uv)))
            .sum();
        assert!(kept < 0.8 * want);
    }

    #[test]
    fn bad_input_falls_back_to_the_flat_area() {
        let plane = Surface::Plane {
            frame: Frame::WORLD,
        };
        let m = model(plane.clone());
        let mut mesh = rectangle(&plane, 1.0, 1.0, false);
        assert_eq!(face_area(&m, FaceId(5), &mesh), mesh_area(&mesh));
        mesh.points[0].uv = Vec2::NAN;
        assert_eq!(face_area(&m, FaceId(0), &mesh), mesh_area(&mesh));
        mesh.triangles.push([0, 1, 99]);
        assert!((mesh_area(&mesh) - 1.0).abs() < 1e-15);
        assert_eq!(face_area(&m, FaceId(0), &FaceMesh::default()), 0.0);
    }
}
