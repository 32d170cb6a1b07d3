//! Trimmed edges anti-aliased by their analytic coverage: an image of faces trimmed per pixel,
//! drawn once (no supersampling) with each pixel on a trimmed edge blended by its distance
//! to the trim boundary, is nearer the 4 × 4 supersampled image of the same view than the
//! same image without the coverage (the error summed over the whole image, so pixels the
//! coverage spoils count against it). Negative control: the image without the coverage is
//! measurably off.

mod common;

use cadre_render::{Camera, DisplayMode, FrameOptions, Renderer, ViewPreset};
use common::{OneShot, gpu};
use image::RgbaImage;

/// Sum over RGB of the absolute difference of two pixels (sRGB, 0–765).
fn distance(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> u32 {
    (0..3).map(|c| u32::from(a[c].abs_diff(b[c]))).sum()
}

#[test]
fn trimmed_edges_take_their_analytic_coverage() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    for name in ["pin-assembly.step", "dome-and-cone.step"] {
        let (model, mesh) = common::model_and_scene(name);
        let scene = mesh.with_trims(&model, 0.001);
        let (lo, hi) = scene.bounds().expect("geometry");
        let (w, h) = (160, 120);
        let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, f64::from(w) / f64::from(h));
        let image = |supersample: u32, analytic_coverage: bool| -> RgbaImage {
            let options = FrameOptions {
                width: w,
                height: h,
                supersample,
                analytic_coverage,
                mode: DisplayMode::Shaded,
                ..FrameOptions::default()
            };
            renderer
                .image_of(&gpu, &scene, &camera, &options)
                .expect("render")
        };
        let reference = image(4, false);
        let sharp = image(1, false);
        let covered = image(1, true);
        // The whole image's error against the supersampled one: the edges (where one sample
        // a pixel is off it) and everything else.
        let (mut edges, mut sharp_error, mut covered_error, mut changed) = (0, 0, 0, 0);
        for ((r, s), c) in reference.pixels().zip(sharp.pixels()).zip(covered.pixels()) {
            edges += u32::from(distance(r, s) > 24);
            sharp_error += distance(r, s);
            covered_error += distance(r, c);
            changed += u32::from(distance(s, c) > 0);
        }
        eprintln!(
            "{name}: {edges} edge pixels, {changed} pixels changed by the coverage; error {sharp_error} sharp, {covered_error} with coverage"
        );
        assert!(edges > 50, "{name}: only {edges} edge pixels");
        assert!(
            changed > 50,
            "{name}: the coverage changed {changed} pixels only"
        );
        assert!(
            (covered_error as f64) < 0.85 * sharp_error as f64,
            "{name}: the coverage brought the image's error from {sharp_error} to {covered_error} only"
        );
    }
}
