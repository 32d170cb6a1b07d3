//! End-to-end tests: a `SpaceNav` client against the simulated spacenavd on a temp socket.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use cadre_spacenav::protocol::{self, encode_packet};
use cadre_spacenav::sim::{SimConfig, SimDaemon};
use cadre_spacenav::{NavSettings, SpaceEvent, SpaceNav, SpaceNavError};

const DEADLINE: Duration = Duration::from_secs(5);

fn temp_socket() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("cadre-spnav-{}-{n}.sock", std::process::id()))
}

fn start(config: SimConfig) -> (SimDaemon, SpaceNav) {
    let daemon = SimDaemon::bind_with(temp_socket(), config).expect("bind sim daemon");
    let nav = SpaceNav::connect_to(daemon.path()).expect("connect");
    assert!(
        daemon.wait_for_clients(1, DEADLINE),
        "sim never accepted the client"
    );
    (daemon, nav)
}

/// Polls until `want` events arrived (or the deadline passes).
fn collect(nav: &mut SpaceNav, want: usize) -> Vec<SpaceEvent> {
    let deadline = Instant::now() + DEADLINE;
    let mut events = Vec::new();
    while events.len() < want && Instant::now() < deadline {
        events.extend(nav.poll().expect("poll"));
        std::thread::sleep(Duration::from_millis(1));
    }
    events
}

fn motion(t: [i32; 3], r: [i32; 3], p: u32) -> SpaceEvent {
    SpaceEvent::Motion {
        translation: t,
        rotation: r,
        period_ms: p,
    }
}

fn button(number: u32, pressed: bool) -> SpaceEvent {
    SpaceEvent::Button { number, pressed }
}

#[test]
fn motion_and_buttons_arrive_in_order() {
    let (daemon, mut nav) = start(SimConfig::default());
    assert!(nav.poll().unwrap().is_empty(), "nothing sent yet");
    assert_eq!(daemon.send_motion([1, -2, 3], [-4, 5, -350], 16), 1);
    daemon.send_button(0, true);
    daemon.send_button(0, false);
    daemon.send_motion([0; 3], [0; 3], 8);
    daemon.send_button(11, true);
    let events = collect(&mut nav, 5);
    assert_eq!(
        events,
        [
            motion([1, -2, 3], [-4, 5, -350], 16),
            button(0, true),
            button(0, false),
            motion([0; 3], [0; 3], 8),
            button(11, true),
        ]
    );
    assert!(
        events[0]
            .navigation_delta(&NavSettings::default())
            .is_some()
    );
    assert_eq!(nav.protocol_version(), 0);
}

#[test]
fn many_packets_span_several_polls() {
    let (daemon, mut nav) = start(SimConfig::default());
    for i in 0..5000 {
        daemon.send_motion([i, 0, 0], [0, -i, 0], 1);
    }
    let events = collect(&mut nav, 5000);
    assert_eq!(events.len(), 5000);
    for (i, ev) in events.iter().enumerate() {
        let i = i as i32;
        assert_eq!(*ev, motion([i, 0, 0], [0, -i, 0], 1));
    }
}

#[test]
fn partial_packets_are_buffered_across_polls() {
    let (daemon, mut nav) = start(SimConfig::default());
    let packet = protocol::motion_packet([10, 20, 30], [40, 50, 60], 7);
    daemon.send_raw(&packet[..13]);
    // Give the half packet time to arrive; it must not produce an event.
    std::thread::sleep(Duration::from_millis(50));
    assert!(nav.poll().unwrap().is_empty());
    daemon.send_raw(&packet[13..]);
    // Then a button split 4 + 28 bytes around a complete packet boundary.
    let b = protocol::button_packet(2, true);
    daemon.send_raw(&b[..4]);
    std::thread::sleep(Duration::from_millis(20));
    let first = collect(&mut nav, 1);
    assert_eq!(first, [motion([10, 20, 30], [40, 50, 60], 7)]);
    daemon.send_raw(&b[4..]);
    assert_eq!(collect(&mut nav, 1), [button(2, true)]);
}

#[test]
fn garbage_packets_are_skipped() {
    let (daemon, mut nav) = start(SimConfig::default());
    daemon.send_raw(&encode_packet(&[99, 1, 2, 3, 4, 5, 6, 7]));
    daemon.send_raw(&encode_packet(&[-1, -1, -1, -1, -1, -1, -1, -1]));
    daemon.send_raw(&encode_packet(&[protocol::UEV_CFG, 0, 0, 0, 0, 0, 0, 0]));
    daemon.send_raw(&encode_packet(&[5, 0, 0, 0, 0, 0, 0, 0])); // raw axis event
    daemon.send_raw(&encode_packet(&[i32::MIN, i32::MAX, 0, 0, 0, 0, 0, 0]));
    daemon.send_raw(&[0xff; 32]);
    daemon.send_button(4, true);
    assert_eq!(collect(&mut nav, 1), [button(4, true)]);
    std::thread::sleep(Duration::from_millis(20));
    assert!(nav.poll().unwrap().is_empty());
}

#[test]
fn disconnect_is_reported_and_reconnect_works() {
    let (daemon, mut nav) = start(SimConfig::default());
    daemon.send_button(1, true);
    daemon.disconnect_all();
    // Events sent before the close are still delivered, then Disconnected.
    let deadline = Instant::now() + DEADLINE;
    let mut events = Vec::new();
    let err = loop {
        match nav.poll() {
            Ok(evs) => events.extend(evs),
            Err(e) => break e,
        }
        assert!(Instant::now() < deadline, "no disconnect seen");
        std::thread::sleep(Duration::from_millis(1));
    };
    assert!(matches!(err, SpaceNavError::Disconnected), "{err}");
    assert_eq!(events, [button(1, true)]);
    // Stays disconnected.
    assert!(matches!(nav.poll(), Err(SpaceNavError::Disconnected)));

    let mut nav = SpaceNav::connect_to(daemon.path()).expect("reconnect");
    assert!(daemon.wait_for_clients(1, DEADLINE));
    daemon.send_button(1, false);
    assert_eq!(collect(&mut nav, 1), [button(1, false)]);
}

#[test]
fn daemon_exit_gives_disconnected_and_connect_error() {
    let (daemon, mut nav) = start(SimConfig::default());
    let path = daemon.path().to_path_buf();
    drop(daemon);
    let deadline = Instant::now() + DEADLINE;
    loop {
        match nav.poll() {
            Err(SpaceNavError::Disconnected) => break,
            Ok(evs) => assert!(evs.is_empty()),
            Err(e) => panic!("unexpected error {e}"),
        }
        assert!(Instant::now() < deadline, "no disconnect seen");
        std::thread::sleep(Duration::from_millis(1));
    }
    assert!(matches!(
        SpaceNav::connect_to(&path),
        Err(SpaceNavError::Connect { .. })
    ));
}

#[test]
fn v0_sensitivity_is_applied_by_daemon() {
    let (daemon, mut nav) = start(SimConfig::default());
    nav.set_sensitivity(2.0).unwrap();
    let deadline = Instant::now() + DEADLINE;
    while daemon.client_sensitivities() != [2.0] {
        assert!(Instant::now() < deadline, "sensitivity never set");
        std::thread::sleep(Duration::from_millis(1));
    }
    daemon.send_motion([10, 0, 0], [0, 0, -5], 4);
    assert_eq!(collect(&mut nav, 1), [motion([20, 0, 0], [0, 0, -10], 4)]);
    assert!(matches!(
        nav.set_sensitivity(f32::NAN),
        Err(SpaceNavError::InvalidSensitivity(_))
    ));
}

#[test]
fn v1_handshake_and_device_queries() {
    let (daemon, mut nav) = start(SimConfig::default());
    // v1 calls are refused before negotiation.
    assert!(matches!(
        nav.device_info(Duration::from_secs(1)),
        Err(SpaceNavError::ProtocolUnsupported(0))
    ));
    // An event sent before the handshake must not desynchronise the stream.
    daemon.send_button(3, true);
    assert_eq!(nav.negotiate_protocol(DEADLINE).unwrap(), 1);
    assert_eq!(nav.protocol_version(), 1);
    let info = nav.device_info(DEADLINE).unwrap();
    assert_eq!(info.num_axes, Some(6));
    assert_eq!(info.num_buttons, Some(2));
    assert_eq!(info.usb_id, Some([0x046d, 0xc626]));
    assert_eq!(info.device_type, Some(0x206));
    nav.set_sensitivity(0.5).unwrap();
    assert_eq!(daemon.client_sensitivities(), [0.5]);
    assert_eq!(daemon.client_protocols(), [1]);

    assert_eq!(daemon.send_device(true, 7), 1);
    daemon.send_motion([100, 0, 0], [0; 3], 9);
    let events = collect(&mut nav, 3);
    assert_eq!(
        events,
        [
            button(3, true),
            SpaceEvent::Device {
                added: true,
                id: 7,
                device_type: 0x206,
                usb_id: [0x046d, 0xc626],
            },
            motion([50, 0, 0], [0; 3], 9),
        ]
    );
}

#[test]
fn old_daemon_keeps_v0_and_restores_sensitivity() {
    let old = SimConfig {
        max_protocol: 0,
        usb_id: None,
        ..SimConfig::default()
    };
    let (daemon, mut nav) = start(old);
    // No answer ever comes: the timeout decides, whatever the machine's speed.
    assert_eq!(
        nav.negotiate_protocol(Duration::from_millis(200)).unwrap(),
        0
    );
    assert!(matches!(
        nav.device_info(Duration::from_secs(1)),
        Err(SpaceNavError::ProtocolUnsupported(0))
    ));
    daemon.send_motion([1, 2, 3], [4, 5, 6], 10);
    assert_eq!(collect(&mut nav, 1), [motion([1, 2, 3], [4, 5, 6], 10)]);
    assert_eq!(daemon.client_sensitivities(), [1.0]);
    assert_eq!(daemon.client_protocols(), [0]);
}

#[test]
fn two_clients_both_receive() {
    let daemon = SimDaemon::bind(temp_socket()).unwrap();
    let mut a = SpaceNav::connect_to(daemon.path()).unwrap();
    let mut b = SpaceNav::connect_to(daemon.path()).unwrap();
    assert!(daemon.wait_for_clients(2, DEADLINE));
    assert_eq!(daemon.send_button(0, true), 2);
    assert_eq!(collect(&mut a, 1), [button(0, true)]);
    assert_eq!(collect(&mut b, 1), [button(0, true)]);
    drop(a);
    let deadline = Instant::now() + DEADLINE;
    while daemon.client_count() != 1 {
        assert!(Instant::now() < deadline, "closed client not dropped");
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[test]
fn stale_socket_file_is_replaced() {
    let path = temp_socket();
    let first = SimDaemon::bind(&path).unwrap();
    // Simulate a crashed daemon that left its socket file behind.
    std::mem::forget(first);
    let daemon = SimDaemon::bind(&path).expect("rebind over stale socket");
    let mut nav = SpaceNav::connect_to(&path).unwrap();
    assert!(daemon.wait_for_clients(1, DEADLINE));
    daemon.send_button(9, false);
    assert_eq!(collect(&mut nav, 1), [button(9, false)]);
}
