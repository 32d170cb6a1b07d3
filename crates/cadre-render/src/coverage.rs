//! How many times over a frame's instances cover the image, estimated before drawing from
//! each instance's bounding sphere: the fill work a frame would do. Six assembly levels of ten
//! uses all shifted along one axis pile 10⁶ cubes into the same
//! pixels, about 10⁴ times over the whole image: hours on a software rasterizer, whatever the
//! instancing. Real assemblies cover the image a few to a few hundred times.

use glam::{DAffine3, DVec3};

use crate::Camera;
use crate::camera::Projection;

/// Most times over a frame's instances may cover the image (estimated by
/// `ImageCoverage`); past it the frame is refused.
pub const MAX_IMAGE_COVERAGE: f64 = 1000.0;

/// A sum of image fractions covered by bounding spheres seen by one camera.
pub(crate) struct ImageCoverage {
    eye: DVec3,
    forward: DVec3,
    projection: Projection,
    /// Images covered so far.
    pub total: f64,
}

impl ImageCoverage {
    /// Nothing covered yet, seen by `camera`.
    pub fn new(camera: &Camera) -> ImageCoverage {
        ImageCoverage {
            eye: camera.eye,
            forward: (camera.target - camera.eye).normalize_or(DVec3::NEG_Z),
            projection: camera.projection,
            total: 0.0,
        }
    }

    /// Adds the sphere (`centre`, `radius`), mesh-local, placed by `world`: the fraction of a
    /// square image of the view's height its disc covers (at most 1; nothing behind the eye).
    pub fn add(&mut self, world: DAffine3, sphere: (DVec3, f64)) {
        let (c, r) = placed_sphere(world, sphere);
        let half_height = match self.projection {
            Projection::Orthographic { height } => 0.5 * height,
            Projection::Perspective { fov_y } => {
                let depth = (c - self.eye).dot(self.forward);
                if depth <= r {
                    // Around or behind the eye: the whole image, or nothing.
                    self.total += if depth > -r { 1.0 } else { 0.0 };
                    return;
                }
                depth * (0.5 * fov_y).tan()
            }
        };
        let fraction = std::f64::consts::PI * r * r / (4.0 * half_height * half_height);
        self.total += if fraction.is_finite() {
            fraction.min(1.0)
        } else {
            1.0
        };
    }
}

/// The mesh-local sphere (`centre`, `radius`) placed by `world`: its centre moved, its radius
/// scaled by the placement's largest axis scale (a sphere around the placed one).
pub(crate) fn placed_sphere(world: DAffine3, (centre, radius): (DVec3, f64)) -> (DVec3, f64) {
    let m = world.matrix3;
    let scale = m
        .x_axis
        .length()
        .max(m.y_axis.length())
        .max(m.z_axis.length());
    (world.transform_point3(centre), radius * scale)
}

/// The bounding sphere (centre, radius) of `points`; radius 0 at the origin for none.
pub(crate) fn bounding_sphere(points: impl Iterator<Item = [f32; 3]>) -> (DVec3, f64) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in points {
        let p = DVec3::from(p.map(f64::from));
        lo = lo.min(p);
        hi = hi.max(p);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return (DVec3::ZERO, 0.0);
    }
    (0.5 * (lo + hi), 0.5 * (hi - lo).length())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::fit(
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            crate::ViewPreset::Iso,
            false,
            1.0,
        )
    }

    /// A fitted model covers part of one image; the same sphere placed 10⁴ times on itself
    /// covers 10⁴ times as much, and one placed behind the eye covers nothing.
    #[test]
    fn coverage_adds_up_the_instances() {
        let cam = camera();
        let sphere = bounding_sphere([[-1.0f32, -1.0, -1.0], [1.0, 1.0, 1.0]].into_iter());
        let mut one = ImageCoverage::new(&cam);
        one.add(DAffine3::IDENTITY, sphere);
        assert!(one.total > 0.1 && one.total <= 1.0, "{}", one.total);
        let mut many = ImageCoverage::new(&cam);
        for _ in 0..10_000 {
            many.add(DAffine3::IDENTITY, sphere);
        }
        assert!((many.total / one.total - 1e4).abs() < 1e-6);
        let mut behind = ImageCoverage::new(&cam);
        let back = cam.eye + (cam.eye - cam.target) * 10.0;
        behind.add(DAffine3::from_translation(back), sphere);
        assert_eq!(behind.total, 0.0);
        // Small spheres far apart cover little.
        let mut small = ImageCoverage::new(&cam);
        small.add(DAffine3::from_scale(DVec3::splat(0.01)), sphere);
        assert!(small.total < 1e-3 * one.total, "{}", small.total);
    }
}
