//! The trim back-end (faces drawn from their exact surfaces, trimmed per pixel) against the
//! CPU ray caster of the exact B-Rep, pixel by pixel, on the adapter the tests draw on: at
//! the fitted views and at close-ups where the mesh's facets show. Negative control: the
//! faces drawn over their whole (u, v) boxes, untrimmed, disagree.

mod common;

use cadre_render::{Camera, FrameOptions, Gpu, RenderScene, Renderer, ViewPreset};
use common::{OneShot, gpu};

/// Object-space tolerance of the trims (mm).
const TRIM_TOLERANCE: f64 = 0.001;

/// The fixtures both exact ways are checked on: every closed-form surface, seams, apexes,
/// poles, a hole across a seam.
const FIXTURES: [&str; 10] = [
    "examples/pin-assembly.step",
    // Every face a B-spline (OCCT's NURBS conversion), drawn as the planes and the oblique
    // cylinder they are (`trim_quadrics`).
    "crates/cadre-render/tests/data/bspline-bore.step",
    // A B-spline sphere's corner cut by three B-spline planes, drawn as the sphere.
    "crates/cadre-render/tests/data/bspline-sphere-corner.step",
    "crates/cadre-render/tests/data/dome-and-cone.step",
    "crates/cadre-mesh/tests/data/cylinder_hole_across_seam.step",
    "crates/cadre-mesh/tests/data/cone_patch_clockwise.step",
    "crates/cadre-mesh/tests/data/half_cones_wrong_sense.step",
    "crates/cadre-mesh/tests/data/unit_cube.step",
    "crates/cadre-render/tests/data/torus-elbow.step",
    "crates/cadre-mesh/tests/data/quarter_sphere_collapsed_sides.step",
];

fn options(width: u32, height: u32) -> FrameOptions {
    FrameOptions {
        width,
        height,
        supersample: 1,
        background: [1.0, 1.0, 1.0, 1.0],
        ..FrameOptions::default()
    }
}

/// `camera` moved `zoom` times nearer the model's surface point seen at the image's
/// centre (or nearest it), looking at it.
fn zoomed(
    model: &cadre_brep::Model,
    camera: Camera,
    zoom: f64,
    bounds: (glam::DVec3, glam::DVec3),
) -> Camera {
    let (w, h) = (64, 48);
    let hits = cadre_render::raycast::RayCaster::new(model, 0.001).hits(&camera, w, h);
    let centre = |i: usize| {
        let (x, y) = (
            (i % w as usize) as f64 - 32.0,
            (i / w as usize) as f64 - 24.0,
        );
        x * x + y * y
    };
    let (_, point) = hits
        .iter()
        .enumerate()
        .filter_map(|(i, hit)| hit.map(|(_, p)| (centre(i), p)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("the view sees the model");
    camera.zoomed_at(point, zoom, bounds)
}

/// Pixels of the test's image where the ray caster sees a face.
fn covered(model: &cadre_brep::Model, camera: &Camera) -> usize {
    let caster = cadre_render::raycast::RayCaster::new(model, 0.001);
    caster
        .face_ids(camera, 128, 96)
        .iter()
        .filter(|&&id| id != 0)
        .count()
}

/// The share of the pixels either image covers, farther than half a pixel from a true
/// boundary, where the GPU's face id is the ray caster's (NaN when fewer than 100 are).
fn agreement(
    gpu: &Gpu,
    renderer: &Renderer,
    (model, scene): (&cadre_brep::Model, &RenderScene),
    camera: &Camera,
) -> f64 {
    agreement_from(gpu, renderer, (model, scene), (camera, camera))
}

/// [`agreement`] of the GPU's image from `drawn` with the ray caster's from `camera`.
fn agreement_from(
    gpu: &Gpu,
    renderer: &Renderer,
    (model, scene): (&cadre_brep::Model, &RenderScene),
    (drawn, camera): (&Camera, &Camera),
) -> f64 {
    let (w, h) = (128, 96);
    let ids = renderer
        .ids_of(gpu, scene, drawn, &options(w, h))
        .expect("ids");
    let caster = cadre_render::raycast::RayCaster::new(model, 0.001);
    assert!(caster.skipped.is_empty(), "{:?}", caster.skipped);
    let exact = caster.face_ids(camera, w, h);
    // Pixels within half a pixel of a true boundary may go either way (the measure).
    let near = caster.near_boundary(camera, w, h, 0.5);
    let either: Vec<bool> = ids
        .iter()
        .zip(&exact)
        .zip(&near)
        .filter(|((g, e), near)| (g[0] != 0 || **e != 0) && !**near)
        .map(|((g, e), _)| scene.face_step_id(g[0]) == *e)
        .collect();
    if either.len() < 100 {
        // A view of slivers and edges alone: nothing to compare away from boundaries.
        return f64::NAN;
    }
    if std::env::var("TRIM_DEBUG").is_ok() {
        let mut text = String::new();
        for y in 0..h as usize {
            for x in 0..w as usize {
                let i = y * w as usize + x;
                let g = scene.face_step_id(ids[i][0]);
                let e = exact[i];
                text.push(match (g == e, g != 0, e != 0) {
                    (true, false, _) => '.',
                    (true, true, _) => 'o',
                    (false, true, false) => 'G',
                    (false, false, true) => 'E',
                    _ => 'X',
                });
            }
            text.push('\n');
        }
        eprintln!("{text}");
        let faces: std::collections::BTreeSet<(u64, u64)> = ids
            .iter()
            .zip(&exact)
            .map(|(g, e)| (scene.face_step_id(g[0]), *e))
            .filter(|(g, e)| g != e)
            .collect();
        eprintln!("disagreeing (gpu, exact): {faces:?}");
    }
    either.iter().filter(|&&b| b).count() as f64 / either.len() as f64
}

#[test]
fn trimmed_faces_agree_with_the_exact_ray_caster() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    // The untrimmed control's largest loss against the trimmed faces, over every view.
    let mut worst_untrimmed: f64 = 0.0;
    let mut compared = 0;
    let untrimmed = Renderer::new(&gpu)
        .expect("pipelines")
        .without_trim_test(&gpu);
    // Every face's surface evaluated by the vertex shader, as when the tessellation pass's
    // room for grid points runs out.
    let vertex_eval = Renderer::new(&gpu)
        .expect("pipelines")
        .with_trim_variant(&gpu, (true, 256, false));
    for name in FIXTURES {
        let bytes = std::fs::read(common::root().join(name)).expect("fixture reads");
        let (model, mesh_scene) = common::model_and_scene_of(bytes, 0.01);
        let trim_scene = mesh_scene.clone().with_trims(&model, TRIM_TOLERANCE);
        let trims = trim_scene.trim.as_ref().expect("trims");
        assert!(trims.fallback.is_empty(), "{name}: {:?}", trims.fallback);
        let prepared = renderer.prepare(&gpu, &trim_scene);
        assert_eq!(prepared.trimmed_faces(), model.faces.len(), "{name}");
        let (lo, hi) = trim_scene.bounds().expect("geometry");
        for view in [ViewPreset::Iso, ViewPreset::Top, ViewPreset::Front] {
            let fitted = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
            for zoom in [1.0, 30.0] {
                let camera = zoomed(&model, fitted, zoom, (lo, hi));
                if zoom > 1.0 && covered(&model, &camera) < 1000 {
                    eprintln!("{name} {view:?} ×{zoom}: the close-up shows little; skipped");
                    continue;
                }
                let trim = agreement(&gpu, &renderer, (&model, &trim_scene), &camera);
                let mesh = agreement(&gpu, &renderer, (&model, &mesh_scene), &camera);
                if trim.is_nan() {
                    eprintln!("{name} {view:?} ×{zoom}: all boundaries; skipped");
                    continue;
                }
                compared += 1;
                eprintln!(
                    "{name} {view:?} ×{zoom}: trim {:.2} %, mesh {:.2} %",
                    100.0 * trim,
                    100.0 * mesh
                );
                assert!(trim >= 0.99, "{name} {view:?} ×{zoom}: {trim}");
                let by_vertex = agreement(&gpu, &vertex_eval, (&model, &trim_scene), &camera);
                assert!(
                    by_vertex >= 0.99,
                    "{name} {view:?} ×{zoom}: vertex eval {by_vertex}"
                );
                // Up close the mesh's facets show where the exact faces do not.
                if zoom > 1.0 {
                    assert!(
                        trim >= mesh - 0.002,
                        "{name} {view:?} ×{zoom}: {trim} < {mesh}"
                    );
                }
                // Negative control: untrimmed, the boxes cover what is not the face.
                let wrong = agreement(&gpu, &untrimmed, (&model, &trim_scene), &camera);
                eprintln!("  untrimmed {:.2} %", 100.0 * wrong);
                worst_untrimmed = worst_untrimmed.min(wrong - trim);
            }
        }
    }
    assert!(compared >= 30, "{compared} views compared");
    assert!(
        worst_untrimmed < -0.05,
        "untrimmed faces lost at most {worst_untrimmed} of the pixels"
    );
}

#[test]
fn ray_cast_faces_agree_with_the_exact_ray_caster_at_every_zoom() {
    // `--method raycast`: plane, cylinder, cone and sphere faces ray cast against their
    // support quadric and trimmed at the hit, the torus elbow's ring torus marched by its
    // exact distance. Negative control: the faces over their whole (u, v) boxes.
    let gpu = gpu();
    let renderer = Renderer::new(&gpu)
        .expect("pipelines")
        .with_ray_cast_faces(&gpu, true);
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    let untrimmed = Renderer::new(&gpu)
        .expect("pipelines")
        .with_ray_cast_faces(&gpu, false);
    let mut compared = 0;
    let mut worst_untrimmed: f64 = 0.0;
    for name in FIXTURES {
        let bytes = std::fs::read(common::root().join(name)).expect("fixture reads");
        let (model, mesh_scene) = common::model_and_scene_of(bytes, 0.01);
        let (lo, hi) = mesh_scene.bounds().expect("geometry");
        // The trims within a quarter pixel at each zoom, as `cadre render` builds them: a
        // fixed tolerance is pixels wide at 1000×.
        let scenes: Vec<(f64, RenderScene)> = [1.0, 100.0, 1000.0]
            .into_iter()
            .map(|zoom| {
                let pixel = (hi - lo).length() / (128.0 * zoom);
                let tolerance = TRIM_TOLERANCE.min(0.25 * pixel);
                (zoom, mesh_scene.clone().with_trims(&model, tolerance))
            })
            .collect();
        for view in [ViewPreset::Iso, ViewPreset::Top, ViewPreset::Front] {
            let fitted = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
            for (zoom, scene) in &scenes {
                let zoom = *zoom;
                let camera = zoomed(&model, fitted, zoom, (lo, hi));
                if zoom > 1.0 && covered(&model, &camera) < 1000 {
                    continue;
                }
                let cast = agreement(&gpu, &renderer, (&model, scene), &camera);
                if cast.is_nan() {
                    continue;
                }
                compared += 1;
                eprintln!("{name} {view:?} ×{zoom}: ray cast {:.2} %", 100.0 * cast);
                assert!(cast >= 0.995, "{name} {view:?} ×{zoom}: {cast}");
                if zoom == 1.0 {
                    let wrong = agreement(&gpu, &untrimmed, (&model, scene), &camera);
                    worst_untrimmed = worst_untrimmed.min(wrong - cast);
                }
            }
        }
    }
    assert!(compared >= 30, "{compared} views compared");
    assert!(
        worst_untrimmed < -0.05,
        "untrimmed faces lost at most {worst_untrimmed} of the pixels"
    );
}

/// B-spline faces (no ray-caster oracle for them yet): the trimmed faces' ids against a
/// mesh of a micrometre's deflection, on the pixels whose 3 × 3 neighbourhood holds one face
/// id in the mesh's image: the bundled quarter sphere (one untrimmed patch), and when the
/// corpus is beside the repository, its key (trj5_k1-al-214: a bicubic patch trimmed to a
/// toothed outline, ruled sides of degree 1 whose knot lines are folds). Negative controls:
/// another view's image, and the key untrimmed.
#[test]
fn trimmed_bspline_faces_agree_with_a_fine_mesh() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    let untrimmed = Renderer::new(&gpu)
        .expect("pipelines")
        .without_trim_test(&gpu);
    let key = common::root().join("../shared/corpus/step/trj5_k1-al-214.stp");
    let mut files = vec![(
        common::root().join("crates/cadre-mesh/tests/data/quarter_sphere_collapsed_sides.step"),
        false,
    )];
    if key.exists() {
        files.push((key, true));
    } else {
        eprintln!("../shared/corpus absent: the trimmed key is not checked");
    }
    for (path, trimmed_outline) in files {
        let bytes = std::fs::read(&path).expect("fixture reads");
        let (model, fine) = common::model_and_scene_of(bytes, 0.001);
        let trimmed = fine.clone().with_trims(&model, TRIM_TOLERANCE);
        let trims = trimmed.trim.as_ref().expect("trims");
        let bspline = trims
            .faces
            .iter()
            .flatten()
            .filter(|f| f.kind == cadre_render::trim_surfaces::SURFACE_BSPLINE)
            .count();
        assert!(bspline > 0, "{}: no B-spline face", path.display());
        let (lo, hi) = trimmed.bounds().expect("geometry");
        let (w, h) = (160usize, 120usize);
        let views = [
            ViewPreset::Iso,
            ViewPreset::Top,
            ViewPreset::Front,
            ViewPreset::Right,
        ];
        let mut worst_untrimmed: f64 = 0.0;
        let ids = |r: &Renderer, s: &RenderScene, view: ViewPreset| -> Vec<u64> {
            let camera = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
            r.ids_of(&gpu, s, &camera, &options(w as u32, h as u32))
                .expect("ids")
                .iter()
                .map(|p| s.face_step_id(p[0]))
                .collect()
        };
        for (k, &view) in views.iter().enumerate() {
            let mesh = ids(&renderer, &fine, view);
            let interior = |i: usize| {
                let (x, y) = (i % w, i / w);
                (x.saturating_sub(1)..=(x + 1).min(w - 1)).all(|a| {
                    (y.saturating_sub(1)..=(y + 1).min(h - 1)).all(|b| mesh[b * w + a] == mesh[i])
                })
            };
            let share = |other: &[u64]| {
                let kept: Vec<usize> = (0..w * h)
                    .filter(|&i| interior(i) && (mesh[i] != 0 || other[i] != 0))
                    .collect();
                let same = kept.iter().filter(|&&i| mesh[i] == other[i]).count();
                (same as f64 / kept.len().max(1) as f64, kept.len())
            };
            let (trim, n) = share(&ids(&renderer, &trimmed, view));
            let (other_view, _) = share(&ids(&renderer, &trimmed, views[(k + 1) % 4]));
            eprintln!(
                "{} {view:?}: trim {:.2} % of {n}, another view {:.2} %",
                path.display(),
                100.0 * trim,
                100.0 * other_view
            );
            if n < 100 {
                continue;
            }
            assert!(trim >= 0.99, "{view:?}: {trim}");
            assert!(
                other_view < 0.97,
                "{view:?}: another view agreed on {other_view}"
            );
            if trimmed_outline {
                let (wrong, _) = share(&ids(&untrimmed, &trimmed, view));
                eprintln!("  untrimmed {:.2} %", 100.0 * wrong);
                worst_untrimmed = worst_untrimmed.min(wrong - trim);
            }
        }
        if trimmed_outline {
            // Some view shows the outline (a side view may not).
            assert!(
                worst_untrimmed < -0.05,
                "untrimmed lost at most {worst_untrimmed}"
            );
        }
    }
}

/// `text` with every 3D Cartesian point moved by `offset`: the model translated (directions
/// are not points; the pcurves' 2D points stay).
fn translated(text: &str, offset: glam::DVec3) -> String {
    const KEY: &str = "CARTESIAN_POINT(";
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(KEY) {
        let (head, tail) = rest.split_at(at + KEY.len());
        out.push_str(head);
        // The name, then the coordinates' list.
        let open = tail.find(",(").expect("a point's coordinates") + 2;
        let close = open + tail[open..].find(')').expect("closed");
        let numbers: Vec<f64> = tail[open..close]
            .split(',')
            .map(|x| x.trim().parse().expect("a coordinate"))
            .collect();
        out.push_str(&tail[..open]);
        if numbers.len() == 3 {
            let p = glam::DVec3::new(numbers[0], numbers[1], numbers[2]) + offset;
            out.push_str(&format!("{:e},{:e},{:e}", p.x, p.y, p.z));
        } else {
            out.push_str(&tail[open..close]);
        }
        rest = &tail[close..];
    }
    out.push_str(rest);
    out
}

/// Parts far from their file's origin (corpus bug29478: a face half a millimetre wide,
/// 2,300 mm out): `f32` holds coordinates to 10⁻⁷ of their size, pixels of such a face up
/// close, unless each mesh is stored from its own centre, each B-spline's control points
/// from the face's, each linear parameter from its box's corner (the draw records adding
/// the rest in `f64`). The fixtures moved 3,000 times their size away, seen at 100×,
/// against the ray caster (in `f64`). Negative control: the GPU's image drawn two pixels
/// aside, the error a lost `f32` precision makes there, disagrees.
#[test]
fn faces_far_from_the_origin_keep_their_precision() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    let mut compared = 0;
    let mut worst_aside: f64 = 0.0;
    for name in [
        "crates/cadre-mesh/tests/data/quarter_sphere_collapsed_sides.step",
        "crates/cadre-render/tests/data/dome-and-cone.step",
        "crates/cadre-mesh/tests/data/cylinder_hole_across_seam.step",
    ] {
        let text = std::fs::read_to_string(common::root().join(name)).expect("fixture reads");
        let (_, near) = common::model_and_scene_of(text.clone().into_bytes(), 0.01);
        let (lo, hi) = near.bounds().expect("geometry");
        let offset = glam::DVec3::new(0.74, 0.12, 0.66) * (3000.0 * (hi - lo).length());
        let far = translated(&text, offset);
        let (model, scene) = common::model_and_scene_of(far.into_bytes(), 0.01);
        let scene = scene.with_trims(&model, TRIM_TOLERANCE);
        let (lo, hi) = scene.bounds().expect("geometry");
        for view in [ViewPreset::Iso, ViewPreset::Front] {
            let fitted = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
            let camera = zoomed(&model, fitted, 100.0, (lo, hi));
            if covered(&model, &camera) < 1000 {
                eprintln!("{name} {view:?} ×100: the close-up shows little; skipped");
                continue;
            }
            let trim = agreement(&gpu, &renderer, (&model, &scene), &camera);
            if trim.is_nan() {
                continue;
            }
            // Two pixels to the right: the eye and target moved along the image's x.
            let forward = (camera.target - camera.eye).normalize();
            let right = forward.cross(camera.up).normalize();
            let pixel = match camera.projection {
                cadre_render::Projection::Perspective { fov_y } => {
                    2.0 * (camera.target - camera.eye).length() * (0.5 * fov_y).tan() / 96.0
                }
                cadre_render::Projection::Orthographic { height } => height / 96.0,
            };
            let aside = Camera {
                eye: camera.eye + right * (2.0 * pixel),
                target: camera.target + right * (2.0 * pixel),
                ..camera
            };
            let wrong = agreement_from(&gpu, &renderer, (&model, &scene), (&aside, &camera));
            eprintln!(
                "{name} {view:?} ×100, {:.0} mm out: trim {:.2} %, drawn 2 px aside {:.2} %",
                offset.length(),
                100.0 * trim,
                100.0 * wrong
            );
            assert!(trim >= 0.99, "{name} {view:?}: {trim}");
            worst_aside = worst_aside.min(wrong - trim);
            compared += 1;
        }
    }
    assert!(compared >= 3, "{compared} views compared");
    assert!(
        worst_aside < -0.005,
        "two pixels aside lost at most {worst_aside} of the pixels"
    );
}

/// Face pixels whose written normal faces away from the eye (orthographic views: the eye
/// looks down −z in view space), out of the face pixels; the 10-bit octahedral map is
/// within 0.003 of the written normal, so −0.01 leaves room for it.
fn normals_facing_away(
    gpu: &Gpu,
    renderer: &Renderer,
    scene: &RenderScene,
    camera: &Camera,
) -> (usize, usize) {
    let prepared = renderer.prepare(gpu, scene);
    let options = options(256, 192);
    let state = cadre_render::ViewState::default();
    let ids = renderer
        .render_ids(gpu, &prepared, camera, &options, &state)
        .expect("ids");
    let normals = renderer
        .render_normals(gpu, &prepared, camera, &options, &state)
        .expect("normals");
    let faces = ids.iter().filter(|id| id[1] != 0).count();
    let away = ids
        .iter()
        .zip(&normals)
        .filter(|(id, n)| id[1] != 0 && n[2] < -0.01)
        .count();
    (away, faces)
}

/// A tessellated curved face's triangles across its silhouette hold points whose
/// interpolated normals lie beyond it, facing away from the eye while the triangle faces
/// it; the shade pass turned such a normal round and lit the pixel as the far side (dark
/// bands along a coarse mesh's silhouettes, specks along a grid's). And a grid held within
/// half a pixel of its surface ends short of the true silhouette, where the face behind it
/// on the same closed solid (a plane cap seen from inside, its trim exact) showed through,
/// lit as facing the eye. On closed solids seen from outside, no back-end writes a normal
/// facing away (the ray-cast faces' are exact, and their tessellated ones' as the trim
/// back-end's); negative control: with the raw normals, and the faces seen from inside
/// kept, the mesh and trim back-ends do.
#[test]
fn silhouette_pixels_keep_normals_facing_the_eye() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let raw = Renderer::new(&gpu)
        .expect("pipelines")
        .with_raw_silhouettes();
    let trims = renderer.draws_trims();
    let cast = Renderer::new(&gpu)
        .expect("pipelines")
        .with_ray_cast_faces(&gpu, true);
    let cast_raw = Renderer::new(&gpu)
        .expect("pipelines")
        .with_ray_cast_faces(&gpu, true)
        .with_raw_silhouettes();
    // Pixels facing away in the control: the meshes', the trimmed faces'.
    let mut raw_away = (0, 0);
    for name in [
        "examples/pin-assembly.step",
        "crates/cadre-render/tests/data/dome-and-cone.step",
        "crates/cadre-render/tests/data/torus-elbow.step",
    ] {
        let bytes = std::fs::read(common::root().join(name)).expect("fixture reads");
        // A coarse mesh: long triangles across the silhouettes.
        let (model, mesh_scene) = common::model_and_scene_of(bytes, 0.5);
        let trim_scene = mesh_scene.clone().with_trims(&model, TRIM_TOLERANCE);
        let (lo, hi) = mesh_scene.bounds().expect("geometry");
        for view in [ViewPreset::Iso, ViewPreset::Front, ViewPreset::Top] {
            let camera = Camera::fit(lo, hi, view, true, 4.0 / 3.0);
            let mut ways = vec![("mesh", &mesh_scene, (&renderer, &raw))];
            if trims {
                ways.push(("trim", &trim_scene, (&renderer, &raw)));
                ways.push(("raycast", &trim_scene, (&cast, &cast_raw)));
            }
            for (method, scene, (renderer, raw)) in ways {
                let (away, faces) = normals_facing_away(&gpu, renderer, scene, &camera);
                let (control, _) = normals_facing_away(&gpu, raw, scene, &camera);
                eprintln!("{name} {view:?} {method}: {away} of {faces} face away ({control} raw)");
                assert!(faces > 1000, "{name} {view:?} {method}: {faces}");
                assert_eq!(away, 0, "{name} {view:?} {method}");
                match method {
                    "mesh" => raw_away.0 += control,
                    "trim" => raw_away.1 += control,
                    _ => {}
                }
            }
        }
    }
    assert!(
        raw_away.0 > 0,
        "the control's meshes face the eye: {raw_away:?}"
    );
    assert!(
        !trims || raw_away.1 > 0,
        "the control's grids face the eye: {raw_away:?}"
    );
}

/// A mirroring placement turns the winding over but not the exact normals (their inverse
/// transpose keeps them outward): the trim back-end's faces of a mirrored closed solid are
/// drawn as its mesh is, not left out as seen from inside (`DRAW_MIRRORED`; without it the
/// mirrored pin's trimmed faces matched its mesh's at 23 % of its pixels). Control: the
/// same part unmirrored.
#[test]
fn mirrored_parts_keep_their_trimmed_faces() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    if !renderer.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders");
        return;
    }
    let bytes = std::fs::read(common::root().join("examples/pin-assembly.step")).expect("reads");
    let (model, mesh_scene) = common::model_and_scene_of(bytes, 0.01);
    for mirrored in [false, true] {
        let mut mesh_scene = mesh_scene.clone();
        if mirrored {
            for &root in &mesh_scene.assembly.roots.clone() {
                let node = &mut mesh_scene.assembly.nodes[root];
                node.transform =
                    glam::DAffine3::from_scale(glam::DVec3::new(-1.0, 1.0, 1.0)) * node.transform;
            }
        }
        let trim_scene = mesh_scene.clone().with_trims(&model, TRIM_TOLERANCE);
        let (lo, hi) = mesh_scene.bounds().expect("geometry");
        let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, 4.0 / 3.0);
        let opts = options(256, 192);
        let mesh = renderer
            .ids_of(&gpu, &mesh_scene, &camera, &opts)
            .expect("ids");
        let trim = renderer
            .ids_of(&gpu, &trim_scene, &camera, &opts)
            .expect("ids");
        let covered = mesh.iter().filter(|p| p[1] != 0).count();
        let same = mesh
            .iter()
            .zip(&trim)
            .filter(|(m, t)| m[1] != 0 && m[0] == t[0])
            .count();
        let share = same as f64 / covered.max(1) as f64;
        eprintln!("mirrored {mirrored}: {covered} px, trim's faces the mesh's at {share:.4}");
        assert!(
            covered > 1000 && share > 0.98,
            "mirrored {mirrored}: {share}"
        );
    }
}

/// Pixels of `camera`'s 128 × 96 image where the ray caster sees one of the faces `faces`
/// (STEP ids) at the pixel's centre and `renderer`'s image shows nothing.
fn faces_missing(
    gpu: &Gpu,
    renderer: &Renderer,
    (model, scene): (&cadre_brep::Model, &RenderScene),
    camera: &Camera,
    faces: &[u64],
) -> usize {
    let (w, h) = (128, 96);
    let ids = renderer
        .ids_of(gpu, scene, camera, &options(w, h))
        .expect("ids");
    let caster = cadre_render::raycast::RayCaster::new(model, 0.001);
    let exact = caster.face_ids(camera, w, h);
    ids.iter()
        .zip(&exact)
        .filter(|(g, e)| faces.contains(e) && g[1] == 0)
        .count()
}

#[test]
fn ray_cast_tori_reach_their_true_silhouette() {
    // `--method raycast` marches a ring torus's exact distance (raycast.wgsl's
    // `cast_torus`), so the torus elbow's silhouette over the background is the exact one:
    // no pixel whose centre the exact image shows on the torus is left empty. Negative
    // control: the torus tessellated by the trim back-end, whose grid, held within half a
    // pixel of the surface, ends short of the silhouette and leaves some.
    let gpu = gpu();
    let cast = Renderer::new(&gpu)
        .expect("pipelines")
        .with_ray_cast_faces(&gpu, true);
    if !cast.draws_trims() {
        eprintln!("skipped: the adapter runs no compute shaders, its scenes keep their meshes");
        return;
    }
    let grid = Renderer::new(&gpu).expect("pipelines");
    let (model, mesh_scene) = common::model_and_scene_at("torus-elbow.step", 0.01);
    let (lo, hi) = mesh_scene.bounds().expect("geometry");
    let torus = [66, 76];
    let (mut cast_missing, mut grid_missing) = (0, 0);
    for zoom in [1.0, 2.0, 3.0, 10.0] {
        let pixel = (hi - lo).length() / (128.0 * zoom);
        let scene = mesh_scene
            .clone()
            .with_trims(&model, TRIM_TOLERANCE.min(0.25 * pixel));
        for view in [
            ViewPreset::Iso,
            ViewPreset::Top,
            ViewPreset::Front,
            ViewPreset::Right,
        ] {
            let fitted = Camera::fit(lo, hi, view, false, 4.0 / 3.0);
            let camera = zoomed(&model, fitted, zoom, (lo, hi));
            let c = faces_missing(&gpu, &cast, (&model, &scene), &camera, &torus);
            let g = faces_missing(&gpu, &grid, (&model, &scene), &camera, &torus);
            eprintln!("{view:?} ×{zoom}: torus pixels left empty, ray cast {c}, grid {g}");
            cast_missing += c;
            grid_missing += g;
        }
    }
    assert_eq!(cast_missing, 0, "ray-cast torus pixels left empty");
    assert!(grid_missing >= 4, "the grid's control left {grid_missing}");
}
