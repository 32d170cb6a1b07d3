//! Shadows of the key light (issue 18 item 4): a shadow map, the depth of everything the
//! visibility pass draws seen from the light — written by every back-end as it writes the
//! view's depth, so the ray-cast quadrics and faces cast exact shadows of their own (their
//! hits' depth, not a proxy's) — read by the shade pass (percentage-closer, 3 × 3).
//!
//! Why a shadow map and not the thesis' shadow volumes (silhouette conics extruded along the
//! light): a volume per quadric and per cut conic is a stencil pass per caster, with the
//! conic of each ray-cast silhouette to build on the CPU every frame, and it serves quadrics
//! only; the map reuses the one visibility pass every back-end (meshes, trimmed faces,
//! quadrics) already has, at a cost independent of the casters' count. Its price is the map's
//! resolution (a texel's footprint), which percentage-closer filtering softens.

use glam::{DMat4, DVec3};

use crate::camera::Projection;
use crate::{Camera, Light};

/// Texels along each side of the shadow map.
pub const SHADOW_MAP_SIZE: u32 = 2048;

/// The key light's view of the scene box `lo`..`hi` for a frame seen by `camera`: an
/// orthographic camera along a directional light (fixed to the camera or to the world),
/// a perspective one from a point or spot light towards the box's centre; `None` without a
/// light or a box.
pub fn light_camera(light: &Light, camera: &Camera, (lo, hi): (DVec3, DVec3)) -> Option<Camera> {
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-9);
    let view_to_world = camera.view_rotation().transpose();
    let towards = match *light {
        Light::CameraDirectional { direction, .. } => {
            Some(view_to_world.transform_vector3(direction))
        }
        Light::Directional { direction, .. } => Some(direction),
        Light::Point { .. } | Light::Spot { .. } => None,
    };
    let mut light_camera = match (towards, light) {
        (Some(dir), _) => {
            let dir = dir.try_normalize()?;
            Camera {
                eye: centre + dir * (3.0 * radius),
                target: centre,
                up: dir.any_orthonormal_vector(),
                projection: Projection::Orthographic {
                    height: 2.05 * radius,
                },
                near: 0.0,
                far: 0.0,
            }
        }
        (None, Light::Point { position, .. } | Light::Spot { position, .. }) => {
            let distance = (centre - *position).length();
            // The box's sphere seen from the light, or a wide cone from within it.
            let half = if distance > radius * 1.02 {
                (radius / distance).asin() * 1.05
            } else {
                75f64.to_radians()
            };
            let dir = (centre - *position).try_normalize().unwrap_or(DVec3::NEG_Z);
            Camera {
                eye: *position,
                target: *position + dir,
                up: dir.any_orthonormal_vector(),
                projection: Projection::Perspective {
                    fov_y: (2.0 * half).clamp(1f64.to_radians(), 150f64.to_radians()),
                },
                near: 0.0,
                far: 0.0,
            }
        }
        _ => return None,
    };
    // Near and far about the box (the near plane no nearer than a thousandth of the far).
    let forward = (light_camera.target - light_camera.eye).normalize();
    let along = (centre - light_camera.eye).dot(forward);
    light_camera.far = (along + radius * 1.1).max(1e-9);
    light_camera.near = (along - radius * 1.1).max(light_camera.far * 1e-3);
    Some(light_camera)
}

/// The frame's shadow terms (`FrameUniform::shadow`, `shadow_params`): the map `light` drew
/// of a frame seen by `camera`, as a map from `camera`'s view space to the light's clip space
/// (in `f64`, through the world, so the eyes' distances cancel before rounding), and the
/// texel's world size per unit of clip w.
pub fn shadow_terms(camera: &Camera, light: &Camera) -> ([[f32; 4]; 4], [f32; 4]) {
    let view_to_world = camera.view_rotation().transpose();
    let to_light = light.projection_matrix(1.0)
        * light.view_rotation()
        * DMat4::from_translation(camera.eye - light.eye)
        * view_to_world;
    let size = f64::from(SHADOW_MAP_SIZE);
    let per_w = match light.projection {
        Projection::Orthographic { height } => height / size,
        Projection::Perspective { fov_y } => 2.0 * (0.5 * fov_y).tan() / size,
    };
    (
        to_light.as_mat4().to_cols_array_2d(),
        [per_w as f32, 0.0, 1.0, SHADOW_MAP_SIZE as f32],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_sees_the_box_and_maps_view_points_into_it() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        let camera = Camera::fit(lo, hi, crate::ViewPreset::Iso, false, 1.0);
        for light in [
            Light::Directional {
                direction: DVec3::new(0.3, -0.4, 1.0),
                radiance: [1.0; 3],
            },
            Light::Point {
                position: DVec3::new(4.0, 3.0, 6.0),
                intensity: [1.0; 3],
                range: 0.0,
            },
        ] {
            let l = light_camera(&light, &camera, (lo, hi)).unwrap();
            let (m, _) = shadow_terms(&camera, &l);
            let m = glam::Mat4::from_cols_array_2d(&m).as_dmat4();
            // Every corner of the box lands in the map, in front of the light.
            for i in 0..8 {
                let corner = DVec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                let view = camera.view_rotation().transform_point3(corner - camera.eye);
                let c = m * view.extend(1.0);
                let ndc = c.truncate() / c.w;
                assert!(
                    c.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0,
                    "{light:?} {ndc}"
                );
                assert!((0.0..=1.0).contains(&ndc.z), "{ndc}");
            }
        }
    }
}
