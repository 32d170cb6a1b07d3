//! Shared sub-assemblies drawn by instancing: a scene whose nodes are shared between their
//! uses (a node graph, as `build_scene` makes for huge assemblies) is drawn from draw records
//! composed with local placements on the GPU (`cadre_render::layout::Local`), and the image
//! and ids are those of one record per instance.

mod common;

use cadre_mesh::scene::{Scene, SceneNode};
use cadre_render::{Camera, FrameOptions, RenderScene, Renderer, ViewPreset, ViewState};
use common::{gpu, scene};
use glam::{DAffine3, DQuat, DVec3};

const W: u32 = 160;
const H: u32 = 120;

/// `levels` levels of `uses` shared nodes over the bundled pin's mesh, each level spread
/// along its own axis, every other use mirrored and turned: `uses^levels` instances.
fn shared_chain(levels: usize, uses: usize, shift: f64) -> RenderScene {
    let pins = scene("pin-assembly.step");
    let mut out = Scene::default();
    out.meshes.push(pins.assembly.meshes[0].clone());
    out.materials = pins.assembly.materials.clone();
    let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
    for p in &out.meshes[0].positions {
        let p = DVec3::from(p.map(f64::from));
        (lo, hi) = (lo.min(p), hi.max(p));
    }
    // Turned about z, the pin needs its xy diagonal of room in x and y.
    let extent = hi - lo;
    let room = DVec3::new(extent.x.hypot(extent.y), extent.x.hypot(extent.y), extent.z);
    let mut below: Vec<usize> = Vec::new();
    let mut spacing = 1.6 * room;
    for level in 0..levels {
        let first = out.nodes.len();
        for u in 0..uses {
            let mut offset = DVec3::ZERO;
            offset[level % 3] = u as f64 * spacing[level % 3] + shift * (u * level) as f64;
            let mirror = if u % 2 == 1 { -1.0 } else { 1.0 };
            out.nodes.push(SceneNode {
                transform: DAffine3::from_scale_rotation_translation(
                    DVec3::new(mirror, 1.0, 1.0),
                    DQuat::from_rotation_z(0.3 * u as f64),
                    offset,
                ),
                mesh: (level == 0).then_some(0),
                children: below.clone(),
                ..SceneNode::default()
            });
        }
        below = (first..first + uses).collect();
        spacing[level % 3] *= uses as f64;
    }
    out.nodes.push(SceneNode {
        children: below,
        ..SceneNode::default()
    });
    out.roots.push(out.nodes.len() - 1);
    RenderScene::from_assembly(out)
}

fn options() -> FrameOptions {
    common::shaded_edges(W, H)
}

/// Share of the pixels covered in both id buffers whose ids in `lane` agree, their
/// number, and how many pixels only one covers (silhouette pixels that f32 rounding of the
/// composed placements moves by a pixel).
fn agreement(a: &[[u32; 4]], b: &[[u32; 4]], lane: usize) -> (f64, usize, usize) {
    let (mut both, mut same, mut one) = (0usize, 0usize, 0usize);
    for (p, q) in a.iter().zip(b) {
        match (p[1] != 0, q[1] != 0) {
            (true, true) => {
                both += 1;
                same += usize::from(p[lane] == q[lane]);
            }
            (false, false) => {}
            _ => one += 1,
        }
    }
    (same as f64 / both.max(1) as f64, both, one)
}

/// The factored and the one-record-per-instance drawings of one shared scene agree on the
/// instance ids of ≥ 99.5 % of the pixels both cover (face ids on 99 %) and cover the same
/// pixels to 1 % (faces and instance numbers: picking reads them), and their images match;
/// a scene with some placements moved does not (negative control). The two drawings also
/// take the two ways of reading instances: the flat one reads its records as vertex
/// attributes (direct calls), the factored one composes them through the call slot.
#[test]
fn factored_instances_draw_like_one_record_each() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).unwrap();
    let scene = shared_chain(4, 4, 0.0); // 256 instances
    assert_eq!(scene.assembly.instances().count(), 256);
    let (lo, hi) = scene.bounds().unwrap();
    let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, f64::from(W) / f64::from(H));
    let state = ViewState::default();
    let flat = renderer.prepare_with_flat_limit(&gpu, &scene, usize::MAX);
    let factored = renderer.prepare_with_flat_limit(&gpu, &scene, 0);
    assert_eq!(flat.run_count(), 256);
    assert!(factored.run_count() < 256, "{}", factored.run_count());
    assert_eq!(factored.instance_count(), 256);
    let ids = |p| {
        renderer
            .render_ids(&gpu, p, &camera, &options(), &state)
            .unwrap()
    };
    let (flat_ids, factored_ids) = (ids(&flat), ids(&factored));
    let (share, covered, one) = agreement(&flat_ids, &factored_ids, 1);
    assert!(covered > 1000, "{covered} covered pixels");
    // Not all: the flat drawing culls the back faces of its closed parts, the factored one
    // cannot (its local placements may mirror), and a pixel whose centre lies on a
    // silhouette edge belongs to the back face by the rasterization rule, so there the
    // culled drawing shows what is behind (2 of 1,069 pixels here).
    assert!(
        share >= 0.995,
        "instances: {share} of {covered} pixels agree"
    );
    // Faces: a pixel on the border of two faces of one part may fall either way.
    let (share, _, _) = agreement(&flat_ids, &factored_ids, 0);
    assert!(share >= 0.99, "faces: {share} of {covered} pixels agree");
    assert!(
        one * 100 <= covered,
        "{one} pixels covered by one drawing only"
    );
    // Every instance number drawn is one the scene has.
    assert!(factored_ids.iter().all(|p| p[1] <= 256));
    let image = |p| {
        renderer
            .render(&gpu, p, &camera, &options(), &state)
            .unwrap()
    };
    let diff = cadre_render::compare::compare(&image(&flat), &image(&factored), 8);
    assert!(diff.passes(0.002), "{} differing", diff.differing);

    // Negative control: the same chain with its uses spaced a little differently.
    let moved = shared_chain(4, 4, 0.05 * (hi - lo).max_element() / 40.0);
    let moved = renderer.prepare_with_flat_limit(&gpu, &moved, 0);
    let (share, covered, one) = agreement(&flat_ids, &ids(&moved), 1);
    assert!(
        share < 0.99 || one * 100 > covered,
        "{share}, {one} of {covered}"
    );
}

/// A scene of 300 distinct meshes (300 draw calls, each bound at its own dynamic offset of the
/// call buffer) draws: the call buffer is bound one call wide, so the uniform binding limit
/// of downlevel devices (16 KiB, 64 calls of 256 bytes) does not cap the calls.
#[test]
fn hundreds_of_draw_calls_draw() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).unwrap();
    let pins = scene("pin-assembly.step");
    let mut many = Scene::default();
    for k in 0..300 {
        many.meshes.push(pins.assembly.meshes[0].clone());
        many.nodes.push(SceneNode {
            transform: DAffine3::from_translation(DVec3::new(
                30.0 * (k % 20) as f64,
                30.0 * (k / 20) as f64,
                0.0,
            )),
            mesh: Some(k),
            ..SceneNode::default()
        });
        many.roots.push(k);
    }
    let many = RenderScene::from_assembly(many);
    let (lo, hi) = many.bounds().unwrap();
    let camera = Camera::fit(lo, hi, ViewPreset::Top, false, f64::from(W) / f64::from(H));
    let prepared = renderer.prepare(&gpu, &many);
    let ids = renderer
        .render_ids(&gpu, &prepared, &camera, &options(), &ViewState::default())
        .unwrap();
    let drawn: std::collections::BTreeSet<u32> =
        ids.iter().map(|p| p[1]).filter(|&i| i > 0).collect();
    assert!(drawn.len() > 250, "{} of 300 instances seen", drawn.len());
}
