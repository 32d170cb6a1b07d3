//! PMI drawn (issue 20) on the corpus's NIST test file (`bug33661_nist_ftc_08_asme1_ap242-
//! e1-tg.stp`, graphic PMI only): every one of its 60 annotations puts ink on the image by
//! itself, each of its 4 saved views matches its golden image, and one view's image is not
//! another's (negative control); and `bug32745_pmi1.stp` (semantic PMI presented by
//! tessellated callouts): its 20 annotations drawn, its two saved views against their golden
//! images, the second cut by its clipping plane into the section it was saved for. Skips with
//! a message when `../shared` is absent.

mod common;

use cadre_render::pmi::{
    Placements, overlay, overlay_bounds, saved_view_camera, saved_view_sections,
};
use cadre_render::{Camera, FrameOptions, RenderScene, Renderer, ViewState};
use common::{check_golden, gpu, model_and_scene_of};
use image::RgbaImage;
use std::path::Path;

const NIST: &str = "bug33661_nist_ftc_08_asme1_ap242-e1-tg.stp";

const CLIPPED: &str = "bug32745_pmi1.stp";

fn nist() -> Option<Vec<u8>> {
    corpus_file(NIST)
}

fn corpus_file(name: &str) -> Option<Vec<u8>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/corpus/step")
        .join(name);
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(_) => {
            eprintln!(
                "skipping: {} not found (clone without the shared data)",
                path.display()
            );
            None
        }
    }
}

fn options(width: u32, height: u32) -> FrameOptions {
    FrameOptions {
        width,
        height,
        supersample: 1,
        ..FrameOptions::default()
    }
}

/// Pixels of the PMI colour (dark blue: blue well above red and green).
fn pmi_ink(image: &RgbaImage) -> usize {
    image
        .pixels()
        .filter(|p| i32::from(p[2]) - i32::from(p[0]) > 60 && p[0] < 150)
        .count()
}

#[test]
fn every_nist_annotation_is_drawn_and_each_saved_view_matches_its_golden_image() {
    let Some(bytes) = nist() else { return };
    let (model, scene) = model_and_scene_of(bytes, 0.2);
    let pmi = &model.pmi;
    assert_eq!(pmi.annotations.len(), 60);
    assert_eq!(
        pmi.annotations
            .iter()
            .map(|a| a.point_count())
            .sum::<usize>(),
        34_138
    );
    assert_eq!(pmi.views.len(), 4);
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let white = [1.0, 1.0, 1.0, 1.0];
    let part = scene.bounds().expect("a part");
    // Each annotation alone, seen from its plane's side (or from above), leaves ink.
    let placements = Placements::of(&model);
    let all = overlay(pmi, None, white, &placements);
    let (lo, hi) = overlay_bounds(&all).map_or(part, |(a, b)| (part.0.min(a), part.1.max(b)));
    let mut blank = Vec::new();
    for (k, a) in pmi.annotations.iter().enumerate() {
        let one = cadre_brep::Pmi {
            annotations: vec![a.clone()],
            ..cadre_brep::Pmi::default()
        };
        let o = overlay(&one, None, white, &placements);
        let to_eye = a
            .plane
            .map(|p| {
                let n = pmi.planes[p].normal;
                glam::DVec3::new(n.x, n.y, n.z)
            })
            .unwrap_or(glam::DVec3::Z);
        let up = if to_eye.z.abs() > 0.9 {
            glam::DVec3::Y
        } else {
            glam::DVec3::Z
        };
        let camera = Camera::fit_along(lo, hi, (to_eye, up), true, 1.0);
        let lines_only = RenderScene::default()
            .with_lines(o.lines)
            .with_labels(o.labels);
        let prepared = renderer.prepare(&gpu, &lines_only);
        let image = renderer
            .render(
                &gpu,
                &prepared,
                &camera,
                &options(160, 160),
                &ViewState::default(),
            )
            .expect("image");
        if pmi_ink(&image) == 0 {
            blank.push(format!("{k} {}", a.name));
        }
    }
    assert!(blank.is_empty(), "annotations that draw nothing: {blank:?}");
    // The saved views.
    let mut images = Vec::new();
    for view in &pmi.views {
        let o = overlay(pmi, Some(view), white, &placements);
        assert!(o.annotations > 0, "{} shows annotations", view.name);
        // The part and this view's annotations, as `cadre render --saved-view` fits them.
        let (vlo, vhi) = overlay_bounds(&o).map_or(part, |(a, b)| (part.0.min(a), part.1.max(b)));
        let camera = saved_view_camera(view, (vlo, vhi), 4.0 / 3.0, &placements);
        let mut scene: RenderScene = scene.clone();
        scene.lines = o.lines;
        scene.labels = o.labels;
        let prepared = renderer.prepare(&gpu, &scene);
        let image = renderer
            .render(
                &gpu,
                &prepared,
                &camera,
                &options(320, 240),
                &ViewState::default(),
            )
            .expect("image");
        assert!(pmi_ink(&image) > 300, "{}: {}", view.name, pmi_ink(&image));
        check_golden(
            &format!("pmi-nist-ftc08-{}.png", view.name.to_lowercase()),
            &image,
        );
        images.push(image);
    }
    // Negative control: two views differ far beyond the golden tolerance.
    let c = cadre_render::compare::compare(&images[0], &images[1], 8);
    assert!(
        c.differing > 0.05,
        "MBD_A and MBD_B images differ in {}",
        c.differing
    );
}

#[test]
fn a_clipped_saved_view_shows_its_section_and_each_view_matches_its_golden_image() {
    let Some(bytes) = corpus_file(CLIPPED) else {
        return;
    };
    let (model, scene) = model_and_scene_of(bytes, 0.05);
    let pmi = &model.pmi;
    assert_eq!(pmi.annotations.len(), 20);
    let names: Vec<&str> = pmi.views.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, ["02", "03"]);
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let white = [1.0, 1.0, 1.0, 1.0];
    let part = scene.bounds().expect("a part");
    let placements = Placements::of(&model);
    let render = |view: &cadre_brep::pmi::SavedView, state: &ViewState| {
        let o = overlay(pmi, Some(view), white, &placements);
        assert!(o.annotations > 0, "{} shows annotations", view.name);
        let (lo, hi) = overlay_bounds(&o).map_or(part, |(a, b)| (part.0.min(a), part.1.max(b)));
        let camera = saved_view_camera(view, (lo, hi), 4.0 / 3.0, &placements);
        let mut scene: RenderScene = scene.clone();
        scene.lines = o.lines;
        scene.labels = o.labels;
        let prepared = renderer.prepare(&gpu, &scene);
        renderer
            .render(&gpu, &prepared, &camera, &options(320, 240), state)
            .expect("image")
    };
    let mut clipped = None;
    for view in &pmi.views {
        let sections = saved_view_sections(view, &placements);
        assert_eq!(
            sections.len(),
            usize::from(view.name == "03"),
            "{}",
            view.name
        );
        let state = ViewState {
            sections,
            ..ViewState::default()
        };
        let image = render(view, &state);
        assert!(pmi_ink(&image) > 100, "{}: {}", view.name, pmi_ink(&image));
        check_golden(&format!("pmi-bug32745-{}.png", view.name), &image);
        if !state.sections.is_empty() {
            clipped = Some((view, image));
        }
    }
    // Negative control: the clipped view without its section is another image (the near
    // half's outside instead of the cut through the counterbored holes).
    let (view, image) = clipped.expect("view 03 is clipped");
    let uncut = render(view, &ViewState::default());
    let c = cadre_render::compare::compare(&image, &uncut, 8);
    assert!(c.differing > 0.01, "the section changes {}", c.differing);
}

#[test]
fn a_generated_callout_points_at_its_face_not_into_the_hole() {
    let bytes = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/toolpath/plate.step"),
    )
    .expect("the bundled plate");
    let (model, _) = model_and_scene_of(bytes, 0.1);
    let (k, axis, radius) = model
        .faces
        .iter()
        .enumerate()
        .find_map(|(k, f)| match &model.surfaces[f.surface.index()] {
            cadre_geom::Surface::Cylinder { frame, radius } => Some((k, *frame, *radius)),
            _ => None,
        })
        .expect("a hole");
    let face = cadre_brep::FaceId(k as u32);
    let p = cadre_render::pmi::faces_anchor(&model, &[face]).expect("an anchor");
    let p = cadre_geom::Vec3::new(p.x, p.y, p.z);
    // On the hole's wall: at its radius from the axis.
    let d = p - axis.origin;
    let off_axis = (d - axis.z * d.dot(axis.z)).length();
    assert!(
        (off_axis - radius).abs() < 1e-6,
        "{off_axis} from the axis, radius {radius}"
    );
    // Negative control: the centre of the face's box is on the axis, in the air.
    let (b, _) =
        cadre_brep::bounds::face_bounds(&model, &model.faces[k], cadre_geom::Accuracy::default());
    let c = 0.5 * (b.min + b.max) - axis.origin;
    assert!((c - axis.z * c.dot(axis.z)).length() < 1e-6);
    assert!(cadre_render::pmi::faces_anchor(&model, &[]).is_none());
}
