//! Interpreting a 10⁶-move program (the target: loaded in ≤ 1 s): a generated
//! pocketing program of feeds, arcs and rapids, as a CAM post-processor writes it.

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};

/// A program of about `moves` moves: rows of G1 feeds joined by G3 half circles, a rapid
/// every 100 moves.
pub fn pocket(moves: usize) -> String {
    let mut text = String::with_capacity(moves * 24);
    text.push_str("%\nG21 G90 G17\nT1 M6\nS12000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F800\n");
    let mut y = 0.0f64;
    for k in 0..moves {
        if k % 100 == 99 {
            text.push_str(&format!("G0 Z5\nG0 X0 Y{y:.3}\nG1 Z-1\n"));
        } else if k % 2 == 0 {
            let x = if (k / 2) % 2 == 0 { 50.0 } else { 0.0 };
            text.push_str(&format!("G1 X{x:.3} Y{y:.3} F1200\n"));
        } else {
            y += 0.5;
            text.push_str(&format!("G3 Y{y:.3} R0.25\n"));
        }
    }
    text.push_str("M30\n%\n");
    text
}

fn bench(c: &mut Criterion) {
    let text = pocket(1_000_000);
    let mut group = c.benchmark_group("gcode");
    group.sample_size(10);
    group.bench_function("interpret 10^6 moves", |b| {
        b.iter(|| cadre_gcode::interpret(&text))
    });
    let program = cadre_gcode::interpret(&text);
    group.bench_function("sample 10^6 moves at 1 µm", |b| {
        b.iter(|| cadre_gcode::sample_moves(&program.moves, 1e-3))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
