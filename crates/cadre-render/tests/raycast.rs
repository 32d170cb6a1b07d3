//! The CPU ray caster (the oracle of every GPU path) against an independent one: the torus
//! elbow fixture (a quarter of a torus tube, R = 10, r = 3, capped by two discs), whose
//! solid is `(ρ − 10)² + z² ≤ 9` with the angle about z in [0, π/2], marched along each
//! ray and bisected to the entry point, whose face follows from where it lies. The ray
//! caster reaches the torus through its cell tree and Newton's method, so this checks that
//! path on fitted views and close-ups, where rays graze the tube (without the refinement of
//! grazing cells, the front view at 30× loses 213 pixels). Negative control: another view's
//! image disagrees.

mod common;

use cadre_render::raycast::{PixelRays, RayCaster};
use cadre_render::{Camera, ViewPreset};
use glam::{DVec2, DVec3};

/// STEP ids of the elbow's faces.
const OUTER: u64 = 66;
const INNER: u64 = 76;
const CAP_AT_0: u64 = 86;
const CAP_AT_90: u64 = 97;

/// Whether `p` is inside the elbow.
fn inside(p: DVec3) -> bool {
    let rho = p.x.hypot(p.y);
    p.x >= 0.0 && p.y >= 0.0 && (rho - 10.0).powi(2) + p.z * p.z <= 9.0
}

/// The face of the elbow's boundary point `p`.
fn face_at(p: DVec3) -> u64 {
    let rho = p.x.hypot(p.y);
    let tube = ((rho - 10.0).powi(2) + p.z * p.z).sqrt();
    // The nearer of the caps' planes and the torus.
    let candidates = [
        (p.y.abs(), CAP_AT_0),
        (p.x.abs(), CAP_AT_90),
        ((tube - 3.0).abs(), if rho > 10.0 { OUTER } else { INNER }),
    ];
    candidates
        .iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("three")
        .1
}

/// The face the ray `o + t·d` enters the elbow through (0 if none): marched in steps of
/// 1/4,000 of its path through the elbow's box, then bisected.
fn marched(o: DVec3, d: DVec3) -> (u64, Option<DVec3>) {
    let (lo, hi) = (DVec3::new(-4.0, -4.0, -4.0), DVec3::new(14.0, 14.0, 4.0));
    let inv = d.recip();
    let (a, b) = ((lo - o) * inv, (hi - o) * inv);
    let (t0, t1) = (a.min(b).max_element().max(0.0), a.max(b).min_element());
    if t0 > t1 {
        return (0, None);
    }
    let step = (t1 - t0) / 4000.0;
    let mut prev = t0;
    for k in 1..=4000 {
        let t = t0 + step * f64::from(k);
        if inside(o + d * t) {
            let (mut out, mut inn) = (prev, t);
            for _ in 0..80 {
                let mid = 0.5 * (out + inn);
                if inside(o + d * mid) {
                    inn = mid;
                } else {
                    out = mid;
                }
            }
            let p = o + d * inn;
            return (face_at(p), Some(p));
        }
        prev = t;
    }
    (0, None)
}

/// The marched image's face ids, and per pixel whether its 3 × 3 neighbourhood shows one
/// face (the pixels compared).
fn marched_image(camera: &Camera, (w, h): (u32, u32)) -> (Vec<u64>, Vec<bool>) {
    let rays = PixelRays::new(camera, w, h);
    let ids: Vec<u64> = (0..w * h)
        .map(|i| {
            let (o, d) = rays.through(DVec2::new(f64::from(i % w), f64::from(i / w)));
            marched(o, d).0
        })
        .collect();
    let (w, h) = (w as usize, h as usize);
    let interior = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            x > 0
                && y > 0
                && x + 1 < w
                && y + 1 < h
                && (y - 1..=y + 1).all(|b| (x - 1..=x + 1).all(|a| ids[b * w + a] == ids[i]))
        })
        .collect();
    (ids, interior)
}

#[test]
fn the_ray_caster_agrees_with_a_marched_torus_elbow() {
    let (model, scene) = common::model_and_scene_at("torus-elbow.step", 0.01);
    let caster = RayCaster::new(&model, 1e-4);
    assert!(caster.skipped.is_empty(), "{:?}", caster.skipped);
    let (lo, hi) = scene.bounds().expect("geometry");
    let size = (96u32, 72u32);
    let mut compared = 0usize;
    let mut previous: Option<Vec<u64>> = None;
    for view in [
        ViewPreset::Iso,
        ViewPreset::Front,
        ViewPreset::Top,
        ViewPreset::Right,
    ] {
        let fitted = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
        // Close-ups about the surface point at the centre, where rays graze the tube.
        let (o, d) = PixelRays::new(&fitted, size.0, size.1).through(DVec2::new(48.0, 36.0));
        let centre = marched(o, d).1.unwrap_or(0.5 * (lo + hi));
        for zoom in [1.0, 30.0, 1000.0] {
            let camera = fitted.zoomed_at(centre, zoom, (lo, hi));
            let (expected, interior) = marched_image(&camera, size);
            let cast = caster.face_ids(&camera, size.0, size.1);
            let kept: Vec<usize> = (0..expected.len()).filter(|&i| interior[i]).collect();
            let wrong: Vec<usize> = kept
                .iter()
                .copied()
                .filter(|&i| cast[i] != expected[i])
                .collect();
            assert!(
                wrong.is_empty(),
                "{view:?} ×{zoom}: {} of {} pixels differ, e.g. pixel {} cast {} marched {}",
                wrong.len(),
                kept.len(),
                wrong[0],
                cast[wrong[0]],
                expected[wrong[0]]
            );
            compared += kept.iter().filter(|&&i| expected[i] != 0).count();
            // Negative control: the previous view's image is not this one.
            if zoom == 1.0
                && let Some(other) = previous.replace(expected.clone())
            {
                let covered: Vec<usize> = kept
                    .iter()
                    .copied()
                    .filter(|&i| other[i] != 0 || expected[i] != 0)
                    .collect();
                let same = covered.iter().filter(|&&i| other[i] == expected[i]).count();
                assert!(
                    (same as f64) < 0.8 * covered.len() as f64,
                    "{view:?}: another view agreed on {same} of {}",
                    covered.len()
                );
            }
        }
    }
    assert!(compared > 5000, "only {compared} covered pixels compared");
}
