//! The axis gizmo: the world axes as the camera sees them, drawn in a corner; clicking an
//! axis looks along it.

use cadre_render::{Camera, ViewPreset};
use glam::{DMat3, DVec2, DVec3};

/// One axis of the gizmo on screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GizmoAxis {
    /// "X", "Y" or "Z".
    pub label: &'static str,
    /// Screen direction of the axis tip from the gizmo's centre (x right, y down), in units
    /// of the gizmo's radius.
    pub tip: DVec2,
    /// Whether the axis points towards the viewer (drawn in front).
    pub towards_viewer: bool,
    /// The view a click on this axis moves to.
    pub preset: ViewPreset,
    /// Linear RGB colour (red, green, blue for X, Y, Z).
    pub colour: [u8; 3],
}

/// The three axes as `camera` sees them, back to front (draw in this order).
pub fn axes(camera: &Camera) -> Vec<GizmoAxis> {
    let rotation = DMat3::from_mat4(camera.view_rotation());
    let mut out: Vec<(f64, GizmoAxis)> = [
        ("X", DVec3::X, ViewPreset::Right, [220, 60, 60]),
        ("Y", DVec3::Y, ViewPreset::Back, [60, 180, 60]),
        ("Z", DVec3::Z, ViewPreset::Top, [70, 110, 230]),
    ]
    .into_iter()
    .map(|(label, axis, preset, colour)| {
        let v = rotation * axis;
        (
            v.z,
            GizmoAxis {
                label,
                tip: DVec2::new(v.x, -v.y),
                towards_viewer: v.z > 0.0,
                preset,
                colour,
            },
        )
    })
    .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.into_iter().map(|(_, a)| a).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_view_shows_x_right_and_z_up() {
        let cam = Camera::fit(
            DVec3::splat(-1.0),
            DVec3::ONE,
            ViewPreset::Front,
            false,
            1.0,
        );
        let axes = axes(&cam);
        let get = |l| axes.iter().find(|a| a.label == l).unwrap();
        assert!(get("X").tip.x > 0.99);
        assert!(get("Z").tip.y < -0.99, "up is negative y on screen");
        // Y points away from the viewer in the front view: drawn first.
        assert_eq!(axes[0].label, "Y");
        assert!(!get("Y").towards_viewer);
        assert_eq!(get("Z").preset, ViewPreset::Top);
    }
}
