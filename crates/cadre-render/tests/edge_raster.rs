//! The visible-edges mode's segments rasterized in compute (`passes/edges/raster.rs`) draw
//! the image the quads draw: the same coverage per pixel, the same depth test, the same blend
//! in total. Compared in perspective and orthographic views, for a mirrored part and an
//! assembly, at two edge widths, with an edge selected and a part hovered (the highlighted
//! segments stay quads over the rasterized rest). Negative control: the quads at another edge
//! width differ from the rasterized image well past the tolerance, so the comparison would
//! see a rasterizer that drew its lines a quarter of a pixel too wide.

mod common;

use cadre_mesh::scene::{Scene, SceneNode};
use cadre_render::{Camera, FrameOptions, Gpu, Pick, RenderScene, Renderer, ViewState};
use common::{gpu, scene};
use glam::{DAffine3, DVec3};

/// The bundled pin's first mesh placed once, mirrored in x.
fn mirrored_pin() -> RenderScene {
    let pins = scene("pin-assembly.step");
    let mut out = Scene {
        meshes: vec![pins.assembly.meshes[0].clone()],
        materials: pins.assembly.materials.clone(),
        ..Scene::default()
    };
    out.nodes.push(SceneNode {
        transform: DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0)),
        mesh: Some(0),
        ..SceneNode::default()
    });
    out.roots.push(0);
    RenderScene::from_assembly(out)
}

/// `scene` from the iso view, shaded with edges `width` pixels wide, 240×180.
fn image(
    (gpu, renderer): (&Gpu, &Renderer),
    scene: &RenderScene,
    (ortho, width): (bool, f32),
    state: &ViewState,
) -> image::RgbaImage {
    let (lo, hi) = scene.bounds().expect("geometry");
    let camera = Camera::fit(lo, hi, cadre_render::ViewPreset::Iso, ortho, 4.0 / 3.0);
    let prepared = renderer.prepare(gpu, scene);
    let options = FrameOptions {
        edge_width: width,
        ..common::shaded_edges(240, 180)
    };
    renderer
        .render(gpu, &prepared, &camera, &options, state)
        .expect("image")
}

#[test]
fn edges_rasterized_in_compute_match_the_quads() {
    let gpu = gpu();
    assert!(gpu.compute, "{}: no compute shaders", gpu.info.name);
    let rastered = Renderer::new(&gpu)
        .expect("pipelines")
        .with_edge_raster(Some(0));
    let quads = Renderer::new(&gpu)
        .expect("pipelines")
        .with_edge_raster(None);
    let selected = ViewState {
        selection: vec![Pick::Edge {
            instance: 0,
            edge: 3,
        }],
        hover: Some(Pick::Part { instance: 1 }),
        ..ViewState::default()
    };
    let scenes = [
        ("mirrored pin", mirrored_pin()),
        ("pin assembly", scene("pin-assembly.step")),
    ];
    let mut compared = 0;
    for (name, scene) in &scenes {
        for (state_name, state) in [
            ("plain", ViewState::default()),
            ("selected", selected.clone()),
        ] {
            for ortho in [false, true] {
                for width in [1.5, 3.0] {
                    let what = format!("{name}, {state_name}, ortho {ortho}, width {width}");
                    let reference = image((&gpu, &quads), scene, (ortho, width), &state);
                    let got = image((&gpu, &rastered), scene, (ortho, width), &state);
                    let diff = cadre_render::compare::compare(&got, &reference, 3);
                    assert!(
                        diff.differing <= 0.001,
                        "{what}: {:.3} % of the pixels differ (max delta {})",
                        100.0 * diff.differing,
                        diff.max_delta
                    );
                    // Negative control: the quads a quarter of a pixel wider.
                    let wider = image((&gpu, &quads), scene, (ortho, width + 0.25), &state);
                    let diff = cadre_render::compare::compare(&got, &wider, 3);
                    assert!(
                        diff.differing > 0.004,
                        "{what}: the negative control differs on {:.3} % only",
                        100.0 * diff.differing
                    );
                    compared += 1;
                }
            }
        }
    }
    // Every frame of the compute renderer took the compute path; none of the quads'.
    assert_eq!(rastered.edge_rastered_frames(), compared);
    assert_eq!(quads.edge_rastered_frames(), 0);
}
