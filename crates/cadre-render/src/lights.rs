//! Lights: a CAD rig fixed to the camera by default, and directional, point and spot lights
//! placed in the world.

use glam::{DMat3, DVec3};

use crate::Camera;
use crate::layout::LightGpu;

/// A light. Radiance and intensity are linear RGB; lengths are model units (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Directional light fixed to the camera: `direction` points towards the light in view
    /// space (x right, y up, z towards the viewer), so it follows the view.
    CameraDirectional {
        /// Towards the light, view space.
        direction: DVec3,
        /// Radiance.
        radiance: [f32; 3],
    },
    /// Directional light fixed to the model: `direction` points towards the light.
    Directional {
        /// Towards the light, world space.
        direction: DVec3,
        /// Radiance.
        radiance: [f32; 3],
    },
    /// Point light: radiance `intensity / d²` at distance `d`, fading to zero at `range`
    /// (0 = no range).
    Point {
        /// Position, world space.
        position: DVec3,
        /// Intensity.
        intensity: [f32; 3],
        /// Distance where the light fades out (0 for none).
        range: f64,
    },
    /// Spot light: a point light limited to a cone around `axis`, full inside `inner` and
    /// fading out at `outer` (half-angles, radians).
    Spot {
        /// Position, world space.
        position: DVec3,
        /// Direction the spot shines in, world space.
        axis: DVec3,
        /// Intensity.
        intensity: [f32; 3],
        /// Distance where the light fades out (0 for none).
        range: f64,
        /// Half-angle of full light.
        inner: f64,
        /// Half-angle where the light ends.
        outer: f64,
    },
}

impl Light {
    /// The default CAD rig: a key light from the upper left, a softer fill from the right and a
    /// rim light from behind, all fixed to the camera.
    pub fn cad_rig() -> Vec<Light> {
        vec![
            Light::CameraDirectional {
                direction: DVec3::new(-0.45, 0.55, 0.70),
                radiance: [2.6; 3],
            },
            Light::CameraDirectional {
                direction: DVec3::new(0.70, 0.10, 0.50),
                radiance: [0.9; 3],
            },
            Light::CameraDirectional {
                direction: DVec3::new(0.05, 0.60, -0.80),
                radiance: [1.1; 3],
            },
        ]
    }

    /// The light in the shader's form: view space, positions relative to the eye (`f64`).
    pub(crate) fn to_gpu(self, camera: &Camera) -> LightGpu {
        let rotation = DMat3::from_mat4(camera.view_rotation());
        let dir = |d: DVec3| d.normalize_or(DVec3::Z).as_vec3().extend(0.0).to_array();
        let pos = |p: DVec3, kind: f32| {
            let v = (rotation * (p - camera.eye)).as_vec3();
            [v.x, v.y, v.z, kind]
        };
        match self {
            Light::CameraDirectional {
                direction,
                radiance,
            } => LightGpu {
                position: [0.0, 0.0, 0.0, 0.0],
                direction: dir(direction),
                colour: [radiance[0], radiance[1], radiance[2], 0.0],
                params: [0.0; 4],
            },
            Light::Directional {
                direction,
                radiance,
            } => LightGpu {
                position: [0.0, 0.0, 0.0, 0.0],
                direction: dir(rotation * direction),
                colour: [radiance[0], radiance[1], radiance[2], 0.0],
                params: [0.0; 4],
            },
            Light::Point {
                position,
                intensity,
                range,
            } => LightGpu {
                position: pos(position, 1.0),
                direction: [0.0, 0.0, 0.0, range as f32],
                colour: [intensity[0], intensity[1], intensity[2], 0.0],
                params: [0.0; 4],
            },
            Light::Spot {
                position,
                axis,
                intensity,
                range,
                inner,
                outer,
            } => {
                let mut d = dir(rotation * axis);
                d[3] = range as f32;
                LightGpu {
                    position: pos(position, 2.0),
                    direction: d,
                    colour: [intensity[0], intensity[1], intensity[2], outer.cos() as f32],
                    params: [inner.min(outer).cos() as f32, 0.0, 0.0, 0.0],
                }
            }
        }
    }
}
