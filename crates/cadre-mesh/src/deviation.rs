//! How far a face mesh lies from its exact surface, sampled: the quality bar's "deviation of
//! triangles from the exact surface ≤ the deflection", measured by the corpus test and
//! `examples/face_debug`.

use cadre_geom::{Accuracy, Surface, Vec2, Vec3};

use crate::face::FaceMesh;
use crate::periodic::{unwrapped_surface, uv_bounds};

/// Barycentric weights sampled in each triangle: the centroid and the edge midpoints.
const SAMPLES: [[f64; 3]; 4] = [
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.5],
    [0.5, 0.0, 0.5],
];

/// The largest sampled distance of a face mesh from its surface, and the triangle it is in.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Largest distance of the triangles from the surface, model units.
    pub distance: f64,
    /// The triangle (indices into the mesh's points) where `distance` is; `None` for a mesh
    /// with no triangle.
    pub triangle: Option<[u32; 3]>,
    /// Largest distance with every corner first moved onto the surface at its (u, v): the
    /// error of the flat triangles themselves, which refinement answers for. It differs from
    /// `distance` only where the file's edges lie off the face's surface.
    pub interpolation: f64,
    /// The triangle where `interpolation` is.
    pub interpolation_triangle: Option<[u32; 3]>,
    /// Largest distance of a mesh point from the surface at its (u, v): how far the file's
    /// edges (the shared boundary points) stray from this face's surface.
    pub boundary_gap: f64,
}

/// The distance, along each triangle's normal, between the triangle and `surface` at the same
/// barycentric (u, v), over `SAMPLES` of every triangle, on the surface the mesher used
/// (closed B-splines repeated across their seam). At a pole or an apex the (u, v) of a vertex
/// is a convention, so a triangle touching one is measured by projecting its samples onto the
/// surface instead.
pub fn sampled_deviation(surface: &Surface, mesh: &FaceMesh) -> Deviation {
    let (lo, hi) = uv_bounds(mesh.points.iter().map(|p| p.uv));
    let extended = unwrapped_surface(surface, lo, hi);
    let surface = extended.as_ref().unwrap_or(surface);
    let singular = |uv: Vec2| {
        let d = surface.derivs(uv.x, uv.y);
        let (a, b) = (d.du.length(), d.dv.length());
        a.min(b) <= 1e-9 * a.max(b)
    };
    let gaps: Vec<Vec3> = mesh
        .points
        .iter()
        .map(|p| p.xyz - surface.eval(p.uv.x, p.uv.y))
        .collect();
    let mut worst = Deviation {
        boundary_gap: gaps
            .iter()
            .map(|g| g.length())
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max),
        ..Deviation::default()
    };
    let distance = |uv: Vec2, flat: Vec3, at_pole: bool, beat: f64| {
        if at_pole {
            surface
                .project(flat, Some((uv.x, uv.y)), Accuracy::default())
                .map_or(0.0, |(u, v)| (surface.eval(u, v) - flat).length())
        } else {
            local_distance(surface, uv, flat, beat)
        }
    };
    for t in &mesh.triangles {
        let q = t.map(|i| mesh.points[i as usize]);
        if (q[1].xyz - q[0].xyz)
            .cross(q[2].xyz - q[0].xyz)
            .try_normalize()
            .is_none()
        {
            continue;
        }
        let gap = t.map(|i| gaps[i as usize]);
        let at_pole = q.iter().any(|p| singular(p.uv));
        for w in SAMPLES {
            let uv = q[0].uv * w[0] + q[1].uv * w[1] + q[2].uv * w[2];
            let flat = q[0].xyz * w[0] + q[1].xyz * w[1] + q[2].xyz * w[2];
            let d = distance(uv, flat, at_pole, worst.distance);
            if d.is_finite() && d > worst.distance {
                worst.distance = d;
                worst.triangle = Some(*t);
            }
            let own_gap = gap[0] * w[0] + gap[1] * w[1] + gap[2] * w[2];
            let d = distance(uv, flat - own_gap, at_pole, worst.interpolation);
            if d.is_finite() && d > worst.interpolation {
                worst.interpolation = d;
                worst.interpolation_triangle = Some(*t);
            }
        }
    }
    worst
}

/// Distance from `q` to the surface point nearest it around `uv` (damped Gauss–Newton on the
/// squared distance, from `uv`, the sample's own parameters): the true distance where the
/// directional measures disagree (across a crease the surface normal and the triangle's are
/// far apart, and either direction overstates the gap). Only worked out when the plain
/// distance to `S(uv)`, an upper bound, exceeds `beat` (the worst found so far).
fn local_distance(surface: &Surface, uv: Vec2, q: Vec3, beat: f64) -> f64 {
    let mut uv = uv;
    let mut d = surface.derivs(uv.x, uv.y);
    let mut best = (d.point - q).length();
    if best.is_nan() || best <= beat {
        return best;
    }
    for _ in 0..12 {
        let r = d.point - q;
        let (a, b, c) = (d.du.dot(d.du), d.du.dot(d.dv), d.dv.dot(d.dv));
        let det = a * c - b * b;
        if det.is_nan() || det <= 1e-300 || best == 0.0 {
            break;
        }
        let (gu, gv) = (d.du.dot(r), d.dv.dot(r));
        let step = Vec2::new((c * gu - b * gv) / det, (a * gv - b * gu) / det);
        // Halve the step until the distance drops (the full step overshoots on strongly
        // curved or rational patches).
        let mut scale = 1.0;
        let mut improved = None;
        for _ in 0..12 {
            let next = uv - step * scale;
            let dn = surface.derivs(next.x, next.y);
            let dist = (dn.point - q).length();
            if dist < best {
                improved = Some((next, dn, dist));
                break;
            }
            scale *= 0.5;
        }
        let Some((next, dn, dist)) = improved else {
            break;
        };
        let converged = best - dist <= 1e-12 * (1.0 + best);
        (uv, d, best) = (next, dn, dist);
        if converged {
            break;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeshParams;
    use crate::face::{BoundaryPoint, FaceDomain, triangulate_face};
    use cadre_geom::Frame;

    #[test]
    fn a_meshed_sphere_cap_is_within_its_deflection_and_one_flat_triangle_is_not() {
        let sphere = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 5.0,
        };
        let corner = |u: f64, v: f64, key: u64| BoundaryPoint {
            uv: Vec2::new(u, v),
            xyz: sphere.eval(u, v),
            key,
        };
        let domain = FaceDomain {
            loops: vec![vec![
                corner(0.0, 0.0, 0),
                corner(1.0, 0.0, 1),
                corner(1.0, 1.0, 2),
                corner(0.0, 1.0, 3),
            ]],
        };
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.5,
            ..MeshParams::default()
        };
        // The boundary is coarse (straight chords of 5 mm), so only the inside is refined:
        // a bare triangle of the corners is far off, the refined mesh much closer.
        let refined = triangulate_face(&sphere, false, &domain, &params).unwrap();
        let coarse = FaceMesh {
            points: refined.points[..4].to_vec(),
            triangles: vec![[0, 1, 2]],
            ..FaceMesh::default()
        };
        let far = sampled_deviation(&sphere, &coarse);
        assert!(far.distance > 0.5, "{far:?}");
        assert_eq!(far.triangle, Some([0, 1, 2]));
        let near = sampled_deviation(&sphere, &refined);
        assert!(near.distance < far.distance, "{near:?} vs {far:?}");
    }
}
