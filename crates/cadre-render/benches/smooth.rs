//! Edge smoothing of a rendered image (the CPU adapters' anti-aliasing): `cargo bench -p
//! cadre-render --bench smooth`, on synthetic images of disks on white (no GPU needed).

#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented function"
)]

use cadre_render::smooth_edges;
use criterion::{Criterion, criterion_group, criterion_main};
use image::{Rgba, RgbaImage};

/// Disks of several colours on white: about the proportion of edge pixels of a CAD image.
fn disks(w: u32, h: u32) -> RgbaImage {
    let centres = [
        (0.3, 0.4, 0.2),
        (0.6, 0.55, 0.25),
        (0.75, 0.3, 0.1),
        (0.45, 0.75, 0.12),
    ];
    let colours = [[160, 60, 220], [200, 210, 40], [90, 90, 95], [20, 20, 25]];
    RgbaImage::from_fn(w, h, |x, y| {
        let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
        for (&(cx, cy, r), c) in centres.iter().zip(colours) {
            if (u - cx).powi(2) + ((v - cy) * h as f32 / w as f32).powi(2) < r * r {
                return Rgba([c[0], c[1], c[2], 255]);
            }
        }
        Rgba([255, 255, 255, 255])
    })
}

fn bench(c: &mut Criterion) {
    for (w, h) in [(800, 600), (1280, 960)] {
        let image = disks(w, h);
        c.bench_function(&format!("smooth_edges {w}x{h}"), |b| {
            b.iter(|| smooth_edges(std::hint::black_box(&image)))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
