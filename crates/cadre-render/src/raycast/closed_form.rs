//! Closed-form ray intersection and (u, v) inversion of planes, cylinders, cones and
//! spheres.

use cadre_geom::{Frame, Surface};
use glam::{DVec2, DVec3};

/// Whether `surface` is intersected in closed form here.
pub(super) fn handles(surface: &Surface) -> bool {
    matches!(
        surface,
        Surface::Plane { .. }
            | Surface::Cylinder { .. }
            | Surface::Cone { .. }
            | Surface::Sphere { .. }
    )
}

/// The (u, v) of a point `p` on a closed-form surface (as its parametrisation has them;
/// angles in (−π, π]).
pub(super) fn uv_of(surface: &Surface, p: DVec3) -> Option<DVec2> {
    let local = |frame: &Frame| {
        let q = p - frame.origin;
        DVec3::new(q.dot(frame.x), q.dot(frame.y), q.dot(frame.z))
    };
    match surface {
        Surface::Plane { frame } => {
            let q = local(frame);
            Some(DVec2::new(q.x, q.y))
        }
        Surface::Cylinder { frame, .. } => {
            let q = local(frame);
            Some(DVec2::new(q.y.atan2(q.x), q.z))
        }
        Surface::Cone {
            frame,
            radius,
            semi_angle,
        } => {
            // Beyond the apex the radius r + v tan α is negative: the angle is opposite.
            let q = local(frame);
            let flip = if radius + q.z * semi_angle.tan() < 0.0 {
                std::f64::consts::PI
            } else {
                0.0
            };
            Some(DVec2::new(q.y.atan2(q.x) + flip, q.z))
        }
        Surface::Sphere { frame, radius } => {
            let q = local(frame);
            Some(DVec2::new(
                q.y.atan2(q.x),
                (q.z / radius).clamp(-1.0, 1.0).asin(),
            ))
        }
        _ => None,
    }
}

/// Ray parameters where `o + t d` meets the surface (closed form; empty for other types).
pub(super) fn hits(surface: &Surface, o: DVec3, d: DVec3) -> Vec<f64> {
    let local = |frame: &cadre_geom::Frame| {
        let q = o - frame.origin;
        (
            DVec3::new(q.dot(frame.x), q.dot(frame.y), q.dot(frame.z)),
            DVec3::new(d.dot(frame.x), d.dot(frame.y), d.dot(frame.z)),
        )
    };
    match surface {
        Surface::Plane { frame } => {
            let (q, e) = local(frame);
            if e.z.abs() < 1e-300 {
                vec![]
            } else {
                vec![-q.z / e.z]
            }
        }
        Surface::Cylinder { frame, radius } => {
            let (q, e) = local(frame);
            quadratic(
                e.x * e.x + e.y * e.y,
                2.0 * (q.x * e.x + q.y * e.y),
                q.x * q.x + q.y * q.y - radius * radius,
            )
        }
        Surface::Sphere { frame, radius } => {
            let (q, e) = local(frame);
            quadratic(e.dot(e), 2.0 * q.dot(e), q.dot(q) - radius * radius)
        }
        Surface::Cone {
            frame,
            radius,
            semi_angle,
        } => {
            // x² + y² = (r + z tan α)²
            let (q, e) = local(frame);
            let k = semi_angle.tan();
            let (r0, r1) = (radius + q.z * k, e.z * k);
            quadratic(
                e.x * e.x + e.y * e.y - r1 * r1,
                2.0 * (q.x * e.x + q.y * e.y - r0 * r1),
                q.x * q.x + q.y * q.y - r0 * r0,
            )
        }
        _ => vec![],
    }
}

/// Real roots of `a t² + b t + c`.
fn quadratic(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a.abs() < 1e-300 {
        return if b.abs() < 1e-300 {
            vec![]
        } else {
            vec![-c / b]
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    // The stable form: no cancellation between b and the root.
    let s = disc.sqrt();
    let q = -0.5 * (b + b.signum() * s);
    let mut roots = vec![q / a];
    if q != 0.0 {
        roots.push(c / q);
    }
    roots
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots_and_surface_hits() {
        let mut r = quadratic(1.0, -3.0, 2.0);
        r.sort_by(f64::total_cmp);
        assert_eq!(r, vec![1.0, 2.0]);
        assert!(quadratic(1.0, 0.0, 1.0).is_empty());
        let sphere = Surface::Sphere {
            frame: cadre_geom::Frame::WORLD,
            radius: 2.0,
        };
        let mut t = hits(&sphere, DVec3::new(-5.0, 0.0, 0.0), DVec3::X);
        t.sort_by(f64::total_cmp);
        assert!(
            (t[0] - 3.0).abs() < 1e-12 && (t[1] - 7.0).abs() < 1e-12,
            "{t:?}"
        );
        let cone = Surface::Cone {
            frame: cadre_geom::Frame::WORLD,
            radius: 1.0,
            semi_angle: std::f64::consts::FRAC_PI_4,
        };
        // At height 1 the cone's radius is 2.
        let mut t = hits(&cone, DVec3::new(-5.0, 0.0, 1.0), DVec3::X);
        t.sort_by(f64::total_cmp);
        assert!(
            (t[0] - 3.0).abs() < 1e-12 && (t[1] - 7.0).abs() < 1e-12,
            "{t:?}"
        );
    }
}
