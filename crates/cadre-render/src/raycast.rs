//! A CPU ray caster of the exact B-Rep: each face is its support surface, intersected in
//! closed form, cut by its trim loops. It is the independent oracle for the GPU's face-id
//! buffer (which draws the tessellation) and the reference for the exact-rendering work that
//! follows. Planes, cylinders, cones and spheres are supported; faces on other surfaces are
//! reported, not guessed.

use cadre_brep::trim::{TrimTolerance, face_trim};
use cadre_brep::{Body, FaceId, Model};
use cadre_geom::{Accuracy, Surface, Transform};
use cadre_mesh::MeshParams;
use cadre_mesh::edges::EdgeDiscretisation;
use glam::{DVec2, DVec3, DVec4};

use crate::Camera;

/// One face ready to be hit: its surface, its trim polygons in (u, v), its periods.
struct CastFace {
    step_id: u64,
    surface: Surface,
    loops: Vec<Vec<DVec2>>,
    period_u: Option<f64>,
    period_v: Option<f64>,
}

/// The ray caster of one model.
pub struct RayCaster {
    faces: Vec<CastFace>,
    /// Per part instance: world → part transform, and the indices of its faces.
    instances: Vec<(Transform, Vec<usize>)>,
    /// STEP ids of faces skipped (unsupported surface, or no trim).
    pub skipped: Vec<u64>,
}

impl RayCaster {
    /// Prepares every face of every part instance of `model`; trims are computed from edges
    /// sampled at `deflection` (model units).
    pub fn new(model: &Model, deflection: f64) -> RayCaster {
        let params = MeshParams {
            deflection,
            angle: 0.2,
            ..MeshParams::default()
        };
        let acc = Accuracy::default();
        let edges = EdgeDiscretisation::new(model, &params, acc);
        let tol = TrimTolerance {
            deflection,
            angle: 0.2,
            accuracy: acc,
            keep_exact: false,
        };
        let mut faces = Vec::new();
        let mut index_of = vec![None; model.faces.len()];
        let mut skipped = Vec::new();
        for (i, face) in model.faces.iter().enumerate() {
            let surface = model.surfaces[face.surface.index()].clone();
            let supported = matches!(
                surface,
                Surface::Plane { .. }
                    | Surface::Cylinder { .. }
                    | Surface::Cone { .. }
                    | Surface::Sphere { .. }
            );
            let trim = face_trim(model, FaceId(i as u32), &edges, &tol);
            match (supported, trim) {
                (true, Ok(trim)) => {
                    index_of[i] = Some(faces.len());
                    faces.push(CastFace {
                        step_id: face.step_id,
                        loops: trim
                            .loops
                            .iter()
                            .map(|l| l.polygon().iter().map(|p| p.uv).collect())
                            .collect(),
                        period_u: surface.u_period(),
                        period_v: surface.v_period(),
                        surface,
                    });
                }
                _ => skipped.push(face.step_id),
            }
        }
        let mut instances = Vec::new();
        model.visit_instances(|visit| {
            let mut ids = Vec::new();
            for body in &model.part(visit.part).bodies {
                let mut push = |f: FaceId| {
                    if let Some(k) = index_of[f.index()] {
                        ids.push(k);
                    }
                };
                match body {
                    Body::Solid(s) => {
                        for shell in model.solids[s.index()].shells() {
                            for &(f, _) in &model.shells[shell.index()].faces {
                                push(f);
                            }
                        }
                    }
                    Body::Shell(shell) => {
                        for &(f, _) in &model.shells[shell.index()].faces {
                            push(f);
                        }
                    }
                    Body::Face(f) => push(*f),
                    _ => {}
                }
            }
            if !ids.is_empty() {
                instances.push((visit.transform.inverse(), ids));
            }
        });
        RayCaster {
            faces,
            instances,
            skipped,
        }
    }

    /// Adds an analytic primitive, cast like a face with the primitive's face id: a sphere
    /// is its whole spherical surface, a rectangle its plane trimmed to it.
    pub fn add_primitive(&mut self, primitive: &crate::AnalyticPrimitive) {
        use crate::AnalyticShape;
        use std::f64::consts::{FRAC_PI_2, TAU};
        let frame = primitive.frame;
        // The trim: a rectangle of (u, v); a sphere's covers its whole domain.
        let (surface, (u0, u1), (v0, v1)) = match primitive.shape {
            AnalyticShape::Sphere { radius } => (
                Surface::Sphere { frame, radius },
                (-0.1, TAU + 0.1),
                (-FRAC_PI_2 - 0.1, FRAC_PI_2 + 0.1),
            ),
            AnalyticShape::Rectangle {
                half_width: a,
                half_height: b,
            } => (Surface::Plane { frame }, (-a, a), (-b, b)),
        };
        let rectangle = vec![
            DVec2::new(u0, v0),
            DVec2::new(u1, v0),
            DVec2::new(u1, v1),
            DVec2::new(u0, v1),
        ];
        self.faces.push(CastFace {
            step_id: u64::from(primitive.face_id),
            loops: vec![rectangle],
            period_u: surface.u_period(),
            period_v: surface.v_period(),
            surface,
        });
        self.instances
            .push((Transform::IDENTITY, vec![self.faces.len() - 1]));
    }

    /// The STEP id of the face seen at the centre of every pixel of a `width` × `height`
    /// image from `camera` (0 for background), row by row.
    pub fn face_ids(&self, camera: &Camera, width: u32, height: u32) -> Vec<u64> {
        self.hits(camera, width, height)
            .into_iter()
            .map(|h| h.map_or(0, |(id, _)| id))
            .collect()
    }

    /// The face (STEP id) and world point seen at the centre of every pixel, row by row.
    pub fn hits(&self, camera: &Camera, width: u32, height: u32) -> Vec<Option<(u64, DVec3)>> {
        self.hits_at(camera, width, height, DVec2::ZERO)
    }

    /// Per pixel, whether a true boundary (between two faces, or a face and the background)
    /// passes within `radius` pixels of its centre: whether the face seen at any of eight
    /// points on the circle of that radius about the centre differs from the one seen at the
    /// centre (a boundary crossing the disc between two of them unseen: a detail thinner than
    /// the sampling, is missed).
    pub fn near_boundary(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        radius: f64,
    ) -> Vec<bool> {
        let centre = self.face_ids_at(camera, width, height, DVec2::ZERO);
        let mut near = vec![false; centre.len()];
        for k in 0..8 {
            let angle = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let offset = DVec2::new(angle.cos(), angle.sin()) * radius;
            let ids = self.face_ids_at(camera, width, height, offset);
            for ((n, a), b) in near.iter_mut().zip(&centre).zip(&ids) {
                *n |= a != b;
            }
        }
        near
    }

    /// [`RayCaster::face_ids`] at `offset` pixels from each pixel's centre.
    fn face_ids_at(&self, camera: &Camera, width: u32, height: u32, offset: DVec2) -> Vec<u64> {
        self.hits_at(camera, width, height, offset)
            .into_iter()
            .map(|h| h.map_or(0, |(id, _)| id))
            .collect()
    }

    /// [`RayCaster::hits`] at `offset` pixels from each pixel's centre (x right, y down).
    fn hits_at(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        offset: DVec2,
    ) -> Vec<Option<(u64, DVec3)>> {
        let aspect = f64::from(width) / f64::from(height);
        let unproject = (camera.projection_matrix(aspect) * camera.view_rotation()).inverse();
        let mut out = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let ndc = DVec2::new(
                    (f64::from(x) + 0.5 + offset.x) / f64::from(width) * 2.0 - 1.0,
                    1.0 - (f64::from(y) + 0.5 + offset.y) / f64::from(height) * 2.0,
                );
                // Reverse Z: depth 1 is the near plane, 0 the far one.
                let near = unproject * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
                let far = unproject * DVec4::new(ndc.x, ndc.y, 0.0, 1.0);
                let (near, far) = (near.truncate() / near.w, far.truncate() / far.w);
                let origin = camera.eye + near;
                let dir = (far - near).normalize();
                out.push(self.cast(origin, dir).map(|(t, id)| (id, origin + dir * t)));
            }
        }
        out
    }

    /// The ray parameter and STEP id of the nearest face hit by the ray.
    fn cast(&self, origin: DVec3, dir: DVec3) -> Option<(f64, u64)> {
        let mut best = (f64::INFINITY, 0);
        for (to_part, ids) in &self.instances {
            let o = to_part.transform_point3(origin);
            let d = to_part.transform_vector3(dir);
            for &k in ids {
                let face = &self.faces[k];
                for t in hits(&face.surface, o, d) {
                    if t > 0.0 && t < best.0 && face.contains(o + d * t) {
                        best = (t, face.step_id);
                    }
                }
            }
        }
        best.0.is_finite().then_some(best)
    }
}

impl CastFace {
    /// Whether a point of the surface lies inside the trim (even-odd over the loops), trying
    /// the (u, v) a period either side on closed surfaces.
    fn contains(&self, p: DVec3) -> bool {
        let Some((u, v)) = self.surface.project(p, None, Accuracy::default()) else {
            return false;
        };
        let shifts = |period: Option<f64>| match period {
            Some(t) => vec![-t, 0.0, t],
            None => vec![0.0],
        };
        for du in shifts(self.period_u) {
            for dv in shifts(self.period_v) {
                if self.even_odd(DVec2::new(u + du, v + dv)) {
                    return true;
                }
            }
        }
        false
    }

    fn even_odd(&self, q: DVec2) -> bool {
        let mut inside = false;
        for poly in &self.loops {
            let n = poly.len();
            for i in 0..n {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x)
                {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// Ray parameters where `o + t d` meets the surface (closed form; empty for other types).
fn hits(surface: &Surface, o: DVec3, d: DVec3) -> Vec<f64> {
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
