//! The viewer's path through the renderer on the machine's adapter (lavapipe in CI): a
//! prepared scene drawn into a kept viewport, picking faces, edges and vertices from it, and
//! the view's styles (hidden, recoloured, see-through, highlighted parts).

mod common;

use common::OneShot;

use cadre_render::{
    Camera, DisplayMode, FrameOptions, Gpu, InstanceStyle, Pick, RenderFace, RenderScene, Renderer,
    ViewPreset, ViewState, Viewport, wgpu,
};
use common::{gpu, scene};
use glam::{DVec3, DVec4};

const W: u32 = 200;
const H: u32 = 150;

/// The bundled pin assembly (two placed pins), tessellated.
fn pin_assembly() -> RenderScene {
    scene("pin-assembly.step")
}

fn camera(scene: &RenderScene) -> Camera {
    let (lo, hi) = scene.bounds().expect("geometry");
    Camera::fit(lo, hi, ViewPreset::Iso, false, f64::from(W) / f64::from(H))
}

fn options() -> FrameOptions {
    common::shaded_edges(W, H)
}

/// The pixel a world point lands on.
fn pixel_of(camera: &Camera, p: DVec3) -> Option<(u32, u32)> {
    let m = camera.projection_matrix(f64::from(W) / f64::from(H)) * camera.view_rotation();
    let c = m * DVec4::from((p - camera.eye, 1.0));
    if c.w <= 0.0 {
        return None;
    }
    let (x, y) = (c.x / c.w, c.y / c.w);
    let px = ((x + 1.0) * 0.5 * f64::from(W)).floor();
    let py = ((1.0 - y) * 0.5 * f64::from(H)).floor();
    (px >= 0.0 && py >= 0.0 && px < f64::from(W) && py < f64::from(H))
        .then_some((px as u32, py as u32))
}

/// The face pick a visibility texel's ids name (none on the background).
fn face_in(id: &[u32; 4]) -> Option<Pick> {
    (id[1] != 0).then(|| Pick::Face {
        instance: id[1] - 1,
        face: id[0],
    })
}

/// The face a pick at pixel `at` of the viewport's last frame finds under the cursor.
fn face_picked(
    renderer: &Renderer,
    gpu: &Gpu,
    (viewport, prepared): (&Viewport, &cadre_render::PreparedScene),
    at: (u32, u32),
) -> Option<Pick> {
    renderer
        .pick(gpu, viewport, prepared, at, 0)
        .expect("pick")
        .face()
        .map(|h| h.pick)
}

/// A colour texture the viewport's frames are drawn into, as a window's surface texture.
fn target(gpu: &Gpu) -> wgpu::TextureView {
    gpu.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("target"),
            size: wgpu::Extent3d {
                width: W,
                height: H,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

#[test]
fn picking_finds_faces_edges_and_vertices_under_the_cursor() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = pin_assembly();
    let prepared = renderer.prepare(&gpu, &scene);
    let camera = camera(&scene);
    let mut viewport = Viewport::new(&gpu, W, H);
    let view = target(&gpu);
    let state = ViewState::default();
    renderer
        .draw(
            &gpu,
            &mut viewport,
            &prepared,
            &camera,
            &options(),
            &state,
            &view,
        )
        .expect("frame");
    let ids = renderer
        .ids_of(&gpu, &scene, &camera, &options())
        .expect("ids");

    // Faces: wherever the visibility buffer has one, the pick under the cursor agrees.
    let mut faces = 0;
    for (i, id) in ids.iter().enumerate().step_by(97) {
        let (x, y) = (i as u32 % W, i as u32 / W);
        let expected = face_in(id);
        let picked = face_picked(&renderer, &gpu, (&viewport, &prepared), (x, y));
        assert_eq!(picked, expected, "pixel {x} {y}");
        faces += usize::from(expected.is_some());
    }
    assert!(faces > 20, "{faces} face pixels checked");

    // Edges: the midpoint of every B-Rep edge of every instance; the visible ones (most, in
    // an iso view of two pins) pick as that edge within 3 pixels.
    let (mut edges, mut hits) = (0, 0);
    let (mut vertices, mut vertex_hits) = (0, 0);
    for (instance, (node, world)) in scene.assembly.instances().enumerate() {
        let Some(mesh) = scene.assembly.nodes[node].mesh else {
            continue;
        };
        for edge in &scene.assembly.meshes[mesh].edges {
            let mid = edge.points[edge.points.len() / 2];
            let p = world.transform_point3(DVec3::from(mid.map(f64::from)));
            let Some(px) = pixel_of(&camera, p) else {
                continue;
            };
            edges += 1;
            let hit = renderer
                .pick(&gpu, &viewport, &prepared, px, 4)
                .expect("pick")
                .nearest(3.0);
            if let Some(hit) = hit
                && hit.pick
                    == (Pick::Edge {
                        instance: instance as u32,
                        edge: edge.id,
                    })
            {
                hits += 1;
            }
        }
        for vertex in &scene.assembly.meshes[mesh].vertices {
            let p = world.transform_point3(DVec3::from(vertex.position.map(f64::from)));
            let Some(px) = pixel_of(&camera, p) else {
                continue;
            };
            vertices += 1;
            let hit = renderer
                .pick(&gpu, &viewport, &prepared, px, 4)
                .expect("pick")
                .nearest(3.0);
            vertex_hits += usize::from(
                hit.map(|h| h.pick)
                    == Some(Pick::Vertex {
                        instance: instance as u32,
                        vertex: vertex.id,
                    }),
            );
        }
    }
    assert!(edges >= 4, "{edges} edges");
    assert!(
        hits * 2 >= edges,
        "{hits} of {edges} edge midpoints pick their edge"
    );
    assert!(
        vertices >= 2 && vertex_hits * 2 >= vertices,
        "{vertex_hits} of {vertices} vertices pick"
    );
}

/// A frame may leave the ids of pixels it does not cover as the last frame wrote them (on a
/// CPU adapter: `VisibilityTargets`); picks must still see the background there.
#[test]
fn picks_see_the_background_where_the_last_frame_had_a_face() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = pin_assembly();
    let prepared = renderer.prepare(&gpu, &scene);
    let fitted = camera(&scene);
    // First a close-up (faces over most of the image), then the fitted view.
    let close = fitted.zoomed_at(fitted.target, 4.0, scene.bounds().expect("geometry"));
    let mut viewport = Viewport::new(&gpu, W, H);
    let view = target(&gpu);
    let state = ViewState::default();
    for camera in [&close, &fitted] {
        renderer
            .draw(
                &gpu,
                &mut viewport,
                &prepared,
                camera,
                &options(),
                &state,
                &view,
            )
            .expect("frame");
    }
    let before = renderer
        .ids_of(&gpu, &scene, &close, &options())
        .expect("ids");
    let now = renderer
        .ids_of(&gpu, &scene, &fitted, &options())
        .expect("ids");
    let (mut uncovered, mut faces) = (0, 0);
    for (i, (was, id)) in before.iter().zip(&now).enumerate().step_by(13) {
        let (x, y) = (i as u32 % W, i as u32 / W);
        let expected = face_in(id);
        let picked = face_picked(&renderer, &gpu, (&viewport, &prepared), (x, y));
        assert_eq!(picked, expected, "pixel {x} {y}");
        uncovered += usize::from(was[1] != 0 && id[1] == 0);
        faces += usize::from(id[1] != 0);
    }
    // The case under test happens: background now where the close-up had faces.
    assert!(
        uncovered > 50,
        "{uncovered} pixels uncovered by the second frame"
    );
    assert!(faces > 20, "{faces} face pixels checked");
}

#[test]
fn a_hover_pick_answers_on_a_later_poll_what_a_click_finds() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = pin_assembly();
    let prepared = renderer.prepare(&gpu, &scene);
    let camera = camera(&scene);
    let mut viewport = Viewport::new(&gpu, W, H);
    let view = target(&gpu);
    renderer
        .draw(
            &gpu,
            &mut viewport,
            &prepared,
            &camera,
            &options(),
            &ViewState::default(),
            &view,
        )
        .expect("frame");
    // Edge midpoints (the pick pass draws there), the image's corners (windows clipped at
    // the borders), its centre, and points past its right and bottom borders (an empty
    // window, answered at once: once polled forever).
    let mut cursors = vec![
        (0, 0),
        (W - 1, H - 1),
        (W / 2, H / 2),
        (W + 20, H / 2),
        (W / 2, H + 20),
    ];
    for (node, world) in scene.assembly.instances() {
        let Some(mesh) = scene.assembly.nodes[node].mesh else {
            continue;
        };
        for edge in &scene.assembly.meshes[mesh].edges {
            let mid = edge.points[edge.points.len() / 2];
            let p = world.transform_point3(DVec3::from(mid.map(f64::from)));
            cursors.extend(pixel_of(&camera, p));
        }
    }
    let mut with_edges = 0;
    for (k, &cursor) in cursors.iter().enumerate() {
        let clicked = renderer
            .pick(&gpu, &viewport, &prepared, cursor, 4)
            .expect("click");
        let mut pending = renderer
            .request_pick(&gpu, &viewport, &prepared, cursor, 4)
            .expect("hover");
        if cursor.0 < W && cursor.1 < H {
            assert_eq!(pending.window().cursor, cursor);
        } else {
            assert_eq!(pending.window().width * pending.window().height, 0);
        }
        let started = std::time::Instant::now();
        let hovered = loop {
            if let Some(answer) = pending.poll(&gpu) {
                break answer.expect("hover answer");
            }
            assert!(started.elapsed().as_secs() < 30, "no answer at {cursor:?}");
            std::thread::yield_now();
        };
        // Once answered, nothing more comes.
        assert!(pending.poll(&gpu).is_none());
        assert_eq!(hovered, clicked, "cursor {cursor:?}");
        assert!(clicked.width <= 9 && clicked.height <= 9);
        // The edge midpoints' windows show edges (most are visible in this view).
        with_edges += usize::from(k >= 5 && clicked.lines.iter().any(|l| l[2] == 2));
    }
    assert_eq!(
        renderer
            .pick(&gpu, &viewport, &prepared, (0, 0), 4)
            .expect("corner")
            .width,
        5,
        "clipped at the left border"
    );
    let midpoints = cursors.len() - 5;
    assert!(
        midpoints >= 4 && with_edges * 2 >= midpoints,
        "{with_edges} of {midpoints}"
    );
}

/// Mean linear-ish colour of the pixels where `mask` holds.
fn mean(image: &image::RgbaImage, mask: &[bool]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0f64;
    for (p, &m) in image.pixels().zip(mask) {
        if m {
            for (s, &c) in sum.iter_mut().zip(&p.0[..3]) {
                *s += f64::from(c);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n.max(1.0))
}

/// Distance between two mean colours (sRGB bytes).
fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The renderer's selection (orange) and hover (light blue) tints, as sRGB bytes.
const ORANGE: [f64; 3] = [255.0, 178.0, 63.0];
const LIGHT_BLUE: [f64; 3] = [149.0, 225.0, 255.0];

#[test]
fn hidden_recoloured_see_through_and_highlighted_parts_draw_as_asked() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = pin_assembly();
    let prepared = renderer.prepare(&gpu, &scene);
    assert!(prepared.instance_count() >= 2, "the example has two pins");
    let camera = camera(&scene);
    let opts = FrameOptions {
        mode: DisplayMode::Shaded,
        ..options()
    };
    let ids = renderer.ids_of(&gpu, &scene, &camera, &opts).expect("ids");
    let first: Vec<bool> = ids.iter().map(|id| id[1] == 1).collect();
    assert!(first.iter().filter(|&&m| m).count() > 100);
    let render = |state: &ViewState| {
        renderer
            .render(&gpu, &prepared, &camera, &opts, state)
            .expect("render")
    };
    let plain = render(&ViewState::default());
    let base = mean(&plain, &first);
    let style = |s: InstanceStyle| ViewState {
        instances: vec![s],
        ..ViewState::default()
    };

    // Hidden: the background (white) where the first pin was.
    let hidden = mean(
        &render(&style(InstanceStyle {
            visible: false,
            colour: None,
        })),
        &first,
    );
    assert!(hidden.iter().all(|&c| c > 250.0), "hidden: {hidden:?}");

    // Red: red dominates.
    let red = mean(
        &render(&style(InstanceStyle {
            visible: true,
            colour: Some([0.8, 0.02, 0.02, 1.0]),
        })),
        &first,
    );
    assert!(
        red[0] > red[1] + 60.0 && red[0] > red[2] + 60.0,
        "red: {red:?}"
    );

    // See-through red over a white background: lighter than the opaque red, still reddish.
    let glass = mean(
        &render(&style(InstanceStyle {
            visible: true,
            colour: Some([0.8, 0.02, 0.02, 0.3]),
        })),
        &first,
    );
    assert!(
        glass[1] > red[1] + 40.0,
        "see-through: {glass:?} vs {red:?}"
    );
    assert!(
        glass[0] > glass[1] + 20.0,
        "see-through keeps its hue: {glass:?}"
    );

    // Selected part: tinted towards orange.
    let selected = mean(
        &render(&ViewState {
            selection: vec![Pick::Part { instance: 0 }],
            ..ViewState::default()
        }),
        &first,
    );
    assert!(
        distance(selected, ORANGE) < distance(base, ORANGE) - 30.0,
        "selected: {selected:?} vs {base:?}"
    );
    // Hovered face: only that face's pixels change.
    let face = ids.iter().find(|id| id[1] == 1).expect("a face")[0];
    let on_face: Vec<bool> = ids.iter().map(|id| id[1] == 1 && id[0] == face).collect();
    let off_face: Vec<bool> = ids.iter().map(|id| id[1] == 1 && id[0] != face).collect();
    let hovered = render(&ViewState {
        hover: Some(Pick::Face { instance: 0, face }),
        ..ViewState::default()
    });
    let (h_on, p_on) = (mean(&hovered, &on_face), mean(&plain, &on_face));
    assert!(
        distance(h_on, LIGHT_BLUE) < distance(p_on, LIGHT_BLUE) - 10.0,
        "hovered face: {h_on:?} vs {p_on:?}"
    );
    let (h_off, p_off) = (mean(&hovered, &off_face), mean(&plain, &off_face));
    assert!(
        (0..3).all(|k| (h_off[k] - p_off[k]).abs() < 1.0),
        "other faces unchanged: {h_off:?} vs {p_off:?}"
    );
}

#[test]
fn a_file_whose_step_ids_pass_u32_picks_and_names_the_right_entities() {
    // Every id of the pin assembly moved past 2³²: cut to u32 (as the id lanes once held
    // STEP ids), they would all have become 0 and shared one id.
    let offset = (1u64 << 32) + 1000;
    let (model, scene) =
        common::model_and_scene_of(common::renumbered("pin-assembly.step", offset), 0.01);
    assert!(model.faces.iter().all(|f| f.step_id > u64::from(u32::MAX)));
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let prepared = renderer.prepare(&gpu, &scene);
    let camera = camera(&scene);
    let mut viewport = Viewport::new(&gpu, W, H);
    renderer
        .draw(
            &gpu,
            &mut viewport,
            &prepared,
            &camera,
            &options(),
            &ViewState::default(),
            &target(&gpu),
        )
        .expect("frame");
    // Faces: the picked face's STEP id is the one the exact ray caster sees there.
    let exact = cadre_render::raycast::RayCaster::new(&model, 0.001).face_ids(&camera, W, H);
    let ids = scene.ids();
    let (mut checked, mut agree) = (0, 0);
    let mut seen = std::collections::BTreeSet::new();
    for (i, &e) in exact.iter().enumerate().step_by(7) {
        let (x, y) = (i as u32 % W, i as u32 / W);
        let hit = renderer
            .pick(&gpu, &viewport, &prepared, (x, y), 0)
            .expect("pick")
            .face();
        let Some(Pick::Face { face, .. }) = hit.map(|h| h.pick) else {
            continue;
        };
        let Some(RenderFace::Brep { face: brep, .. }) = scene.face(face) else {
            panic!("face id {face} is not a B-Rep face");
        };
        assert_eq!(ids.brep_face(face), Some(*brep));
        assert_eq!(ids.face_step_id(face), model.faces[brep.index()].step_id);
        checked += 1;
        agree += usize::from(ids.face_step_id(face) == e);
        seen.insert(face);
    }
    assert!(checked > 50, "{checked} face pixels");
    assert!(
        agree * 100 >= checked * 98,
        "{agree} of {checked} agree with the oracle"
    );
    assert!(
        seen.len() >= 3,
        "distinct faces keep distinct ids: {seen:?}"
    );
    // Edges: the midpoint of each picks the edge whose STEP id is the model's.
    let mut edges = 0;
    for (node, world) in scene.assembly.instances() {
        let Some(mesh) = scene.assembly.nodes[node].mesh else {
            continue;
        };
        for edge in &scene.assembly.meshes[mesh].edges {
            let mid = edge.points[edge.points.len() / 2];
            let p = world.transform_point3(DVec3::from(mid.map(f64::from)));
            let Some(px) = pixel_of(&camera, p) else {
                continue;
            };
            let hit = renderer
                .pick(&gpu, &viewport, &prepared, px, 4)
                .expect("pick")
                .nearest(3.0);
            if let Some(Pick::Edge { edge: id, .. }) = hit.map(|h| h.pick)
                && id == edge.id
            {
                let e = ids.edge(id).expect("a model edge");
                assert_eq!(ids.edge_step_id(id), model.edges[e.index()].step_id);
                assert!(ids.edge_step_id(id) > u64::from(u32::MAX));
                edges += 1;
            }
        }
    }
    assert!(edges >= 2, "{edges} edges picked");
}
