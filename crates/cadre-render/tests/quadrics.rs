//! The ray-cast quadrics (seed 001) against the CPU `f64` ray caster: every class of quadric,
//! cut by 0 to 6 planes, as patches and volumes, in perspective and orthographic views and
//! magnified 1× to 10⁴× onto a silhouette. Every pixel farther than half a pixel from a true
//! boundary shows the oracle's primitive (silhouettes within 0.5 px), at the oracle's depth
//! within 2⁻²⁰ relative.

mod common;

use std::sync::Arc;

use cadre_geom::{CutKind, CutQuadric, Frame, HalfSpace, Quadric};
use cadre_render::raycast::RayCaster;
use cadre_render::{
    AnalyticPrimitive, AnalyticShape, Camera, FrameOptions, PreparedScene, QuadricShape,
    RenderScene, Renderer, ViewPreset, ViewState,
};
use common::gpu;
use glam::{DVec3, DVec4};

const W: u32 = 160;
const H: u32 = 120;

/// Face id of primitive k: `FIRST_ID + k`.
const FIRST_ID: u32 = 1000;

fn options() -> FrameOptions {
    FrameOptions {
        width: W,
        height: H,
        supersample: 1,
        ..FrameOptions::default()
    }
}

/// One quadric of every real-surface class, about unit size.
fn classes() -> Vec<Quadric> {
    vec![
        Quadric::ellipsoid(1.0, 0.7, 0.85),
        Quadric::hyperboloid_one_sheet(0.45, 0.55, 0.6),
        Quadric::hyperboloid_two_sheets(0.5, 0.45, 0.35),
        Quadric::cone(0.8, 0.6, 1.0),
        Quadric::elliptic_paraboloid(0.6, 0.8),
        Quadric::hyperbolic_paraboloid(0.8, 0.7),
        Quadric::elliptic_cylinder(0.6, 0.8),
        Quadric::hyperbolic_cylinder(0.35, 0.5),
        Quadric::parabolic_cylinder(0.3),
        Quadric::intersecting_planes(1.0, 0.7),
        Quadric::parallel_planes(0.6),
        Quadric::sphere(0.9),
    ]
}

/// `count` planes (0..=6) of a slightly tilted box of half-size 0.9: +z, −z, +x, −x, +y, −y.
fn box_planes(count: usize, tilt: f64) -> Vec<HalfSpace> {
    (0..count)
        .map(|i| {
            let axis = [DVec3::Z, DVec3::X, DVec3::Y][i / 2];
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            let lean = axis.any_orthonormal_vector() * tilt * (i as f64 + 1.0) * 0.3;
            HalfSpace::through(axis * sign * 0.9, (axis + lean) * sign)
        })
        .collect()
}

/// The grid of primitives: class k in cell k (4 × 3, 2.2 apart), rotated its own way, a patch
/// or a volume by turn, cut by as many planes as close it (6 for the unbounded classes, k % 4
/// for the ellipsoids). `scale` grows each one about its own centre (the negative control's
/// wrong oracle), `far` moves the whole grid away from the origin.
fn primitives(scale: f64, far: DVec3) -> Vec<AnalyticPrimitive> {
    classes()
        .into_iter()
        .enumerate()
        .map(|(k, q)| {
            let bounded = k == 0 || k == 11;
            let planes = if bounded { k % 4 } else { 6 };
            let kind = if k % 2 == 0 {
                CutKind::Patch
            } else {
                CutKind::Volume
            };
            let grow = glam::DMat4::from_scale(DVec3::splat(scale));
            let cut = CutQuadric {
                quadric: q,
                planes: box_planes(planes, 0.1 + 0.05 * k as f64),
                kind,
            }
            .transformed(grow)
            .expect("invertible");
            let shape = QuadricShape::new(cut).expect("bounded");
            let axis = DVec3::new(0.3 + 0.1 * k as f64, -0.4, 1.0);
            let frame = Frame::from_axis(
                far + DVec3::new(2.2 * (k % 4) as f64, 2.2 * (k / 4) as f64, 0.0),
                axis,
                Some(DVec3::new(1.0, 0.2 * k as f64, 0.0)),
            )
            .expect("frame");
            AnalyticPrimitive {
                shape: AnalyticShape::Quadric(Arc::clone(&shape)),
                frame,
                face_id: FIRST_ID + k as u32,
                colour: [0.2 + 0.05 * k as f32, 0.5, 0.8 - 0.05 * k as f32, 1.0],
            }
        })
        .collect()
}

struct Grid {
    shown: Vec<AnalyticPrimitive>,
    prepared: PreparedScene,
    caster: RayCaster,
    lo: DVec3,
    hi: DVec3,
}

fn grid(renderer: &Renderer, gpu: &cadre_render::Gpu, far: DVec3, oracle_scale: f64) -> Grid {
    let shown = primitives(1.0, far);
    let scene = RenderScene::default().with_primitives(shown.clone());
    let shown_again = shown;
    let (lo, hi) = scene.bounds().expect("primitives");
    let prepared = renderer.prepare(gpu, &scene);
    let mut caster = RayCaster::new(&cadre_brep::Model::default(), 1e-3);
    for p in primitives(oracle_scale, far) {
        caster.add_primitive(&p);
    }
    Grid {
        shown: shown_again,
        prepared,
        caster,
        lo,
        hi,
    }
}

/// What one view shows against the oracle: pixels compared (not within half a pixel of a
/// true boundary), those showing another primitive, the worst relative depth error among
/// the rest where the view ray meets the surface at more than [`GRAZING`] from its tangent
/// plane and where it does not, and how many pixels show a primitive at all.
#[derive(Debug)]
struct Comparison {
    compared: usize,
    wrong: usize,
    depth_error: f64,
    grazing_depth_error: f64,
    covered: usize,
}

/// sin of the angle between a view ray and the tangent plane below which the ray grazes:
/// there the depth of a hit is conditioned by 1 / sin (the root of a nearly double root), in
/// `f64` as in `f32`, while the hit stays on the surface.
const GRAZING: f64 = 0.05;

fn compare(
    gpu: &cadre_render::Gpu,
    renderer: &Renderer,
    grid: &Grid,
    camera: &Camera,
) -> Comparison {
    let ids = renderer
        .render_ids(
            gpu,
            &grid.prepared,
            camera,
            &options(),
            &ViewState::default(),
        )
        .expect("ids");
    let hits = grid.caster.hits(camera, W, H);
    let near = grid.caster.near_boundary(camera, W, H, 0.5);
    let aspect = f64::from(W) / f64::from(H);
    let clip = camera.projection_matrix(aspect) * camera.view_rotation();
    let mut out = Comparison {
        compared: 0,
        wrong: 0,
        depth_error: 0.0,
        grazing_depth_error: 0.0,
        covered: 0,
    };
    for (i, ((g, hit), near)) in ids.iter().zip(&hits).zip(&near).enumerate() {
        out.covered += usize::from(g[1] != 0);
        if *near {
            continue;
        }
        out.compared += 1;
        let shown = if g[1] == 0 { 0 } else { u64::from(g[0]) };
        let exact = hit.map_or(0, |(id, _)| id);
        if shown != exact {
            out.wrong += 1;
            continue;
        }
        if let Some((id, point)) = hit {
            let h = clip * DVec4::from(((point - camera.eye), 1.0));
            let depth = h.z / h.w;
            let gpu_depth = f64::from(f32::from_bits(g[3]));
            let error = (gpu_depth - depth).abs() / depth.abs();
            let (x, y) = ((i as u32 % W) as f64 + 0.5, (i as u32 / W) as f64 + 0.5);
            let k = (*id - u64::from(FIRST_ID)) as usize;
            if incidence(&grid.shown[k], camera, (x, y)) < GRAZING {
                out.grazing_depth_error = out.grazing_depth_error.max(error);
            } else {
                out.depth_error = out.depth_error.max(error);
            }
        }
    }
    out
}

/// Views of the grid: fitted iso, top and front in perspective, iso orthographic, and iso
/// magnified 100× and 10⁴× onto a silhouette point of each of three primitives.
fn cameras(grid: &Grid) -> Vec<(String, Camera)> {
    let aspect = f64::from(W) / f64::from(H);
    let mut out = Vec::new();
    for view in [ViewPreset::Iso, ViewPreset::Top, ViewPreset::Front] {
        out.push((
            format!("{view:?}"),
            Camera::fit(grid.lo, grid.hi, view, false, aspect),
        ));
    }
    let iso = Camera::fit(grid.lo, grid.hi, ViewPreset::Iso, true, aspect);
    out.push(("iso orthographic".into(), iso));
    let iso = Camera::fit(grid.lo, grid.hi, ViewPreset::Iso, false, aspect);
    // Silhouette points: where a row of the fitted view leaves a primitive, found to 10⁻¹²
    // of a pixel by bisection between the pixel that sees it and the next (so that at 10⁴×
    // the silhouette crosses the image).
    let ids = grid.caster.hits(&iso, W, H);
    let mut targets = Vec::new();
    for y in 1..H - 1 {
        for x in 1..W - 1 {
            let i = (y * W + x) as usize;
            if let (Some((a, _)), None) = (ids[i], ids[i + 1])
                && !targets.iter().any(|(id, _)| *id == a)
            {
                let k = (a - u64::from(FIRST_ID)) as usize;
                let point = silhouette(&grid.shown[k], &iso, (x, y));
                targets.push((a, point));
            }
        }
    }
    assert!(targets.len() >= 10, "{} silhouettes found", targets.len());
    for (id, point) in targets {
        for zoom in [100.0, 1e4] {
            out.push((
                format!("iso {zoom}× on primitive {id}"),
                iso.zoomed_at(point, zoom, (grid.lo, grid.hi)),
            ));
        }
    }
    out
}

/// The world ray through the point (x, y) of the image (pixel units, centres at + 0.5).
fn ray(camera: &Camera, x: f64, y: f64) -> (DVec3, DVec3) {
    let aspect = f64::from(W) / f64::from(H);
    let unproject = (camera.projection_matrix(aspect) * camera.view_rotation()).inverse();
    let at = |depth: f64| {
        let ndc = DVec4::new(
            x / f64::from(W) * 2.0 - 1.0,
            1.0 - y / f64::from(H) * 2.0,
            depth,
            1.0,
        );
        let p = unproject * ndc;
        p.truncate() / p.w
    };
    let (near, mid) = (at(1.0), at(0.5));
    (camera.eye + near, (mid - near).normalize())
}

/// |sin| of the angle between the ray through the image point (x, y) and the tangent plane
/// where it meets `p` (1 where it misses).
fn incidence(p: &AnalyticPrimitive, camera: &Camera, (x, y): (f64, f64)) -> f64 {
    let AnalyticShape::Quadric(q) = &p.shape else {
        unreachable!()
    };
    let (o, d) = ray(camera, x, y);
    let f = &p.frame;
    let local_d = DVec3::new(d.dot(f.x), d.dot(f.y), d.dot(f.z));
    q.cut()
        .hit(f.to_local(o), local_d, 0.0)
        .map_or(1.0, |h| h.normal.dot(local_d).abs())
}

/// The point of `p`'s silhouette on row `y` between pixel `x` (which sees it) and `x + 1`.
fn silhouette(p: &AnalyticPrimitive, camera: &Camera, (x, y): (u32, u32)) -> DVec3 {
    let AnalyticShape::Quadric(q) = &p.shape else {
        unreachable!()
    };
    let hit = |u: f64| {
        let (o, d) = ray(camera, u, f64::from(y) + 0.5);
        let f = &p.frame;
        let local_d = DVec3::new(d.dot(f.x), d.dot(f.y), d.dot(f.z));
        q.cut()
            .hit(f.to_local(o), local_d, 0.0)
            .map(|h| f.to_world(h.point))
    };
    let (mut a, mut b) = (f64::from(x) + 0.5, f64::from(x) + 1.5);
    let mut point = hit(a).expect("the pixel sees it");
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        match hit(m) {
            Some(h) => {
                a = m;
                point = h;
            }
            None => b = m,
        }
    }
    point
}

#[test]
fn every_class_cut_by_planes_matches_the_exact_ray_caster_at_every_zoom() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let grid = grid(&renderer, &gpu, DVec3::ZERO, 1.0);
    let cameras = cameras(&grid);
    assert!(cameras.len() >= 24, "{} views", cameras.len());
    for (name, camera) in cameras {
        let c = compare(&gpu, &renderer, &grid, &camera);
        eprintln!("{name}: {c:?}");
        assert!(c.covered > 200, "{name}: {c:?}");
        assert_eq!(
            c.wrong, 0,
            "{name}: pixels away from every boundary disagree: {c:?}"
        );
        assert!(c.depth_error <= 2f64.powi(-20), "{name}: depth {c:?}");
        assert!(
            c.grazing_depth_error <= 2f64.powi(-16),
            "{name}: grazing depth {c:?}"
        );
    }
}

#[test]
fn far_from_the_origin_the_quadrics_keep_their_precision() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let grid = grid(&renderer, &gpu, DVec3::new(3.0e5, -2.0e5, 1.0e5), 1.0);
    for (name, camera) in cameras(&grid) {
        let c = compare(&gpu, &renderer, &grid, &camera);
        eprintln!("{name}: {c:?}");
        assert_eq!(c.wrong, 0, "{name}: {c:?}");
        assert!(c.depth_error <= 2f64.powi(-20), "{name}: depth {c:?}");
        assert!(
            c.grazing_depth_error <= 2f64.powi(-16),
            "{name}: grazing depth {c:?}"
        );
    }
}

#[test]
fn a_wrong_oracle_or_a_wrong_depth_is_caught() {
    // Negative controls: an oracle whose primitives are 10 % larger disagrees with the image
    // away from the boundaries; the proxies' depth written instead of the hits' is off.
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let grown = grid(&renderer, &gpu, DVec3::ZERO, 1.1);
    let camera = Camera::fit(
        grown.lo,
        grown.hi,
        ViewPreset::Iso,
        false,
        f64::from(W) / f64::from(H),
    );
    let c = compare(&gpu, &renderer, &grown, &camera);
    assert!(c.wrong > 20, "{c:?}");
    let proxy = Renderer::new(&gpu).expect("pipelines").with_proxy_depth();
    let grid = grid(&proxy, &gpu, DVec3::ZERO, 1.0);
    let c = compare(&gpu, &proxy, &grid, &camera);
    assert!(c.depth_error > 1e-3, "{c:?}");
}

#[test]
fn silhouettes_carry_their_analytic_coverage() {
    // A 1× image with the quadrics' coverage (F / |∇F| in pixels from the silhouette conic
    // and the cut edges) is nearer a 4 × 4 supersampled one than the same image without it:
    // the thesis' robot (39 quadrics of 7 classes, cut by planes, patches and volumes).
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let text = std::fs::read_to_string(common::root().join("examples/scenes/robot.json"))
        .expect("scene reads");
    let loaded = cadre_render::scene_file::load_scene(&text).expect("scene loads");
    let scene = RenderScene::default().with_primitives(loaded.primitives);
    let (lo, hi) = scene.bounds().expect("objects");
    let prepared = renderer.prepare(&gpu, &scene);
    let (eye, target, up, fov) = loaded.camera.expect("camera");
    let camera = Camera::looking((eye, target, up), fov, (lo, hi));
    let image = |supersample: u32, analytic_coverage: bool| {
        let options = FrameOptions {
            width: W,
            height: H,
            supersample,
            smooth: false,
            analytic_coverage,
            ..FrameOptions::default()
        };
        renderer
            .render(&gpu, &prepared, &camera, &options, &ViewState::default())
            .expect("image")
    };
    let reference = image(4, false);
    let error = |img: &image::RgbaImage| -> f64 {
        img.pixels()
            .zip(reference.pixels())
            .map(|(a, b)| {
                (0..3)
                    .map(|c| (f64::from(a[c]) - f64::from(b[c])).abs())
                    .sum::<f64>()
            })
            .sum()
    };
    let (plain, covered) = (error(&image(1, false)), error(&image(1, true)));
    eprintln!("error against 4x4 supersampling: plain {plain:.0}, analytic coverage {covered:.0}");
    // Measured 0.84: the coverage blends the pixels whose centres are on the surface (as
    // the trimmed edges'); those just off it, the volumes' plane edges and the intersections
    // between primitives are left to supersampling.
    assert!(covered < 0.9 * plain, "{covered} vs {plain}");
}

#[test]
fn a_crowd_past_one_storage_binding_is_drawn_in_chunks() {
    // 400,000 records of 368 bytes are more than lavapipe's 128 MiB binding: the records go
    // in chunks, each drawn; the last chunk's objects show (face ids past the first chunk's).
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let text =
        r#"{"generate": [{"count": 400000, "kinds": ["sphere"], "extent": 200, "size": 1.5}]}"#;
    let loaded = cadre_render::scene_file::load_scene(text).expect("scene");
    let scene = RenderScene::default().with_primitives(loaded.primitives);
    let (lo, hi) = scene.bounds().expect("objects");
    let prepared = renderer.prepare(&gpu, &scene);
    let camera = Camera::fit(lo, hi, ViewPreset::Top, true, 1.0);
    let options = FrameOptions {
        width: 96,
        height: 96,
        supersample: 1,
        ..FrameOptions::default()
    };
    let ids = renderer
        .render_ids(&gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("a crowd past one binding renders");
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    let per_chunk = limit as usize / std::mem::size_of::<cadre_render::layout::Primitive>();
    let last = ids
        .iter()
        .filter(|g| g[1] != 0)
        .map(|g| g[0])
        .max()
        .unwrap_or(0);
    eprintln!("{per_chunk} records a chunk; largest face id shown {last}");
    if per_chunk < 400_000 {
        assert!(last as usize > per_chunk, "the second chunk is drawn");
    }
    let covered = ids.iter().filter(|g| g[1] != 0).count();
    eprintln!("covered {covered}");
    // The cube fills about a third of the fitted view (fitted to its bounding sphere).
    assert!(covered > 96 * 96 / 4, "{covered}");
}

#[test]
fn sections_cap_quadric_volumes_and_see_through_quadrics_blend() {
    // The house rule: a ray-cast quadric is cut and capped by section planes like a meshed
    // solid (a volume), and a see-through one leaves the ids to what is behind it.
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let cylinder = |volume: bool, colour: [f32; 4], id: u32, x: f64| AnalyticPrimitive {
        shape: AnalyticShape::Quadric(
            QuadricShape::new(CutQuadric {
                quadric: Quadric::cylinder(1.0),
                planes: vec![
                    HalfSpace::through(DVec3::new(0.0, 0.0, 1.5), DVec3::Z),
                    HalfSpace::through(DVec3::new(0.0, 0.0, -1.5), -DVec3::Z),
                ],
                kind: CutKind::volume_if(volume),
            })
            .expect("bounded"),
        ),
        frame: Frame {
            origin: DVec3::new(x, 0.0, 0.0),
            ..Frame::WORLD
        },
        face_id: id,
        colour,
    };
    let scene = RenderScene::default().with_primitives(vec![
        cylinder(true, [0.8, 0.3, 0.2, 1.0], 1, -1.5),
        cylinder(false, [0.2, 0.3, 0.8, 1.0], 2, 1.5),
    ]);
    let prepared = renderer.prepare(&gpu, &scene);
    let (lo, hi) = scene.bounds().expect("objects");
    let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, 1.0);
    let options = FrameOptions {
        width: 96,
        height: 96,
        supersample: 1,
        ..FrameOptions::default()
    };
    // Cut away the half facing the eye through both: the volume shows caps, the patch none.
    let towards_eye = (camera.eye - 0.5 * (lo + hi)).normalize();
    let state = ViewState {
        sections: vec![cadre_render::SectionPlane::through(
            0.5 * (lo + hi),
            towards_eye,
        )],
        ..ViewState::default()
    };
    let ids = renderer
        .render_ids(&gpu, &prepared, &camera, &options, &state)
        .expect("ids");
    let caps = |instance: u32| {
        ids.iter()
            .filter(|g| g[1] == instance + 1 && g[2] & cadre_render::SECTION_CAP != 0)
            .count()
    };
    let (volume, patch) = (
        caps(prepared.primitive_instance(0)),
        caps(prepared.primitive_instance(1)),
    );
    eprintln!("cap pixels: volume {volume}, patch {patch}");
    assert!(volume > 100 && patch == 0, "{volume} {patch}");
    // See-through: the patch at half opacity is left out of the ids (the volume stays).
    let faint = RenderScene::default().with_primitives(vec![
        cylinder(true, [0.8, 0.3, 0.2, 1.0], 1, -1.5),
        cylinder(false, [0.2, 0.3, 0.8, 0.5], 2, 1.5),
    ]);
    let prepared = renderer.prepare(&gpu, &faint);
    let ids = renderer
        .render_ids(&gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("ids");
    let shown = |id: u32| ids.iter().filter(|g| g[1] != 0 && g[0] == id).count();
    assert!(shown(1) > 100 && shown(2) == 0, "{} {}", shown(1), shown(2));
    let image = renderer
        .render(&gpu, &prepared, &camera, &options, &ViewState::default())
        .expect("image");
    // Where the faint cylinder is, the image is tinted blue, not the white background.
    let bluish = image
        .pixels()
        .filter(|p| p[2] > p[0] + 20 && p[0] < 240)
        .count();
    assert!(bluish > 100, "{bluish} blended pixels");
}
