//! Camera navigation: orbit (turntable or trackball) about a pivot, pan, zoom to a point,
//! fit, and animated transitions between views. Pure maths on [`Camera`], in `f64`.
//!
//! The camera is kept as an orbit: the point looked at, the distance to it, the camera's
//! orientation (a rotation from camera axes — x right, y up, z back towards the eye — to
//! world axes) and the orthographic height. Every gesture changes those, and [`Navigator::camera`]
//! turns them into a [`Camera`] with clip planes around the model.

use std::f64::consts::PI;

use cadre_render::{Camera, Projection, ViewPreset};
use glam::{DMat3, DQuat, DVec2, DVec3};

/// How a drag orbits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrbitStyle {
    /// Yaw about the world's Z (up) axis and pitch about the screen's horizontal: the model's
    /// up stays up (the usual CAD default).
    Turntable,
    /// Rotation about the screen axis perpendicular to the drag: any orientation reachable.
    Trackball,
}

/// Vertical field of view of the perspective camera.
const FOV_Y: f64 = PI / 6.0;
/// Radians of orbit per window height dragged.
const ORBIT_PER_HEIGHT: f64 = PI;
/// Length of animated transitions, seconds.
const TRANSITION: f64 = 0.35;

/// The camera as an orbit about `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Orbit {
    target: DVec3,
    distance: f64,
    rotation: DQuat,
    /// Height of the orthographic view (kept in step with the perspective framing).
    ortho_height: f64,
}

impl Orbit {
    fn forward(&self) -> DVec3 {
        self.rotation * DVec3::NEG_Z
    }

    fn eye(&self) -> DVec3 {
        self.target - self.forward() * self.distance
    }

    /// Interpolation from `self` (t = 0) to `to` (t = 1).
    fn lerp(&self, to: &Orbit, t: f64) -> Orbit {
        Orbit {
            target: self.target.lerp(to.target, t),
            // Geometric interpolation: zooms feel even.
            distance: self.distance * (to.distance / self.distance).powf(t),
            rotation: self.rotation.slerp(to.rotation, t),
            ortho_height: self.ortho_height * (to.ortho_height / self.ortho_height).powf(t),
        }
    }
}

/// An animated transition in progress.
#[derive(Clone, Copy, Debug)]
struct Transition {
    from: Orbit,
    to: Orbit,
    /// Seconds elapsed.
    elapsed: f64,
}

/// The camera controller of a view.
#[derive(Clone, Debug)]
pub struct Navigator {
    orbit: Orbit,
    /// Perspective or orthographic.
    pub orthographic: bool,
    /// How drags orbit.
    pub style: OrbitStyle,
    /// The model's box, for clip planes and fitting.
    bounds: (DVec3, DVec3),
    transition: Option<Transition>,
}

/// Camera-to-world rotation of a camera looking along `forward` with `up` up.
fn look_rotation(forward: DVec3, up: DVec3) -> DQuat {
    let back = -forward.normalize_or(DVec3::NEG_Z);
    let right = up.cross(back);
    let right = if right.length_squared() > 1e-20 {
        right.normalize()
    } else {
        back.any_orthonormal_vector()
    };
    let up = back.cross(right);
    DQuat::from_mat3(&DMat3::from_cols(right, up, back)).normalize()
}

/// Smooth start and stop.
fn ease(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Navigator {
    /// A navigator looking at the box `lo`..`hi` from the iso view.
    pub fn new(lo: DVec3, hi: DVec3, aspect: f64) -> Navigator {
        let mut nav = Navigator {
            orbit: Orbit {
                target: DVec3::ZERO,
                distance: 1.0,
                rotation: DQuat::IDENTITY,
                ortho_height: 1.0,
            },
            orthographic: false,
            style: OrbitStyle::Turntable,
            bounds: (lo, hi),
            transition: None,
        };
        nav.orbit = nav.framing(ViewPreset::Iso.direction(), lo, hi, aspect);
        nav
    }

    /// The orbit framing `lo`..`hi` looking along `(direction, up)` (from the eye towards
    /// the model is `-direction`).
    fn framing(&self, (direction, up): (DVec3, DVec3), lo: DVec3, hi: DVec3, aspect: f64) -> Orbit {
        let fitted = Camera::fit(lo, hi, ViewPreset::Iso, false, aspect);
        let radius = 0.5 * (hi - lo).length().max(1e-9);
        let distance = (fitted.eye - fitted.target).length();
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        Orbit {
            target: 0.5 * (lo + hi),
            distance,
            rotation: look_rotation(-direction, up),
            ortho_height: 2.0 * radius * 1.05 / aspect.min(1.0),
        }
    }

    /// The model's box.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.bounds
    }

    /// Replaces the model's box (clip planes follow it).
    pub fn set_bounds(&mut self, lo: DVec3, hi: DVec3) {
        self.bounds = (lo, hi);
    }

    /// The point the camera orbits by default and looks at.
    pub fn target(&self) -> DVec3 {
        self.orbit.target
    }

    /// The camera now, with near and far planes around the model's box.
    pub fn camera(&self) -> Camera {
        let o = self.orbit;
        let eye = o.eye();
        let (lo, hi) = self.bounds;
        let centre = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length().max(1e-9);
        let d = (centre - eye).dot(o.forward());
        // Reverse-Z keeps precision with a near plane far closer than the model.
        let far = (d + radius * 1.5).max(radius * 1e-3);
        let near = (d - radius * 1.5).max(far * 1e-6).max(1e-9);
        Camera {
            eye,
            target: o.target,
            up: o.rotation * DVec3::Y,
            projection: if self.orthographic {
                Projection::Orthographic {
                    height: o.ortho_height,
                }
            } else {
                Projection::Perspective { fov_y: FOV_Y }
            },
            near,
            far,
        }
    }

    /// Orbits by a drag of (`dx`, `dy`) pixels in a view `height` pixels tall, about `pivot`
    /// (the point under the cursor when the drag began, or the target).
    pub fn orbit(&mut self, (dx, dy): (f64, f64), height: f64, pivot: DVec3) {
        self.transition = None;
        let k = ORBIT_PER_HEIGHT / height.max(1.0);
        let right = self.orbit.rotation * DVec3::X;
        let delta = match self.style {
            // Dragging right turns the model right: the camera yaws left about world Z.
            OrbitStyle::Turntable => {
                DQuat::from_axis_angle(DVec3::Z, -dx * k) * DQuat::from_axis_angle(right, -dy * k)
            }
            OrbitStyle::Trackball => {
                let (ax, ay) = (dy, dx);
                let len = (ax * ax + ay * ay).sqrt();
                if len < 1e-12 {
                    return;
                }
                let axis = self.orbit.rotation * DVec3::new(ax / len, ay / len, 0.0);
                DQuat::from_axis_angle(axis, -len * k)
            }
        };
        self.rotate_about(delta, pivot);
    }

    /// Applies the world rotation `delta` to the camera about `pivot`.
    fn rotate_about(&mut self, delta: DQuat, pivot: DVec3) {
        let o = &mut self.orbit;
        o.rotation = (delta * o.rotation).normalize();
        o.target = pivot + delta * (o.target - pivot);
    }

    /// World size of one pixel at the target's depth, in a view `height` pixels tall.
    pub fn pixel_size(&self, height: f64) -> f64 {
        let view_height = if self.orthographic {
            self.orbit.ortho_height
        } else {
            2.0 * self.orbit.distance * (0.5 * FOV_Y).tan()
        };
        view_height / height.max(1.0)
    }

    /// Pans by a drag of (`dx`, `dy`) pixels (right, down) in a view `height` pixels tall:
    /// the model follows the cursor at the target's depth.
    pub fn pan(&mut self, (dx, dy): (f64, f64), height: f64) {
        self.transition = None;
        let s = self.pixel_size(height);
        let right = self.orbit.rotation * DVec3::X;
        let up = self.orbit.rotation * DVec3::Y;
        self.orbit.target += (-dx * right + dy * up) * s;
    }

    /// Zooms by `factor` (< 1 closer) towards `point`, which stays under the cursor.
    pub fn zoom_to(&mut self, factor: f64, point: DVec3) {
        self.transition = None;
        let factor = factor.clamp(1e-3, 1e3);
        let o = &mut self.orbit;
        // A homothety of the camera about the point keeps it where it is on screen.
        let eye = point + (o.eye() - point) * factor;
        o.target = point + (o.target - point) * factor;
        o.distance = (o.target - eye).length().max(1e-12);
        o.ortho_height *= factor;
    }

    /// The world point on the ray through `ndc` (x right, y up, in −1..1) at the target's
    /// depth: where to zoom when nothing is under the cursor.
    pub fn point_at_target_depth(&self, ndc: DVec2, aspect: f64) -> DVec3 {
        let o = self.orbit;
        let (right, up) = (o.rotation * DVec3::X, o.rotation * DVec3::Y);
        let half_h = 0.5 * self.pixel_size(1.0);
        let offset = right * ndc.x * half_h * aspect + up * ndc.y * half_h;
        o.target + offset
    }

    /// Moves (animated) to look at the box `lo`..`hi` from `preset`.
    pub fn view_preset(&mut self, preset: ViewPreset, aspect: f64) {
        let (lo, hi) = self.bounds;
        self.animate_to(self.framing(preset.direction(), lo, hi, aspect));
    }

    /// Moves (animated) to look at the whole box from `direction` (unit, target → eye) with
    /// `up` on screen: a saved view's orientation.
    pub fn view_along(&mut self, (direction, up): (DVec3, DVec3), aspect: f64) {
        let (lo, hi) = self.bounds;
        self.animate_to(self.framing((direction, up), lo, hi, aspect));
    }

    /// Frames the box `lo`..`hi` (animated), keeping the direction of view.
    pub fn fit(&mut self, lo: DVec3, hi: DVec3, aspect: f64) {
        let direction = -self.orbit.forward();
        let up = self.orbit.rotation * DVec3::Y;
        self.animate_to(self.framing((direction, up), lo, hi, aspect));
    }

    fn animate_to(&mut self, to: Orbit) {
        self.transition = Some(Transition {
            from: self.orbit,
            to,
            elapsed: 0.0,
        });
    }

    /// Advances a transition by `dt` seconds; `true` while one is running.
    pub fn tick(&mut self, dt: f64) -> bool {
        let Some(mut t) = self.transition else {
            return false;
        };
        t.elapsed += dt.max(0.0);
        let s = t.elapsed / TRANSITION;
        self.orbit = t.from.lerp(&t.to, ease(s));
        if s >= 1.0 {
            self.orbit = t.to;
            self.transition = None;
            false
        } else {
            self.transition = Some(t);
            true
        }
    }

    /// Whether a transition is running.
    pub fn animating(&self) -> bool {
        self.transition.is_some()
    }

    /// A 3D mouse's motion: `translate` and `rotate` (view axes: x right, y up, z towards the
    /// viewer; the object's motion, radians) scaled to the model. The cap pushed right moves
    /// the model right; twisted, the model turns about the target.
    pub fn spacemouse(&mut self, translate: [f64; 3], rotate: [f64; 3]) {
        self.transition = None;
        let (lo, hi) = self.bounds;
        let size = (hi - lo).length().max(1e-9);
        let o = self.orbit;
        let (right, up, back) = (
            o.rotation * DVec3::X,
            o.rotation * DVec3::Y,
            o.rotation * DVec3::Z,
        );
        // Object moving right = camera moving left.
        self.orbit.target -= (right * translate[0] + up * translate[1]) * size * 0.5;
        // Object towards the viewer = zoom in.
        let factor = (-translate[2] * 1.5).exp();
        let target = self.orbit.target;
        self.zoom_to(factor, target);
        let axis = right * rotate[0] + up * rotate[1] + back * rotate[2];
        let angle = axis.length();
        if angle > 1e-12 {
            // The object turns by +angle: the camera by −angle about the target.
            self.rotate_about(DQuat::from_axis_angle(axis / angle, -angle), target);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nav() -> Navigator {
        Navigator::new(DVec3::splat(-10.0), DVec3::splat(10.0), 1.5)
    }

    /// Where `p` lands in normalised device coordinates.
    fn ndc(nav: &Navigator, p: DVec3) -> DVec3 {
        let cam = nav.camera();
        (cam.projection_matrix(1.5) * cam.view_rotation()).project_point3(p - cam.eye)
    }

    #[test]
    fn the_model_is_framed_and_inside_the_clip_planes() {
        let nav = nav();
        for i in 0..8 {
            let c = DVec3::new(
                if i & 1 == 0 { -10.0 } else { 10.0 },
                if i & 2 == 0 { -10.0 } else { 10.0 },
                if i & 4 == 0 { -10.0 } else { 10.0 },
            );
            let q = ndc(&nav, c);
            assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{q}");
            assert!(q.z > 0.0 && q.z < 1.0, "depth {q}");
        }
    }

    #[test]
    fn dragging_right_turns_the_near_side_of_the_model_right() {
        for style in [OrbitStyle::Turntable, OrbitStyle::Trackball] {
            let mut nav = nav();
            nav.style = style;
            let target = nav.target();
            // The point of the model nearest the eye.
            let near = target - nav.orbit.forward() * 5.0;
            let before = ndc(&nav, near);
            nav.orbit((50.0, 0.0), 600.0, target);
            let after = ndc(&nav, near);
            assert!(after.x > before.x + 0.01, "{style:?}: {before} → {after}");
            // The pivot stays put.
            let p = ndc(&nav, target);
            assert!(
                p.x.abs() < 1e-9 && p.y.abs() < 1e-9,
                "{style:?} pivot moved: {p}"
            );
        }
    }

    #[test]
    fn turntable_keeps_world_z_up_on_screen() {
        let mut nav = nav();
        nav.orbit((123.0, 40.0), 600.0, nav.target());
        nav.orbit((-300.0, -10.0), 600.0, nav.target());
        let up = nav.camera().up;
        let right = nav.orbit.rotation * DVec3::X;
        // Screen right stays horizontal: no roll.
        assert!(right.z.abs() < 1e-9, "roll: {right}");
        assert!(up.z > 0.0);
    }

    #[test]
    fn orbiting_about_a_pivot_keeps_the_pivot_on_screen() {
        let mut nav = nav();
        let pivot = DVec3::new(8.0, -3.0, 2.0);
        let before = ndc(&nav, pivot);
        nav.orbit((80.0, -35.0), 600.0, pivot);
        let after = ndc(&nav, pivot);
        assert!((after.truncate() - before.truncate()).length() < 1e-9);
    }

    #[test]
    fn panning_moves_the_model_with_the_cursor() {
        for ortho in [false, true] {
            let mut nav = nav();
            nav.orthographic = ortho;
            let target = nav.target();
            let before = ndc(&nav, target);
            // 60 px right, 30 px down in a 600 px tall view (NDC spans 2 over 600 px).
            nav.pan((60.0, 30.0), 600.0);
            let after = ndc(&nav, target);
            assert!(
                (after.x - before.x - 60.0 * 2.0 / 600.0 / 1.5).abs() < 1e-9,
                "{ortho}"
            );
            assert!(
                (after.y - before.y + 30.0 * 2.0 / 600.0).abs() < 1e-9,
                "{ortho}"
            );
        }
    }

    #[test]
    fn zooming_keeps_the_point_under_the_cursor() {
        for ortho in [false, true] {
            let mut nav = nav();
            nav.orthographic = ortho;
            let point = nav.point_at_target_depth(DVec2::new(0.6, -0.4), 1.5);
            let before = ndc(&nav, point);
            assert!(
                (before.x - 0.6).abs() < 1e-9 && (before.y + 0.4).abs() < 1e-9,
                "{before}"
            );
            let size_before = ndc(&nav, point + DVec3::X).truncate() - before.truncate();
            nav.zoom_to(0.5, point);
            let after = ndc(&nav, point);
            assert!(
                (after.truncate() - before.truncate()).length() < 1e-9,
                "{ortho}"
            );
            // Twice as close: things look twice as large.
            let size_after = ndc(&nav, point + DVec3::X).truncate() - after.truncate();
            let ratio = size_after.length() / size_before.length();
            assert!((ratio - 2.0).abs() < 0.1, "{ortho}: ×{ratio}");
        }
    }

    #[test]
    fn presets_animate_to_their_view_and_stop() {
        let mut nav = nav();
        nav.view_preset(ViewPreset::Front, 1.5);
        assert!(nav.animating());
        let mut steps = 0;
        while nav.tick(1.0 / 60.0) {
            steps += 1;
            assert!(steps < 100, "the transition ends");
        }
        assert!(steps > 5, "it animates over several frames");
        let cam = nav.camera();
        // Front: looking along +Y, Z up.
        let forward = (cam.target - cam.eye).normalize();
        assert!((forward - DVec3::Y).length() < 1e-9, "{forward}");
        assert!((cam.up - DVec3::Z).length() < 1e-9);
    }

    #[test]
    fn fit_frames_a_small_box() {
        let mut nav = nav();
        nav.fit(DVec3::splat(1.0), DVec3::splat(2.0), 1.5);
        while nav.tick(0.1) {}
        assert!((nav.target() - DVec3::splat(1.5)).length() < 1e-9);
        let q = ndc(&nav, DVec3::splat(2.0));
        assert!(q.x.abs() < 1.0 && q.y.abs() < 1.0);
        assert!(nav.orbit.distance < 10.0);
    }

    #[test]
    fn spacemouse_motion_moves_turns_and_zooms() {
        let mut nav = nav();
        let target = nav.target();
        let before = ndc(&nav, target);
        nav.spacemouse([0.1, 0.0, 0.0], [0.0; 3]);
        assert!(
            ndc(&nav, target).x > before.x,
            "pushed right, the model goes right"
        );
        let d = nav.orbit.distance;
        nav.spacemouse([0.0, 0.0, 0.2], [0.0; 3]);
        assert!(
            nav.orbit.distance < d,
            "pushed towards the viewer, it comes closer"
        );
        let r = nav.orbit.rotation;
        nav.spacemouse([0.0; 3], [0.0, 0.3, 0.0]);
        assert!(nav.orbit.rotation.angle_between(r) > 0.29);
    }
}
