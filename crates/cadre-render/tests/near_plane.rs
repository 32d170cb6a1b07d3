//! A line that passes behind the eye is drawn clipped to the near plane: its quad is built
//! from the part in front, not from an end behind the eye (whose division by a negative w
//! would throw it across the screen).

mod common;

use cadre_mesh::scene::{Scene, SceneMesh, SceneNode};
use cadre_render::{Camera, Projection, RenderScene, Renderer};
use common::{OneShot, gpu};
use glam::DVec3;

/// A scene of one wire segment from `from` to `to`.
fn wire(from: [f32; 3], to: [f32; 3]) -> RenderScene {
    let mut scene = Scene {
        meshes: vec![SceneMesh {
            lines: vec![[from, to]],
            ..SceneMesh::default()
        }],
        ..Scene::default()
    };
    scene.nodes.push(SceneNode {
        mesh: Some(0),
        ..SceneNode::default()
    });
    scene.roots.push(0);
    RenderScene::from_assembly(scene)
}

/// Non-background pixels of `image` in its left and right halves.
fn drawn(image: &image::RgbaImage) -> (usize, usize) {
    let half = image.width() / 2;
    let mut sides = (0, 0);
    for (x, _, p) in image.enumerate_pixels() {
        if p.0[..3].iter().any(|&c| c < 200) {
            if x < half {
                sides.0 += 1;
            } else {
                sides.1 += 1;
            }
        }
    }
    sides
}

#[test]
fn a_line_through_the_eye_plane_is_clipped_to_the_near_plane() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    // The eye at the origin looking down −z; the line at x = −1, y = 0.3 from 5 behind the
    // eye to 50 in front: all of its visible part projects to the left half.
    let camera = Camera {
        eye: DVec3::ZERO,
        target: DVec3::NEG_Z,
        up: DVec3::Y,
        projection: Projection::Perspective {
            fov_y: std::f64::consts::FRAC_PI_3,
        },
        near: 0.1,
        far: 100.0,
    };
    let options = common::shaded_edges(160, 120);
    // The image of the line at x = −1, y = 0.3 from z = `start` to 50 in front of the eye.
    let line_from = |start: f32| {
        renderer
            .image_of(
                &gpu,
                &wire([-1.0, 0.3, start], [-1.0, 0.3, -50.0]),
                &camera,
                &options,
            )
            .expect("image")
    };
    let through = line_from(5.0);
    // The same line cut on the CPU just in front of the near plane (the piece between it
    // and the near plane projects off the image).
    let cut = line_from(-0.2);
    let (left, right) = drawn(&through);
    assert!(left > 40, "{left} pixels of the line");
    assert_eq!(right, 0, "{right} pixels thrown to the right half");
    let diff = cadre_render::compare::compare(&through, &cut, 8);
    assert!(diff.passes(0.0), "{} of the pixels differ", diff.differing);
    // The comparison sees a difference where there is one: the line starting 3 in front.
    let shorter = line_from(-3.0);
    let diff = cadre_render::compare::compare(&through, &shorter, 8);
    assert!(!diff.passes(0.0), "a shorter line draws the same");
}
