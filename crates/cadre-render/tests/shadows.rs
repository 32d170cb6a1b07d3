//! Shadows of the key light (issue 18 item 4): a ray-cast sphere above a ray-cast plate, lit
//! at 45° and seen from straight above, casts the sphere's exact shadow, the ellipse of
//! semi-axes r √2 and r (π r² √2), from the hits' depth in the shadow map. Negative controls:
//! without shadows nothing darkens; with the proxies' depth written (the screen rectangles'
//! constant depth, from the light as from the eye) the shadow is not the ellipse.

mod common;

use std::sync::Arc;

use cadre_geom::{CutKind, CutQuadric, Frame, HalfSpace, Quadric};
use cadre_render::{
    AnalyticPrimitive, AnalyticShape, Camera, FrameOptions, Light, Projection, QuadricShape,
    RenderScene, Renderer, ViewState,
};
use common::gpu;
use glam::DVec3;

const SIZE: u32 = 160;
/// The sphere's radius and the view's height (model units): the sphere is 29 pixels wide.
const RADIUS: f64 = 1.0;
const VIEW: f64 = 11.0;
/// The sphere's centre above the plate: its shadow, 3 to +x, clears its image.
const HEIGHT: f64 = 3.0;

fn scene() -> RenderScene {
    let plate = CutQuadric {
        quadric: Quadric::cylinder(5.0),
        planes: vec![
            HalfSpace::through(DVec3::ZERO, DVec3::Z),
            HalfSpace::through(DVec3::new(0.0, 0.0, -0.2), -DVec3::Z),
        ],
        kind: CutKind::Volume,
    };
    let sphere = CutQuadric {
        quadric: Quadric::sphere(RADIUS),
        planes: vec![],
        kind: CutKind::Patch,
    };
    let primitive = |cut: CutQuadric, z: f64, id: u32| AnalyticPrimitive {
        shape: AnalyticShape::Quadric(Arc::clone(&QuadricShape::new(cut).expect("bounded"))),
        frame: Frame {
            origin: DVec3::new(0.0, 0.0, z),
            ..Frame::WORLD
        },
        face_id: id,
        colour: [0.8, 0.8, 0.8, 1.0],
    };
    RenderScene::default()
        .with_primitives(vec![primitive(plate, 0.0, 1), primitive(sphere, HEIGHT, 2)])
}

/// Pixels of the plate darker than the plate far from the shadow, seen from straight above
/// with the light from −x at 45°.
fn shadow_pixels(gpu: &cadre_render::Gpu, renderer: &Renderer, shadows: bool) -> usize {
    let scene = scene();
    let prepared = renderer.prepare(gpu, &scene);
    let camera = Camera {
        eye: DVec3::new(0.0, 0.0, 20.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height: VIEW },
        near: 5.0,
        far: 30.0,
    };
    let options = FrameOptions {
        width: SIZE,
        height: SIZE,
        supersample: 1,
        lights: vec![Light::Directional {
            direction: DVec3::new(-1.0, 0.0, 1.0),
            radiance: [2.0; 3],
        }],
        shadows,
        ..FrameOptions::default()
    };
    let image = renderer
        .render(gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("image");
    let ids = renderer
        .render_ids(gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("ids");
    // The plate's lit level: a pixel 3 units to −x, away from the shadow.
    let reference = image.get_pixel(SIZE / 2 - 44, SIZE / 2)[0];
    ids.iter()
        .zip(image.pixels())
        .filter(|(g, p)| g[0] == 1 && g[1] != 0 && p[0] + 20 < reference)
        .count()
}

#[test]
fn a_ray_cast_sphere_casts_its_exact_shadow() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let pixel = VIEW / f64::from(SIZE);
    let ellipse = std::f64::consts::PI * std::f64::consts::SQRT_2 * (RADIUS / pixel).powi(2);
    let shown = shadow_pixels(&gpu, &renderer, true) as f64;
    let none = shadow_pixels(&gpu, &renderer, false);
    eprintln!("shadow pixels {shown} (ellipse {ellipse:.0}), without shadows {none}");
    assert_eq!(none, 0, "nothing darkens without shadows");
    assert!(
        (shown - ellipse).abs() < 0.06 * ellipse,
        "{shown} vs {ellipse:.0}"
    );
    let proxy = Renderer::new(&gpu).expect("pipelines").with_proxy_depth();
    let wrong = shadow_pixels(&gpu, &proxy, true) as f64;
    eprintln!("with the proxies' depth: {wrong}");
    assert!(
        (wrong - ellipse).abs() > 0.2 * ellipse,
        "{wrong} vs {ellipse:.0}"
    );
}
