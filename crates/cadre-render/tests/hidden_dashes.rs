//! Hidden-line dashes on the edge's screen arc length (issue 19 item 2): a wire of 61 pieces
//! of 1.3 pixels hidden behind a plate is dashed 4 on, 4 off along its whole length, as the
//! pattern counted from its start says — not restarted at every piece (which drew every piece's
//! first pixels: a nearly solid line). Negative control: the same pattern half a period off
//! is told apart.

mod common;

use cadre_mesh::scene::{Scene, SceneMesh, SceneNode};
use cadre_render::{
    AnalyticPrimitive, AnalyticShape, Camera, DisplayMode, FrameOptions, Projection, QuadricShape,
    RenderScene, Renderer, Stipple, ViewState,
};
use common::gpu;
use glam::DVec3;

/// A wire along y = 0.5 from x = −40 to 40 at z = −5 in `pieces` pieces, under a plate.
fn scene(pieces: usize) -> RenderScene {
    let lines: Vec<[[f32; 3]; 2]> = (0..pieces)
        .map(|k| {
            let x = |k: usize| -40.0 + 80.0 * k as f32 / pieces as f32;
            [[x(k), 0.5, -5.0], [x(k + 1), 0.5, -5.0]]
        })
        .collect();
    let mut assembly = Scene {
        meshes: vec![SceneMesh {
            lines,
            ..SceneMesh::default()
        }],
        ..Scene::default()
    };
    assembly.nodes.push(SceneNode {
        mesh: Some(0),
        ..SceneNode::default()
    });
    assembly.roots.push(0);
    let plate = AnalyticPrimitive {
        shape: AnalyticShape::Quadric(
            QuadricShape::new(cadre_geom::CutQuadric {
                quadric: cadre_geom::Quadric::cylinder(48.0),
                planes: vec![
                    cadre_geom::HalfSpace::through(DVec3::ZERO, DVec3::Z),
                    cadre_geom::HalfSpace::through(DVec3::new(0.0, 0.0, -1.0), -DVec3::Z),
                ],
                kind: cadre_geom::CutKind::Volume,
            })
            .expect("bounded"),
        ),
        frame: cadre_geom::Frame::WORLD,
        face_id: 1,
        colour: [1.0, 1.0, 1.0, 1.0],
    };
    RenderScene::from_assembly(assembly).with_primitives(vec![plate])
}

#[test]
fn hidden_dashes_run_along_the_whole_polyline() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let camera = Camera {
        eye: DVec3::new(0.0, 0.0, 50.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height: 100.0 },
        near: 1.0,
        far: 200.0,
    };
    let options = FrameOptions {
        width: 100,
        height: 100,
        supersample: 1,
        mode: DisplayMode::HiddenLine,
        ..FrameOptions::default()
    };
    let prepared = renderer.prepare(&gpu, &scene(61));
    let image = renderer
        .render(&gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("image");
    // Row 49 holds y = 0.5; the wire starts at column 10 (x = −40).
    let darkness: Vec<f64> = (0..100)
        .map(|x| 1.0 - f64::from(image.get_pixel(x, 49)[1]) / 255.0)
        .collect();
    let full = darkness.iter().copied().fold(0.0, f64::max);
    assert!(full > 0.2, "the hidden wire is drawn: {darkness:?}");
    let dashes = Stipple {
        pattern: 0x0F0F,
        factor: 1,
    };
    // Columns wholly inside a drawn or an undrawn bit: dark, or background.
    let agree = |shift: f64| {
        (12..88)
            .filter(|&x| {
                let s = f64::from(x) + 0.5 - 10.0 + shift;
                let inside = dashes.drawn_at(s - 0.45) == dashes.drawn_at(s + 0.45);
                inside && {
                    let drawn = darkness[x as usize] > 0.5 * full;
                    drawn == dashes.drawn_at(s)
                }
            })
            .count()
    };
    let columns = agree(0.0);
    let off = agree(4.0);
    eprintln!(
        "{columns} of 76 columns as the pattern from the wire's start; {off} half a period off"
    );
    assert!(columns >= 74, "{columns}");
    assert!(off <= 4, "{off}");
}
