//! Anti-aliasing by edge smoothing (`FrameOptions::smooth`), against 4 × 4 supersampling as
//! the reference: a smoothed 1× image must come closer to it than the plain 1× image (the
//! negative control), on a fixture drawn shaded and shaded with edges.

mod common;

use common::OneShot;

use cadre_render::{Camera, DisplayMode, FrameOptions, Renderer, ViewPreset};
use common::{gpu, scene};
use image::RgbaImage;

/// Mean absolute difference of the colour channels, in 8-bit steps.
fn mean_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let sum: u64 = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>())
        .sum();
    sum as f64 / (3 * a.width() * a.height()) as f64
}

#[test]
fn smoothing_brings_a_1x_image_closer_to_supersampling() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = scene("pin-assembly.step");
    let (lo, hi) = scene.bounds().expect("fixture has geometry");
    let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, 4.0 / 3.0);
    for mode in [DisplayMode::Shaded, DisplayMode::ShadedEdges] {
        let draw = |supersample, smooth| {
            let options = FrameOptions {
                width: 160,
                height: 120,
                supersample,
                smooth,
                mode,
                ..FrameOptions::default()
            };
            renderer
                .image_of(&gpu, &scene, &camera, &options)
                .expect("render")
        };
        let reference = draw(4, false);
        let (plain, smoothed) = (draw(1, false), draw(1, true));
        let (before, after) = (
            mean_difference(&plain, &reference),
            mean_difference(&smoothed, &reference),
        );
        assert!(
            before > 0.2,
            "{mode:?}: the 1× image should differ from the supersampled one ({before:.3})"
        );
        assert!(
            after < 0.9 * before,
            "{mode:?}: smoothing should come closer to supersampling ({before:.3} → {after:.3})"
        );
        assert_ne!(plain, smoothed, "{mode:?}: smoothing changed nothing");
    }
}
