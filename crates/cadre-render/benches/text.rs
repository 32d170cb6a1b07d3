//! The text pass at 1080p (issue 20's targets on a GPU: 10,000 glyphs in one draw ≤ 0.3 ms,
//! 3,000 on-screen labels at ≥ 60 fps): a frame of an empty scene (the baseline: clears,
//! shading, readback), the same frame with 3,000 billboard labels of 10,890 glyphs in
//! one draw, and the labels' layout and upload (what a new set of labels costs). The text's
//! cost is the difference of the first two. Run: `cargo bench -p cadre-render --bench text`
//! (`TEXT_BENCH_SIZE=WxH` for another size than 1920x1080).

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use cadre_render::{
    Camera, FrameOptions, Gpu, Label, LabelSet, Projection, RenderScene, Renderer, ViewState,
};
use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;

/// 3,000 numbers on a 60 × 50 grid, 10 px tall: 10,890 glyphs.
fn labels() -> LabelSet {
    LabelSet {
        labels: (0..3000)
            .map(|i| {
                let (x, y) = (f64::from(i % 60), f64::from(i / 60));
                Label::billboard(
                    format!("{i}"),
                    DVec3::new(-480.0 + 16.0 * x, -270.0 + 10.8 * y, 0.0),
                    10.0,
                )
            })
            .collect(),
        fills: Vec::new(),
    }
}

fn bench(c: &mut Criterion) {
    let gpu = Gpu::headless().expect("a GPU or lavapipe");
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let camera = Camera {
        eye: DVec3::new(0.0, 0.0, 1000.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height: 560.0 },
        near: 1.0,
        far: 5000.0,
    };
    let (w, h) = std::env::var("TEXT_BENCH_SIZE")
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
    let set = labels();
    let scene = RenderScene::default().with_labels(set.clone());
    let text = renderer.prepare(&gpu, &scene);
    eprintln!(
        "{} labels, {} glyph quads in one draw, on {}",
        set.labels.len(),
        text.text_quads(),
        gpu.info.name
    );
    let state = ViewState::default();
    let mut group = c.benchmark_group("text 1080p");
    group.sample_size(10);
    group.bench_function("empty frame", |b| {
        b.iter(|| {
            renderer
                .render(&gpu, &empty, &camera, &options, &state)
                .unwrap()
        })
    });
    group.bench_function("3,000 labels (10k glyphs), one draw", |b| {
        b.iter(|| {
            renderer
                .render(&gpu, &text, &camera, &options, &state)
                .unwrap()
        })
    });
    let mut prepared = renderer.prepare(&gpu, &RenderScene::default());
    group.bench_function("3,000 labels laid out and uploaded", |b| {
        b.iter(|| renderer.replace_labels(&gpu, &mut prepared, &set))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
