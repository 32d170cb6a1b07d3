//! Back faces of closed solids are culled (`DrawCall::cull`): seen from inside a closed part,
//! nothing of it is drawn, while an open copy of the same mesh (one triangle fewer: its
//! back faces may show) and the same part cut by a section plane (whose caps need the back
//! faces) still show its inner side. From outside the images are the same either way (the
//! golden images did not change).

mod common;

use cadre_mesh::scene::{Scene, SceneNode};
use cadre_render::{Camera, Gpu, RenderScene, Renderer, SectionPlane, ViewState};
use common::{gpu, scene};
use glam::{DAffine3, DVec3};

/// The bundled pin's first mesh, placed once (mirrored in x when `mirrored`); with its last
/// triangle removed when `open`.
fn pin(open: bool, mirrored: bool) -> RenderScene {
    let pins = scene("pin-assembly.step");
    let mut mesh = pins.assembly.meshes[0].clone();
    if open {
        let prim = mesh
            .primitives
            .iter_mut()
            .find(|p| p.indices.len() >= 3)
            .expect("a primitive with triangles");
        prim.indices.truncate(prim.indices.len() - 3);
    }
    let mut out = Scene {
        meshes: vec![mesh],
        materials: pins.assembly.materials.clone(),
        ..Scene::default()
    };
    out.nodes.push(SceneNode {
        transform: DAffine3::from_scale(DVec3::new(if mirrored { -1.0 } else { 1.0 }, 1.0, 1.0)),
        mesh: Some(0),
        ..SceneNode::default()
    });
    out.roots.push(0);
    RenderScene::from_assembly(out)
}

/// How many pixels show the part, with the eye at the centre of its box looking along its
/// longest axis.
fn covered_from_inside(scene: &RenderScene, state: &ViewState) -> usize {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let (lo, hi) = scene.bounds().expect("geometry");
    let centre = 0.5 * (lo + hi);
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        DVec3::X
    } else if extent.y >= extent.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    let fitted = Camera::fit(lo, hi, cadre_render::ViewPreset::Iso, false, 4.0 / 3.0);
    let camera = Camera {
        eye: centre,
        target: centre + axis,
        up: if axis == DVec3::Z { DVec3::X } else { DVec3::Z },
        near: 1e-3 * extent.length(),
        ..fitted
    };
    let prepared = renderer.prepare(&gpu, scene);
    let ids = renderer
        .render_ids(
            &gpu,
            &prepared,
            &camera,
            &common::shaded_edges(64, 48),
            state,
        )
        .expect("ids");
    ids.iter().filter(|id| id[1] != 0).count()
}

#[test]
fn a_closed_part_seen_from_inside_shows_nothing_of_itself() {
    let none = ViewState::default();
    for mirrored in [false, true] {
        let closed = covered_from_inside(&pin(false, mirrored), &none);
        let open = covered_from_inside(&pin(true, mirrored), &none);
        // The negative control: the open copy's inner side covers most of the view.
        assert!(
            open > 64 * 48 / 2,
            "mirrored {mirrored}: the open copy shows its inside ({open} px)"
        );
        assert_eq!(
            closed, 0,
            "mirrored {mirrored}: back faces drawn from inside"
        );
    }
    // A section plane that keeps the whole part still turns culling off (caps are found
    // from the back faces).
    let far = SectionPlane {
        normal: DVec3::X,
        offset: 1e9,
    };
    let state = ViewState {
        sections: vec![far],
        ..ViewState::default()
    };
    let cut = covered_from_inside(&pin(false, false), &state);
    assert!(
        cut > 64 * 48 / 2,
        "with a section plane the inside shows ({cut} px)"
    );
}

/// The image of `scene` from the iso view (orthographic or not), shaded with edges, 200×150,
/// by `renderer`.
fn edges_image(
    (gpu, renderer): (&Gpu, &Renderer),
    scene: &RenderScene,
    ortho: bool,
) -> image::RgbaImage {
    let (lo, hi) = scene.bounds().expect("geometry");
    let camera = Camera::fit(lo, hi, cadre_render::ViewPreset::Iso, ortho, 4.0 / 3.0);
    let prepared = renderer.prepare(gpu, scene);
    renderer
        .render(
            gpu,
            &prepared,
            &camera,
            &common::shaded_edges(200, 150),
            &ViewState::default(),
        )
        .expect("image")
}

/// Edges on the far side of their own closed solid (both faces turned away) are dropped
/// before rasterization; that changes next to no pixel: the images equal those drawn with
/// every edge rasterized and the hidden ones rejected by the depth test, in perspective and
/// orthographic views, for a mirrored part and an assembly, but for a few pixels (≤ 0.05 %)
/// where a hidden edge just behind a curved silhouette peeked out by part of its width
/// (measured: 4 of 30,000 pixels). Negative control: dropping every edge between two faces
/// (a margin past any cosine) loses visible edges.
#[test]
fn edges_behind_their_solid_are_dropped_without_changing_the_image() {
    let gpu = gpu();
    let culled = Renderer::new(&gpu).expect("pipelines");
    let drawn = Renderer::new(&gpu)
        .expect("pipelines")
        .with_edge_culling_margin(None);
    let everything = Renderer::new(&gpu)
        .expect("pipelines")
        .with_edge_culling_margin(Some(-2.0));
    let scenes = [
        ("pin", pin(false, false)),
        ("mirrored pin", pin(false, true)),
        ("pin assembly", scene("pin-assembly.step")),
    ];
    for (name, scene) in &scenes {
        for ortho in [false, true] {
            let reference = edges_image((&gpu, &drawn), scene, ortho);
            let image = edges_image((&gpu, &culled), scene, ortho);
            let diff = cadre_render::compare::compare(&image, &reference, 2);
            assert!(
                diff.differing <= 0.0005,
                "{name}, ortho {ortho}: {} of the pixels differ",
                diff.differing
            );
            let wrong = edges_image((&gpu, &everything), scene, ortho);
            let diff = cadre_render::compare::compare(&wrong, &reference, 2);
            assert!(
                diff.differing > 0.002,
                "{name}, ortho {ortho}: the negative control differs on {} only",
                diff.differing
            );
        }
    }
}
