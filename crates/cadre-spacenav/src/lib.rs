//! 3D mouse (3Dconnexion SpaceMouse, SpaceNavigator, …) input for cadre through the free
//! [spacenavd](https://github.com/FreeSpacenav/spacenavd) daemon's Unix-socket protocol — the
//! protocol libspnav speaks — without linking libspnav.
//!
//! * [`SpaceNav`]: a non-blocking client. [`SpaceNav::connect`] finds the socket like libspnav
//!   (`$SPNAV_SOCKET`, then `socket = …` in `/etc/spnavrc`, then `/var/run/spnav.sock`);
//!   [`SpaceNav::poll`] returns every complete event available without blocking.
//!   The original protocol (v0) is used unless [`SpaceNav::negotiate_protocol`] is called,
//!   which upgrades to v1 when the daemon supports it (device queries, hot-plug events).
//! * [`navigation_delta`]: frame-rate independent conversion of a motion event into a
//!   camera/object delta in a right-handed view frame (see [`nav`] for the axis convention).
//! * [`sim::SimDaemon`]: a simulated spacenavd writing the exact bytes spacenavd writes, for
//!   tests and manual runs (`cargo run -p cadre-spacenav --example spacenav_sim -- PATH`).
//!
//! See [`protocol`] for the wire format.

mod client;
pub mod nav;
pub mod protocol;
pub mod sim;

pub use client::{
    DEFAULT_SOCKET_PATH, DeviceInfo, SpaceNav, SpaceNavError, parse_spnavrc_socket,
    socket_path_candidates,
};
pub use nav::{NavDelta, NavSettings, navigation_delta, navigation_velocity};

/// One input event from the daemon.
///
/// `Motion` values are in spacenavd's left-handed device frame (x right, y up, z away from
/// the user), already scaled by the daemon's sensitivity settings; typical full deflection is
/// about ±350 (see [`nav::FULL_SCALE`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SpaceEvent {
    /// Current deflection of the cap (all six axes, not a difference).
    Motion {
        /// `[x, y, z]` translation deflection.
        translation: [i32; 3],
        /// `[rx, ry, rz]` rotation deflection.
        rotation: [i32; 3],
        /// Milliseconds since the previous motion event of the device.
        period_ms: u32,
    },
    /// A button changed state.
    Button {
        /// Button number (after the daemon's button mapping), from 0.
        number: u32,
        /// `true` on press, `false` on release.
        pressed: bool,
    },
    /// A device was added or removed (protocol v1 only, after
    /// [`SpaceNav::negotiate_protocol`]).
    Device {
        /// `true` when added, `false` when removed.
        added: bool,
        /// Daemon-assigned device id.
        id: i32,
        /// Device type (spacenavd `DEV_*` enum, e.g. `0x206` = SpaceNavigator).
        device_type: i32,
        /// USB `[vendor, product]` id, `[0, 0]` for serial devices.
        usb_id: [u16; 2],
    },
}

impl SpaceEvent {
    /// For a `Motion` event, its [`navigation_delta`]; `None` for other events.
    pub fn navigation_delta(&self, settings: &NavSettings) -> Option<NavDelta> {
        match *self {
            SpaceEvent::Motion {
                translation,
                rotation,
                period_ms,
            } => Some(navigation_delta(translation, rotation, period_ms, settings)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn event_delta_only_for_motion() {
        let s = NavSettings::default();
        let m = SpaceEvent::Motion {
            translation: [100, 0, 0],
            rotation: [0; 3],
            period_ms: 10,
        };
        assert!(m.navigation_delta(&s).is_some_and(|d| d.translate[0] > 0.0));
        let b = SpaceEvent::Button {
            number: 0,
            pressed: true,
        };
        assert_eq!(b.navigation_delta(&s), None);
    }
}
