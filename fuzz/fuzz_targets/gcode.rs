//! Fuzzes the G-code interpreter (`cadre_gcode`): arbitrary bytes as a CAM program. Beyond
//! "no panic, no hang, no unbounded allocation" (loops and calls are bounded by the limits
//! below), it checks that every warning names a line of the program, that every move ends at
//! a finite point, and that sampling the moves for drawing terminates with finite points.
//!
//!   cargo +nightly fuzz run gcode -- -dict=fuzz/gcode.dict -max_len=4096

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let limits = cadre_gcode::Limits {
        max_blocks: 200_000,
        max_moves: 100_000,
        ..cadre_gcode::Limits::default()
    };
    let program = cadre_gcode::interpret_with(&text, &limits);
    let lines = text.lines().count() as u32;
    for w in &program.warnings {
        assert!(w.line <= lines.max(1), "line {} of {lines}", w.line);
    }
    for m in &program.moves {
        assert!(m.end.iter().all(|v| v.is_finite()), "{m:?}");
        assert!(m.turns.is_none_or(f64::is_finite), "{m:?}");
    }
    for run in cadre_gcode::sample_moves(&program.moves, 0.01) {
        assert!(run.points.iter().all(|p| p.is_finite()));
    }
});
