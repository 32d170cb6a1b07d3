//! The lines pass at 1080p (issue 19's target: 10⁶ segments, scan + draw, ≤ 1 ms on a GPU):
//! a frame of an empty scene (the baseline: clears, shading, readback), the same frame with
//! 10⁶ stippled segments (a spiral of sub-pixel segments and 1,000 toolpath-like zigzags),
//! and the scan alone (with its 4 MB readback). The lines' cost is the difference of the
//! first two. Run: `cargo bench -p cadre-render --bench lines` (`LINES_BENCH_SIZE=WxH` for
//! another size than 1920x1080: a small one leaves the fragments out of the cost).

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use cadre_render::{
    Camera, FrameOptions, Gpu, LineSet, LineStyle, LineWidth, Polyline, Projection, RenderScene,
    Renderer, Stipple, ViewState,
};
use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;

fn million_segments() -> LineSet {
    let n = 500_000;
    let spiral = Polyline {
        points: (0..=n)
            .map(|k| {
                let f = k as f64 / n as f64;
                let a = f * 200.0 * std::f64::consts::TAU;
                let r = 50.0 + 400.0 * f;
                DVec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect(),
        style: 0,
        colours: Vec::new(),
    };
    let mut polylines = vec![spiral];
    for k in 0..1000 {
        let y = -450.0 + 0.9 * f64::from(k);
        polylines.push(Polyline {
            points: (0..=500)
                .map(|j| DVec3::new(-450.0 + 1.8 * f64::from(j), y + f64::from(j % 2), 1.0))
                .collect(),
            style: 1,
            colours: Vec::new(),
        });
    }
    LineSet {
        polylines,
        styles: vec![
            LineStyle {
                stipple: Stipple::parse("dash-dot", 2).unwrap(),
                ..LineStyle::default()
            },
            LineStyle {
                width: LineWidth::Pixels(1.0),
                colour: [0.8, 0.2, 0.1, 1.0],
                ..LineStyle::default()
            },
        ],
    }
}

fn bench(c: &mut Criterion) {
    let gpu = Gpu::headless().expect("a GPU or lavapipe");
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let camera = Camera {
        eye: DVec3::new(0.0, 0.0, 1000.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height: 1000.0 },
        near: 1.0,
        far: 5000.0,
    };
    let (w, h) = std::env::var("LINES_BENCH_SIZE")
        .ok()
        .and_then(|s| {
            let (a, b) = s.split_once('x')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        })
        .unwrap_or((1920, 1080));
    let options = FrameOptions {
        width: w,
        height: h,
        supersample: 1,
        ..FrameOptions::default()
    };
    let empty = renderer.prepare(&gpu, &RenderScene::default());
    let set = million_segments();
    eprintln!("{} segments on {}", set.segment_count(), gpu.info.name);
    let lines = renderer.prepare(&gpu, &RenderScene::default().with_lines(set));
    let state = ViewState::default();
    let mut group = c.benchmark_group("lines 1080p");
    group.sample_size(10);
    group.bench_function("empty frame", |b| {
        b.iter(|| {
            renderer
                .render(&gpu, &empty, &camera, &options, &state)
                .unwrap()
        })
    });
    group.bench_function("10^6 segments, scan + draw", |b| {
        b.iter(|| {
            renderer
                .render(&gpu, &lines, &camera, &options, &state)
                .unwrap()
        })
    });
    group.bench_function("10^6 segments, scan + readback", |b| {
        b.iter(|| {
            renderer
                .line_arc_lengths(&gpu, &lines, &camera, (w, h))
                .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
