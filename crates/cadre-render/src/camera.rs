//! The camera: where it is, what it looks at, how it projects; presets and fitting.
//!
//! Positions stay `f64` here. The GPU gets only camera-relative data: a rotation-only view
//! matrix and model matrices whose translation is taken relative to the eye in `f64`, so
//! `f32` precision is spent near the camera, not near the origin.

use glam::{DMat4, DVec3, Mat4};

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view (radians).
    Perspective {
        /// Vertical field of view, radians.
        fov_y: f64,
    },
    /// Orthographic with a visible height (model units).
    Orthographic {
        /// Height of the view volume, model units.
        height: f64,
    },
}

/// Standard CAD views (Z up): where the camera sits relative to the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewPreset {
    /// From the front, right and above (+X, −Y, +Z).
    Iso,
    /// From −Y, looking along +Y.
    Front,
    /// From +Y.
    Back,
    /// From +Z, looking down, +Y up in the image.
    Top,
    /// From −Z, looking up, −Y up in the image.
    Bottom,
    /// From −X.
    Left,
    /// From +X.
    Right,
}

impl ViewPreset {
    /// Unit direction from the target to the eye, and the up vector.
    pub fn direction(self) -> (DVec3, DVec3) {
        match self {
            ViewPreset::Iso => (DVec3::new(1.0, -1.0, 1.0).normalize(), DVec3::Z),
            ViewPreset::Front => (DVec3::NEG_Y, DVec3::Z),
            ViewPreset::Back => (DVec3::Y, DVec3::Z),
            ViewPreset::Top => (DVec3::Z, DVec3::Y),
            ViewPreset::Bottom => (DVec3::NEG_Z, DVec3::NEG_Y),
            ViewPreset::Left => (DVec3::NEG_X, DVec3::Z),
            ViewPreset::Right => (DVec3::X, DVec3::Z),
        }
    }

    /// Parses a preset name (`iso`, `front`, `back`, `top`, `bottom`, `left`, `right`).
    pub fn from_name(name: &str) -> Option<ViewPreset> {
        Some(match name.to_ascii_lowercase().as_str() {
            "iso" | "isometric" => ViewPreset::Iso,
            "front" => ViewPreset::Front,
            "back" => ViewPreset::Back,
            "top" => ViewPreset::Top,
            "bottom" => ViewPreset::Bottom,
            "left" => ViewPreset::Left,
            "right" => ViewPreset::Right,
            _ => return None,
        })
    }
}

/// A camera in model units (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Point looked at.
    pub target: DVec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: DVec3,
    /// Projection.
    pub projection: Projection,
    /// Distance to the near plane (> 0).
    pub near: f64,
    /// Distance to the far plane (> near).
    pub far: f64,
}

/// The view volume of a camera seen for an image of some aspect, as planes for culling:
/// the four sides and the near plane, each (n, d) keeping the camera-relative points p with
/// n·p + d ≥ 0, n unit.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    eye: DVec3,
    planes: [(DVec3, f64); 5],
}

impl Frustum {
    /// The view volume of `camera` for an image of `aspect` (width / height).
    pub fn new(camera: &Camera, aspect: f64) -> Frustum {
        let m = camera.projection_matrix(aspect) * camera.view_rotation();
        let row = |i: usize| glam::DVec4::new(m.x_axis[i], m.y_axis[i], m.z_axis[i], m.w_axis[i]);
        let (x, y, z, w) = (row(0), row(1), row(2), row(3));
        // −w ≤ x ≤ w, −w ≤ y ≤ w, and reverse Z: depth ≤ 1 in front of the near plane.
        let planes = [w + x, w - x, w + y, w - y, w - z].map(|p| {
            let n = p.truncate();
            let len = n.length().max(f64::MIN_POSITIVE);
            (n / len, p.w / len)
        });
        Frustum {
            eye: camera.eye,
            planes,
        }
    }

    /// Whether the sphere (world centre, radius) may show: it is not wholly outside one of
    /// the planes.
    pub fn holds(&self, (centre, radius): (DVec3, f64)) -> bool {
        let p = centre - self.eye;
        self.planes.iter().all(|(n, d)| n.dot(p) + d >= -radius)
    }
}

/// Default vertical field of view of a fitted perspective camera (30°).
pub(crate) const FIT_FOV: f64 = std::f64::consts::PI / 6.0;

impl Camera {
    /// A camera looking at the box `lo`..`hi` from `preset`, framing its bounding sphere in an
    /// image of width/height `aspect`, perspective or orthographic.
    pub fn fit(
        lo: DVec3,
        hi: DVec3,
        preset: ViewPreset,
        orthographic: bool,
        aspect: f64,
    ) -> Camera {
        Camera::fit_along(lo, hi, preset.direction(), orthographic, aspect)
    }

    /// Fits the box `lo`..`hi` into the view seen from direction `dir` (unit, from the target
    /// towards the eye) with `up` (a saved view's orientation; [`Camera::fit`] for the presets).
    pub fn fit_along(
        lo: DVec3,
        hi: DVec3,
        (dir, up): (DVec3, DVec3),
        orthographic: bool,
        aspect: f64,
    ) -> Camera {
        let dir = dir.normalize_or(DVec3::Z);
        let up = if up.cross(dir).length_squared() > 1e-12 {
            up
        } else {
            dir.any_orthonormal_vector()
        };
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-9 * (1.0 + centre.abs().max_element()));
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        // The sphere must fit the narrower of the two fields.
        let (projection, distance) = if orthographic {
            let height = 2.0 * radius * 1.05 / aspect.min(1.0);
            (Projection::Orthographic { height }, 3.0 * radius)
        } else {
            let half_v = 0.5 * FIT_FOV;
            let half_h = (half_v.tan() * aspect).atan();
            let half = half_v.min(half_h);
            (
                Projection::Perspective { fov_y: FIT_FOV },
                radius * 1.05 / half.sin(),
            )
        };
        Camera {
            eye: centre + dir * distance,
            target: centre,
            up,
            projection,
            near: (distance - radius * 1.1).max(distance * 1e-3),
            far: distance + radius * 1.1,
        }
    }

    /// This camera magnifying `point` `zoom` times: it looks at `point` from as far as it
    /// looked at its target, along the same direction, through a field of view (or an
    /// orthographic height) `zoom` times narrower, with near and far planes around the box
    /// `lo`..`hi`. The eye stays where the fitted view put it, outside the model, so a
    /// close-up of any detail at any magnification shows the outside of the parts.
    pub fn zoomed_at(&self, point: DVec3, zoom: f64, (lo, hi): (DVec3, DVec3)) -> Camera {
        let zoom = if zoom.is_finite() && zoom > 0.0 {
            zoom
        } else {
            1.0
        };
        let projection = match self.projection {
            Projection::Perspective { fov_y } => Projection::Perspective {
                fov_y: 2.0 * ((0.5 * fov_y).tan() / zoom).atan(),
            },
            Projection::Orthographic { height } => Projection::Orthographic {
                height: height / zoom,
            },
        };
        Camera {
            eye: point + (self.eye - self.target),
            target: point,
            up: self.up,
            projection,
            near: 0.0,
            far: 0.0,
        }
        .with_planes_around(lo, hi)
    }

    /// A camera from `eye` to `target` with `up`, perspective with vertical field of view
    /// `fov_y` (radians), its near and far planes around the box `lo`..`hi`.
    pub fn looking(
        (eye, target, up): (DVec3, DVec3, DVec3),
        fov_y: f64,
        (lo, hi): (DVec3, DVec3),
    ) -> Camera {
        Camera {
            eye,
            target,
            up,
            projection: Projection::Perspective { fov_y },
            near: 0.0,
            far: 0.0,
        }
        .with_planes_around(lo, hi)
    }

    /// This camera with its near and far planes holding the box `lo`..`hi` (along the view
    /// direction), the near plane at least a thousandth of the far one.
    fn with_planes_around(mut self, lo: DVec3, hi: DVec3) -> Camera {
        let forward = (self.target - self.eye).normalize_or(DVec3::NEG_Z);
        let centre = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length();
        let along = (centre - self.eye).dot(forward);
        let far = (along + radius * 1.1).max(1e-9);
        self.far = far;
        self.near = (along - radius * 1.1).max(far * 1e-3);
        self
    }

    /// Rotation-only view matrix (the eye at the origin): world directions → view space
    /// (x right, y up, looking down −z).
    pub fn view_rotation(&self) -> DMat4 {
        let forward = (self.target - self.eye).normalize_or(DVec3::NEG_Z);
        let up = if forward.cross(self.up).length_squared() > 1e-24 {
            self.up
        } else {
            forward.any_orthonormal_vector()
        };
        DMat4::look_to_rh(DVec3::ZERO, forward, up)
    }

    /// Reverse-Z projection (near → depth 1, far → depth 0) for an image of `aspect`.
    pub fn projection_matrix(&self, aspect: f64) -> DMat4 {
        let (near, far) = (self.near, self.far);
        match self.projection {
            // Swapping near and far in glam's [0, 1] projections reverses the depth.
            Projection::Perspective { fov_y } => DMat4::perspective_rh(fov_y, aspect, far, near),
            Projection::Orthographic { height } => {
                let (h, w) = (0.5 * height, 0.5 * height * aspect);
                DMat4::orthographic_rh(-w, w, -h, h, far, near)
            }
        }
    }

    /// Projection × rotation-only view, as the GPU gets it.
    pub fn view_projection_f32(&self, aspect: f64) -> Mat4 {
        (self.projection_matrix(aspect) * self.view_rotation()).as_mat4()
    }

    /// The height in model units of what the view shows at its target's distance: what the
    /// image's rows span there.
    pub fn view_height(&self) -> f64 {
        match self.projection {
            Projection::Orthographic { height } => height,
            Projection::Perspective { fov_y } => {
                2.0 * (self.target - self.eye).length() * (0.5 * fov_y).tan()
            }
        }
    }

    /// Whether the projection is orthographic.
    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(cam: &Camera, p: DVec3) -> DVec3 {
        let m = cam.projection_matrix(1.0) * cam.view_rotation();
        m.project_point3(p - cam.eye)
    }

    #[test]
    fn a_fitted_box_lands_inside_the_image_with_reverse_depth() {
        let (lo, hi) = (DVec3::new(-1.0, -2.0, -3.0), DVec3::new(4.0, 5.0, 6.0));
        for preset in [
            ViewPreset::Iso,
            ViewPreset::Front,
            ViewPreset::Top,
            ViewPreset::Bottom,
            ViewPreset::Left,
        ] {
            for ortho in [false, true] {
                let cam = Camera::fit(lo, hi, preset, ortho, 1.0);
                for i in 0..8 {
                    let c = DVec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    let q = project(&cam, c);
                    assert!(
                        q.x.abs() <= 1.0 && q.y.abs() <= 1.0,
                        "{preset:?} {ortho} {q}"
                    );
                    assert!(q.z > 0.0 && q.z < 1.0, "{preset:?} {ortho} depth {}", q.z);
                }
                // Nearer points get larger depth (reverse Z).
                let centre = 0.5 * (lo + hi);
                let (dir, _) = preset.direction();
                let near = project(&cam, centre + dir * 0.5);
                let far = project(&cam, centre - dir * 0.5);
                assert!(near.z > far.z, "{preset:?} {ortho}");
            }
        }
    }

    #[test]
    fn the_frustum_keeps_what_the_view_shows_and_culls_the_rest() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        for ortho in [false, true] {
            let camera = Camera::fit(lo, hi, ViewPreset::Iso, ortho, 1.5);
            let f = Frustum::new(&camera, 1.5);
            let forward = (camera.target - camera.eye).normalize();
            assert!(f.holds((DVec3::ZERO, 0.1)));
            assert!(f.holds((DVec3::ONE, 0.01)), "a corner of the fitted box");
            // Behind the eye, far to a side: culled; a large sphere reaching in: kept.
            assert!(!f.holds((camera.eye - forward * 5.0, 0.5)));
            let side = forward.cross(DVec3::Z).normalize();
            assert!(!f.holds((side * 50.0, 1.0)));
            assert!(f.holds((side * 50.0, 60.0)));
        }
    }

    #[test]
    fn presets_put_the_expected_axis_up_and_right() {
        let cam = Camera::fit(
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            ViewPreset::Front,
            true,
            1.0,
        );
        // Front view: +X to the right, +Z up.
        assert!(project(&cam, DVec3::X).x > 0.0);
        assert!(project(&cam, DVec3::Z).y > 0.0);
        let cam = Camera::fit(
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            ViewPreset::Top,
            true,
            1.0,
        );
        assert!(project(&cam, DVec3::X).x > 0.0);
        assert!(project(&cam, DVec3::Y).y > 0.0);
        assert_eq!(ViewPreset::from_name("ISO"), Some(ViewPreset::Iso));
        assert_eq!(ViewPreset::from_name("diagonal"), None);
    }
}
