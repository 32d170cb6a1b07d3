//! The thesis' scenes (seed 001), bundled in `examples/scenes`: each loads from its scene
//! file, shows the CPU ray caster's primitive at every pixel away from the boundaries, and
//! matches its golden image, its shadows included (`CADRE_BLESS=1` rewrites them).

mod common;

use cadre_render::raycast::RayCaster;
use cadre_render::scene_file::{LoadedScene, load_scene};
use cadre_render::{Camera, FrameOptions, RenderScene, Renderer, ViewState};
use common::{check_golden, gpu, root};

/// The scene file `name` of `examples/scenes`.
fn scene(name: &str) -> LoadedScene {
    let path = root().join("examples/scenes").join(name);
    let text = std::fs::read_to_string(&path).expect("scene file reads");
    let loaded = load_scene(&text).expect("scene file parses");
    assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
    loaded
}

/// The file's camera for a `w` × `h` image.
fn camera(loaded: &LoadedScene, scene: &RenderScene) -> Camera {
    let (lo, hi) = scene.bounds().expect("objects");
    let (eye, target, up, fov) = loaded.camera.expect("the scene's camera");
    Camera::looking((eye, target, up), fov, (lo, hi))
}

/// Pixels away from every boundary (half a pixel) where the GPU's primitive is not the
/// oracle's, and the pixels covered.
fn disagreement(name: &str, (w, h): (u32, u32)) -> (usize, usize) {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let loaded = scene(name);
    let scene = RenderScene::default().with_primitives(loaded.primitives.clone());
    let camera = camera(&loaded, &scene);
    let prepared = renderer.prepare(&gpu, &scene);
    let options = FrameOptions {
        width: w,
        height: h,
        supersample: 1,
        ..FrameOptions::default()
    };
    let ids = renderer
        .render_ids(&gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("ids");
    let mut caster = RayCaster::new(&cadre_brep::Model::default(), 1e-3);
    for p in &loaded.primitives {
        caster.add_primitive(p);
    }
    let exact = caster.face_ids(&camera, w, h);
    let near = caster.near_boundary(&camera, w, h, 0.5);
    let mut wrong = 0;
    for ((g, e), near) in ids.iter().zip(&exact).zip(&near) {
        let shown = if g[1] == 0 { 0 } else { u64::from(g[0]) };
        wrong += usize::from(!near && shown != *e);
    }
    let covered = ids.iter().filter(|g| g[1] != 0).count();
    (wrong, covered)
}

#[test]
fn the_thesis_scenes_show_the_exact_primitive_at_every_pixel() {
    for (name, size, least) in [
        ("teapot.json", (192, 144), 3000),
        ("robot.json", (192, 144), 2000),
        ("dna.json", (160, 160), 1500),
        ("mandala.json", (128, 128), 3000),
    ] {
        let (wrong, covered) = disagreement(name, size);
        eprintln!("{name}: {wrong} wrong of {covered} covered pixels");
        assert!(covered >= least, "{name}: {covered} pixels covered");
        assert_eq!(wrong, 0, "{name}");
    }
}

#[test]
fn the_thesis_scenes_match_their_golden_images() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    for name in ["teapot", "robot", "dna", "mandala"] {
        let loaded = scene(&format!("{name}.json"));
        let scene = RenderScene::default().with_primitives(loaded.primitives.clone());
        let camera = camera(&loaded, &scene);
        let prepared = renderer.prepare(&gpu, &scene);
        let mut options = FrameOptions {
            width: 240,
            height: 180,
            supersample: 1,
            ..FrameOptions::default()
        };
        if !loaded.lights.is_empty() {
            options.lights = loaded.lights.clone();
        }
        options.shadows = loaded.shadows;
        let image = renderer
            .render(&gpu, &prepared, &camera, &options, &ViewState::default())
            .expect("image");
        check_golden(&format!("quadrics-{name}.png"), &image);
    }
}
