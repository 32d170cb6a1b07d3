//! A scripted fake spacenavd for trying the 3D-mouse support without a device.
//!
//! ```text
//! cargo run -p cadre-spacenav --example spacenav_sim -- /tmp/spnav.sock [--loop] [--packets N] [--interval-ms MS]
//! SPNAV_SOCKET=/tmp/spnav.sock cadre view model.step
//! ```
//!
//! Waits for a client, then plays: orbit (rotate about y), pan right, push towards the
//! screen, press and release button 0, press and release button 1. `--loop` repeats forever.

use std::process::ExitCode;
use std::time::Duration;

use cadre_spacenav::sim::SimDaemon;

struct Args {
    path: String,
    repeat: bool,
    packets: u32,
    interval_ms: u32,
}

fn parse_args() -> Result<Args, String> {
    let mut args = std::env::args().skip(1);
    let mut out = Args {
        path: String::new(),
        repeat: false,
        packets: 120,
        interval_ms: 16,
    };
    while let Some(arg) = args.next() {
        let mut number = |name: &str| -> Result<u32, String> {
            args.next()
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| format!("{name} needs a number"))
        };
        match arg.as_str() {
            "--loop" => out.repeat = true,
            "--packets" => out.packets = number("--packets")?,
            "--interval-ms" => out.interval_ms = number("--interval-ms")?.max(1),
            "-h" | "--help" => return Err(String::new()),
            _ if out.path.is_empty() && !arg.starts_with('-') => out.path = arg,
            _ => return Err(format!("unexpected argument {arg:?}")),
        }
    }
    if out.path.is_empty() {
        return Err("missing socket path".into());
    }
    Ok(out)
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(msg) => {
            if !msg.is_empty() {
                eprintln!("error: {msg}");
            }
            eprintln!("usage: spacenav_sim SOCKET_PATH [--loop] [--packets N] [--interval-ms MS]");
            return ExitCode::from(2);
        }
    };
    let daemon = match SimDaemon::bind(&args.path) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: cannot bind {}: {e}", args.path);
            return ExitCode::FAILURE;
        }
    };
    eprintln!(
        "spacenav_sim: listening on {} (set SPNAV_SOCKET to this path)",
        args.path
    );
    if !daemon.wait_for_clients(1, Duration::from_secs(600)) {
        eprintln!("spacenav_sim: no client connected within 10 minutes");
        return ExitCode::FAILURE;
    }
    eprintln!("spacenav_sim: client connected, playing script");
    let pause = Duration::from_millis(u64::from(args.interval_ms));
    let hold = |t: [i32; 3], r: [i32; 3], what: &str| {
        eprintln!("spacenav_sim: {what}");
        for _ in 0..args.packets {
            daemon.send_motion(t, r, args.interval_ms);
            std::thread::sleep(pause);
        }
        // Cap released: spacenavd reports the return to centre.
        daemon.send_motion([0; 3], [0; 3], args.interval_ms);
        std::thread::sleep(pause * 10);
    };
    let click = |n: u32| {
        eprintln!("spacenav_sim: button {n}");
        daemon.send_button(n, true);
        std::thread::sleep(Duration::from_millis(100));
        daemon.send_button(n, false);
        std::thread::sleep(Duration::from_millis(300));
    };
    loop {
        hold([0; 3], [0, 150, 0], "rotate about y");
        hold([150, 0, 0], [0; 3], "pan right");
        hold([0, 0, 150], [0; 3], "push towards the screen");
        click(0);
        click(1);
        if !args.repeat || daemon.client_count() == 0 {
            break;
        }
    }
    eprintln!("spacenav_sim: done");
    ExitCode::SUCCESS
}
