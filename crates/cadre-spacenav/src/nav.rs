//! Turning raw motion values into camera deltas.
//!
//! # Axis convention
//!
//! spacenavd reports motion in a **left-handed** frame (with its default configuration):
//! `x` to the right, `y` up, `z` *away from the user* (pushing the cap towards the screen is
//! `+z`). Rotations `rx`, `ry`, `rz` are about those axes. Evidence: libspnav's
//! `spnav_posrot_moveobj` (`src/util.c`) uses `(x, y, -z)` and the rotation axis
//! `(rx, ry, -rz)` to drive an OpenGL (right-handed) object, and spacenavd's default config
//! (`cfgfile.c`: `invert-trans = yz`, `invert-rot = yz` on the device axes) produces that frame.
//!
//! [`NavDelta`] is expressed in the usual **right-handed view frame** instead: `x` right,
//! `y` up, `+z` towards the user (the camera looks down `-z`, as in glam/wgpu view space).
//! The conversion negates `z` and `rz`. A `NavDelta` describes how the user moved the cap,
//! i.e. how the *object* should move relative to the view (libspnav's "move object");
//! to move the *camera* instead, apply the inverse (negate both vectors), as libspnav's
//! `spnav_posrot_moveview` does.
//!
//! Rotation components are small angles in radians about the view axes (right-hand rule);
//! use them as a rotation vector (axis × angle).
//!
//! # Time scaling
//!
//! spacenavd sends a motion event whenever the device reports, carrying the *current*
//! deflection of all six axes and `period_ms`, the time since the previous motion event.
//! [`navigation_delta`] multiplies the velocity by that period, so summing the deltas of all
//! events received during a frame integrates the motion independently of the frame rate and
//! of the device report rate. The period is clamped to [`NavSettings::max_period_ms`] because
//! the first event after the cap has been idle carries the whole idle time.
//! Alternatively, keep the latest event as a velocity ([`navigation_velocity`]) and multiply
//! by the frame time yourself (useful if the device stops reporting while held still).

use std::ops::{Add, AddAssign, Mul, Neg};

/// Typical absolute raw value at full deflection of a SpaceNavigator / SpaceMouse at
/// sensitivity 1 (the USB HID logical range is about ±350; some models reach ±512).
pub const FULL_SCALE: f64 = 350.0;

/// Tuning of the raw-motion → camera-delta mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavSettings {
    /// Translation speed at full deflection ([`FULL_SCALE`]), in view units per second.
    pub translation_speed: f64,
    /// Rotation speed at full deflection, in radians per second.
    pub rotation_speed: f64,
    /// Per-axis dead zone in raw units: `|v| <= dead_zone` counts as 0, larger values are
    /// reduced by `dead_zone` so the response starts smoothly at the edge.
    pub dead_zone: i32,
    /// Upper bound for an event's `period_ms` in [`navigation_delta`].
    pub max_period_ms: u32,
}

impl Default for NavSettings {
    /// 1 unit/s and 90°/s at full deflection, dead zone 8, period clamped to 100 ms.
    fn default() -> Self {
        Self {
            translation_speed: 1.0,
            rotation_speed: std::f64::consts::FRAC_PI_2,
            dead_zone: 8,
            max_period_ms: 100,
        }
    }
}

/// A camera/object motion in the right-handed view frame (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavDelta {
    /// Translation `[x right, y up, z towards the user]`, in view units.
    pub translate: [f64; 3],
    /// Rotation vector about `[x, y, z]` of the view frame, radians (right-hand rule).
    pub rotate: [f64; 3],
}

impl NavDelta {
    /// No motion.
    pub const ZERO: Self = Self {
        translate: [0.0; 3],
        rotate: [0.0; 3],
    };

    /// Whether both vectors are exactly zero.
    pub fn is_zero(&self) -> bool {
        *self == Self::ZERO
    }
}

impl Add for NavDelta {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        let mut out = self;
        out += rhs;
        out
    }
}

impl AddAssign for NavDelta {
    fn add_assign(&mut self, rhs: Self) {
        for i in 0..3 {
            self.translate[i] += rhs.translate[i];
            self.rotate[i] += rhs.rotate[i];
        }
    }
}

impl Mul<f64> for NavDelta {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self {
            translate: self.translate.map(|v| v * s),
            rotate: self.rotate.map(|v| v * s),
        }
    }
}

impl Neg for NavDelta {
    type Output = Self;
    fn neg(self) -> Self {
        self * -1.0
    }
}

/// Applies the dead zone to one raw value and normalises it by [`FULL_SCALE`].
fn shape(value: i32, dead_zone: i32) -> f64 {
    let dz = i64::from(dead_zone.max(0));
    let v = i64::from(value);
    let mag = v.abs() - dz;
    if mag <= 0 {
        0.0
    } else {
        (mag * v.signum()) as f64 / FULL_SCALE
    }
}

/// The motion rate (per second) for raw spacenavd values, in the right-handed view frame.
pub fn navigation_velocity(
    translation: [i32; 3],
    rotation: [i32; 3],
    settings: &NavSettings,
) -> NavDelta {
    let t = translation.map(|v| shape(v, settings.dead_zone) * settings.translation_speed);
    let r = rotation.map(|v| shape(v, settings.dead_zone) * settings.rotation_speed);
    // spacenavd's frame is left-handed (z away from the user): flip z and rz.
    NavDelta {
        translate: [t[0], t[1], -t[2]],
        rotate: [r[0], r[1], -r[2]],
    }
}

/// The motion of one spacenavd motion event: [`navigation_velocity`] × the event's period
/// (clamped to `settings.max_period_ms`), in the right-handed view frame.
pub fn navigation_delta(
    translation: [i32; 3],
    rotation: [i32; 3],
    period_ms: u32,
    settings: &NavSettings,
) -> NavDelta {
    let dt = f64::from(period_ms.min(settings.max_period_ms)) / 1000.0;
    if dt == 0.0 {
        return NavDelta::ZERO;
    }
    navigation_velocity(translation, rotation, settings) * dt
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn dead_zone_zeroes_small_values() {
        let s = NavSettings::default();
        let d = navigation_delta([8, -8, 3], [-1, 0, 8], 16, &s);
        assert!(d.is_zero());
        let d = navigation_delta(
            [9, 0, 0],
            [0; 3],
            1000,
            &NavSettings {
                max_period_ms: 1000,
                ..s
            },
        );
        assert!(close(d.translate[0], 1.0 / FULL_SCALE));
    }

    #[test]
    fn full_deflection_for_one_second_moves_speed() {
        let s = NavSettings {
            translation_speed: 2.0,
            rotation_speed: 3.0,
            dead_zone: 0,
            max_period_ms: 2000,
        };
        let full = FULL_SCALE as i32;
        let d = navigation_delta([full, 0, 0], [0, full, 0], 1000, &s);
        assert!(close(d.translate[0], 2.0));
        assert!(close(d.rotate[1], 3.0));
    }

    #[test]
    fn frame_rate_independent() {
        // Same deflection held for 120 ms: 15 events of 8 ms or 4 events of 30 ms.
        let s = NavSettings::default();
        let sum = |n: u32, p: u32| {
            let mut acc = NavDelta::ZERO;
            for _ in 0..n {
                acc += navigation_delta([100, -50, 20], [10, 200, -300], p, &s);
            }
            acc
        };
        let a = sum(15, 8);
        let b = sum(4, 30);
        for i in 0..3 {
            assert!(close(a.translate[i], b.translate[i]));
            assert!(close(a.rotate[i], b.rotate[i]));
        }
    }

    #[test]
    fn period_is_clamped_and_zero_period_is_zero() {
        let s = NavSettings::default();
        let long = navigation_delta([200, 0, 0], [0; 3], 60_000, &s);
        let max = navigation_delta([200, 0, 0], [0; 3], s.max_period_ms, &s);
        assert_eq!(long, max);
        assert!(navigation_delta([200, 0, 0], [0; 3], 0, &s).is_zero());
    }

    #[test]
    fn z_axes_are_flipped_to_right_handed() {
        let s = NavSettings {
            dead_zone: 0,
            ..NavSettings::default()
        };
        // Pushing the cap away from the user (+z in spacenavd) moves along -z in view space.
        let v = navigation_velocity([10, 20, 30], [40, 50, 60], &s);
        assert!(v.translate[0] > 0.0 && v.translate[1] > 0.0 && v.translate[2] < 0.0);
        assert!(v.rotate[0] > 0.0 && v.rotate[1] > 0.0 && v.rotate[2] < 0.0);
    }

    #[test]
    fn extreme_values_do_not_overflow() {
        let s = NavSettings {
            dead_zone: i32::MAX,
            ..NavSettings::default()
        };
        let d = navigation_delta([-i32::MAX, i32::MAX, 0], [i32::MAX; 3], u32::MAX, &s);
        assert!(d.is_zero());
        // |i32::MIN| exceeds i32::MAX by one raw unit.
        let d = navigation_delta([i32::MIN, 0, 0], [0; 3], u32::MAX, &s);
        assert!(d.translate[0] < 0.0 && d.translate[0] > -0.01);
        let s = NavSettings {
            dead_zone: -5,
            ..NavSettings::default()
        };
        let d = navigation_delta([i32::MIN, i32::MAX, 0], [i32::MIN; 3], u32::MAX, &s);
        assert!(d.translate.iter().chain(&d.rotate).all(|v| v.is_finite()));
    }

    #[test]
    fn delta_ops() {
        let a = NavDelta {
            translate: [1.0, 2.0, 3.0],
            rotate: [0.5, 0.0, -0.5],
        };
        assert_eq!(a + (-a), NavDelta::ZERO);
        assert_eq!((a * 2.0).translate, [2.0, 4.0, 6.0]);
    }
}
