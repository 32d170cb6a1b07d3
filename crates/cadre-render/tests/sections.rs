//! Section planes on the machine's adapter (lavapipe in CI): what a plane cuts away is gone,
//! closed solids get caps exactly where the plane passes through their material (checked
//! against a CPU inside test on the same triangles), caps lie on their plane, planes that miss
//! the model change nothing, three planes cut a corner, caps are hatched, and one golden
//! image.

mod common;

use cadre_render::{
    Camera, DisplayMode, FrameOptions, Gpu, PreparedScene, RenderScene, Renderer, SectionPlane,
    ViewPreset, ViewState, section_cap,
};
use common::{check_golden, gpu, scene};
use glam::{DAffine3, DVec3, DVec4};
use image::RgbaImage;

const W: u32 = 128;
const H: u32 = 96;

/// The scene with every root placed by `t` first.
fn placed(scene: &RenderScene, t: DAffine3) -> RenderScene {
    let mut out = scene.clone();
    for &r in &scene.assembly.roots {
        out.assembly.nodes[r].transform = t * out.assembly.nodes[r].transform;
    }
    out
}

fn options(supersample: u32) -> FrameOptions {
    FrameOptions {
        width: W,
        height: H,
        supersample,
        ..FrameOptions::default()
    }
}

/// The fixtures, each with a plane normal that cuts it through the middle of its box
/// towards the iso eye (the pins lie apart: only a horizontal plane meets both) and a point
/// inside one solid where three planes keep a corner.
const FIXTURES: [(&str, DVec3, DVec3); 2] = [
    ("pin-assembly.step", DVec3::Z, DVec3::new(20.0, 0.0, 5.0)),
    (
        "dome-and-cone.step",
        DVec3::NEG_Y,
        DVec3::new(12.0, 0.0, 3.0),
    ),
];

/// A scene seen from `preset`: its camera, centre and size (box diagonal).
struct View {
    camera: Camera,
    centre: DVec3,
    size: f64,
}

fn view(scene: &RenderScene, preset: ViewPreset) -> View {
    view_ortho(scene, preset, false)
}

fn view_ortho(scene: &RenderScene, preset: ViewPreset, orthographic: bool) -> View {
    let (lo, hi) = scene.bounds().expect("geometry");
    View {
        camera: Camera::fit(lo, hi, preset, orthographic, f64::from(W) / f64::from(H)),
        centre: 0.5 * (lo + hi),
        size: (hi - lo).length(),
    }
}

fn sections(planes: &[SectionPlane]) -> ViewState {
    ViewState {
        sections: planes.to_vec(),
        ..ViewState::default()
    }
}

fn ids(
    gpu: &Gpu,
    renderer: &Renderer,
    prepared: &PreparedScene,
    camera: &Camera,
    state: &ViewState,
) -> Vec<[u32; 4]> {
    renderer
        .render_ids(gpu, prepared, camera, &options(1), state)
        .expect("ids")
}

/// The world point a pixel's reverse-Z depth lands on.
fn unproject(camera: &Camera, (x, y): (u32, u32), depth: f32) -> DVec3 {
    let m = camera.projection_matrix(f64::from(W) / f64::from(H)) * camera.view_rotation();
    let ndc = DVec4::new(
        (f64::from(x) + 0.5) / f64::from(W) * 2.0 - 1.0,
        1.0 - (f64::from(y) + 0.5) / f64::from(H) * 2.0,
        f64::from(depth),
        1.0,
    );
    let p = m.inverse() * ndc;
    camera.eye + p.truncate() / p.w
}

/// The view ray of a pixel: origin (on the near plane) and unit direction.
fn ray(camera: &Camera, (x, y): (u32, u32)) -> (DVec3, DVec3) {
    let near = unproject(camera, (x, y), 1.0);
    let far = unproject(camera, (x, y), 0.5);
    (near, (far - near).normalize())
}

/// Signed distance of `p` from the plane (positive on the cut-away side).
fn signed(plane: &SectionPlane, p: DVec3) -> f64 {
    plane.normal.dot(p) - plane.offset
}

/// Every triangle of the scene in world coordinates.
fn world_triangles(scene: &RenderScene) -> Vec<[DVec3; 3]> {
    let scene = &scene.assembly;
    let mut out = Vec::new();
    for (node, world) in scene.instances() {
        let Some(mesh) = scene.nodes[node].mesh else {
            continue;
        };
        let mesh = &scene.meshes[mesh];
        for prim in &mesh.primitives {
            for tri in prim.indices.chunks_exact(3) {
                out.push([tri[0], tri[1], tri[2]].map(|i| {
                    world.transform_point3(DVec3::from(mesh.positions[i as usize].map(f64::from)))
                }));
            }
        }
    }
    out
}

/// Whether `p` lies inside the closed triangle meshes: crossings of a ray from it (in a
/// direction no fixture edge is parallel to) are odd.
fn inside(triangles: &[[DVec3; 3]], p: DVec3) -> bool {
    let d = DVec3::new(0.1234, 0.2718, 0.9541).normalize();
    let mut crossings = 0;
    for [a, b, c] in triangles {
        // Möller–Trumbore.
        let (e1, e2) = (*b - *a, *c - *a);
        let q = d.cross(e2);
        let det = e1.dot(q);
        if det.abs() < 1e-18 {
            continue;
        }
        let s = p - *a;
        let u = s.dot(q) / det;
        let r = s.cross(e1);
        let v = d.dot(r) / det;
        let t = e2.dot(r) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 {
            crossings += 1;
        }
    }
    crossings % 2 == 1
}

/// Where the view ray of a pixel enters the region the planes keep (the nearest point a cap
/// could be drawn at), if it does so past the near plane after crossing a plane.
fn entry(camera: &Camera, px: (u32, u32), planes: &[SectionPlane]) -> Option<DVec3> {
    let (o, d) = ray(camera, px);
    let mut t_in = 0.0f64;
    for plane in planes {
        let towards = plane.normal.dot(d);
        let t = -signed(plane, o) / towards;
        if towards < 0.0 {
            // Entering this plane's kept side.
            t_in = t_in.max(t);
        } else if signed(plane, o) > 0.0 {
            // Moving away while cut: never kept.
            return None;
        }
    }
    (t_in > 0.0).then_some(o + d * t_in)
}

/// Checks a sectioned id image against the unsectioned one and the CPU oracle: no visible
/// point is cut away, caps lie on their planes, kept surfaces are unchanged, and caps are
/// where the view ray enters the kept region inside a solid. Returns the cap pixel count.
fn check_sectioned(
    v: &View,
    triangles: &[[DVec3; 3]],
    planes: &[SectionPlane],
    plain: &[[u32; 4]],
    cut: &[[u32; 4]],
) -> usize {
    let tol = 1e-3 * v.size;
    let (mut caps, mut agree, mut tested) = (0, 0, 0);
    let (mut kept_before, mut kept_same) = (0, 0);
    for (i, (a, b)) in plain.iter().zip(cut).enumerate() {
        let px = (i as u32 % W, i as u32 / W);
        if b[1] != 0 {
            let p = unproject(&v.camera, px, f32::from_bits(b[3]));
            for plane in planes {
                assert!(
                    signed(plane, p) < tol,
                    "pixel {px:?} shows a cut-away point"
                );
            }
            if let Some(k) = section_cap(*b) {
                caps += 1;
                let d = signed(&planes[k], p).abs();
                assert!(d < tol, "cap pixel {px:?} lies {d} off its plane");
                assert_eq!(b[0], 0, "a cap has no face id");
            }
        }
        // What the plane keeps (by a margin) is drawn as before.
        if a[1] != 0 {
            let p = unproject(&v.camera, px, f32::from_bits(a[3]));
            if planes.iter().all(|plane| signed(plane, p) < -tol) {
                kept_before += 1;
                kept_same += usize::from(a == b);
            }
        }
        // The oracle, on every other pixel (a CPU ray test per pixel).
        if i % 2 == 0 {
            let expected = entry(&v.camera, px, planes).is_some_and(|q| inside(triangles, q));
            tested += 1;
            agree += usize::from(expected == section_cap(*b).is_some());
        }
    }
    assert!(
        kept_same as f64 >= 0.995 * kept_before as f64,
        "{kept_same} of {kept_before} kept pixels unchanged"
    );
    eprintln!(
        "caps agree with the oracle on {agree} of {tested} pixels; {kept_same} of {kept_before} kept pixels unchanged"
    );
    assert!(
        agree as f64 >= 0.98 * tested as f64,
        "caps agree with the oracle on {agree} of {tested} pixels"
    );
    caps
}

#[test]
fn a_plane_through_the_middle_cuts_away_its_side_and_caps_the_solids() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    for (name, normal, _) in FIXTURES {
        let base = scene(name);
        // Also mirrored (the winding turns over), a million millimetres away (the plane's
        // offset is taken relative to the eye in f64) and orthographic (parallel rays).
        let mirror = DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let far = DAffine3::from_translation(DVec3::new(1e6, -1e6, 1e6));
        let mut masks = Vec::new();
        for (label, t, ortho) in [
            ("as is", DAffine3::IDENTITY, false),
            ("mirrored", mirror, false),
            ("far", far, false),
            ("orthographic", DAffine3::IDENTITY, true),
        ] {
            let scene = placed(&base, t);
            let v = view_ortho(&scene, ViewPreset::Iso, ortho);
            let prepared = renderer.prepare(&gpu, &scene);
            let plain = ids(&gpu, &renderer, &prepared, &v.camera, &ViewState::default());
            let normal = t.transform_vector3(normal);
            let plane = SectionPlane::through(v.centre, normal);
            let cut = ids(&gpu, &renderer, &prepared, &v.camera, &sections(&[plane]));
            let before = plain.iter().filter(|p| p[1] != 0).count();
            let after = cut.iter().filter(|p| p[1] != 0).count();
            let removed = plain
                .iter()
                .enumerate()
                .filter(|(i, p)| {
                    let px = (*i as u32 % W, *i as u32 / W);
                    p[1] != 0
                        && signed(&plane, unproject(&v.camera, px, f32::from_bits(p[3])))
                            > 1e-3 * v.size
                })
                .count();
            assert!(
                removed > 100,
                "{name} {label}: {removed} pixels to cut away"
            );
            let triangles = world_triangles(&scene);
            let caps = check_sectioned(&v, &triangles, &[plane], &plain, &cut);
            eprintln!(
                "{name} {label}: {before} covered, {removed} cut away, {after} after, {caps} caps"
            );
            assert!(caps > 100, "{name} {label}: {caps} cap pixels");
            masks.push(cut.iter().map(|p| section_cap(*p)).collect::<Vec<_>>());
        }
        // Far away, the caps cover the same pixels.
        let same = masks[0]
            .iter()
            .zip(&masks[2])
            .filter(|(a, b)| a == b)
            .count();
        assert!(
            same as f64 >= 0.995 * masks[0].len() as f64,
            "{name}: far caps agree on {same} pixels"
        );
    }
}

#[test]
fn a_plane_that_misses_the_model_changes_nothing() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = scene("pin-assembly.step");
    let v = view(&scene, ViewPreset::Iso);
    let prepared = renderer.prepare(&gpu, &scene);
    let plain = ids(&gpu, &renderer, &prepared, &v.camera, &ViewState::default());
    let image = |state: &ViewState| {
        renderer
            .render(&gpu, &prepared, &v.camera, &options(1), state)
            .expect("image")
    };
    let plain_image = image(&ViewState::default());
    let towards_eye = (v.camera.eye - v.centre).normalize();
    for (label, plane) in [
        // Between the model and the eye, facing the eye: the eye is cut away, not the model.
        (
            "in front",
            SectionPlane::through(v.centre + towards_eye * 0.6 * v.size, towards_eye),
        ),
        // Behind the model, facing away.
        (
            "behind",
            SectionPlane::through(v.centre - towards_eye * 0.6 * v.size, -towards_eye),
        ),
        // Beside it, along an axis.
        (
            "beside",
            SectionPlane::through(v.centre + DVec3::X * 0.6 * v.size, DVec3::X),
        ),
    ] {
        let state = sections(&[plane]);
        let cut = ids(&gpu, &renderer, &prepared, &v.camera, &state);
        assert!(plain == cut, "{label}: the ids changed");
        assert_eq!(
            image(&state).as_raw(),
            plain_image.as_raw(),
            "{label}: the image changed"
        );
    }
}

#[test]
fn three_planes_keep_a_corner() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    for (name, _, corner) in FIXTURES {
        let scene = scene(name);
        let v = view(&scene, ViewPreset::Iso);
        let prepared = renderer.prepare(&gpu, &scene);
        let plain = ids(&gpu, &renderer, &prepared, &v.camera, &ViewState::default());
        // Each plane cuts away the side facing the iso eye (+X, −Y, +Z): what stays is the
        // corner away from it, whose three cut faces face the eye. A fourth plane is ignored.
        let planes = [DVec3::X, DVec3::NEG_Y, DVec3::Z].map(|n| SectionPlane::through(corner, n));
        let ignored = SectionPlane::through(corner, DVec3::NEG_X);
        let mut state = sections(&planes);
        state.sections.push(ignored);
        let cut = ids(&gpu, &renderer, &prepared, &v.camera, &state);
        let triangles = world_triangles(&scene);
        let caps = check_sectioned(&v, &triangles, &planes, &plain, &cut);
        let mut per_plane = [0usize; 3];
        for p in &cut {
            if let Some(k) = section_cap(*p) {
                per_plane[k] += 1;
            }
        }
        eprintln!("{name}: {caps} cap pixels, per plane {per_plane:?}");
        assert!(
            per_plane.iter().all(|&n| n > 10),
            "{name}: caps per plane {per_plane:?}"
        );
    }
}

#[test]
fn caps_are_hatched() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let scene = scene("dome-and-cone.step");
    let v = view(&scene, ViewPreset::Iso);
    let prepared = renderer.prepare(&gpu, &scene);
    let state = sections(&[SectionPlane::through(v.centre, DVec3::NEG_Y)]);
    let cut = ids(&gpu, &renderer, &prepared, &v.camera, &state);
    let image = renderer
        .render(&gpu, &prepared, &v.camera, &options(1), &state)
        .expect("image");
    // The caps' inner pixels (two pixels from anything else: the outline stays out).
    let is_cap = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(W)
            && y < i64::from(H)
            && section_cap(cut[(y * i64::from(W) + x) as usize]).is_some()
    };
    let mut luma = Vec::new();
    for y in 0..i64::from(H) {
        for x in 0..i64::from(W) {
            if (-2..=2).all(|dy| (-2..=2).all(|dx| is_cap(x + dx, y + dy))) {
                let p = image.get_pixel(x as u32, y as u32).0;
                luma.push((f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0);
            }
        }
    }
    assert!(luma.len() > 100, "{} inner cap pixels", luma.len());
    let mut sorted = luma.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let mean = luma.iter().sum::<f64>() / luma.len() as f64;
    let variance = luma.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / luma.len() as f64;
    let dark = luma.iter().filter(|&&l| l < 0.7 * median).count() as f64 / luma.len() as f64;
    eprintln!(
        "caps: median {median:.0}, std {:.1}, dark {dark:.3}",
        variance.sqrt()
    );
    assert!(
        variance.sqrt() > 15.0,
        "caps are flat: std {}",
        variance.sqrt()
    );
    // Lines one pixel wide every eight pixels (across the lines): about a tenth of the
    // pixels are mostly line.
    assert!((0.04..0.3).contains(&dark), "dark fraction {dark}");
    // The rest of the cap is the part's colour, not black.
    assert!(median > 80.0, "median {median}");
}

/// The dome and cone cut in half towards the iso eye, with edges, 256 × 192 (at 128 the
/// hatching has two or three lines per cap).
fn sectioned_image(gpu: &Gpu) -> RgbaImage {
    let renderer = Renderer::new(gpu).expect("pipelines");
    let scene = scene("dome-and-cone.step");
    let (lo, hi) = scene.bounds().expect("geometry");
    let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, 4.0 / 3.0);
    let prepared = renderer.prepare(gpu, &scene);
    let state = sections(&[SectionPlane::through(0.5 * (lo + hi), DVec3::NEG_Y)]);
    let options = FrameOptions {
        mode: DisplayMode::ShadedEdges,
        width: 256,
        height: 192,
        ..options(2)
    };
    renderer
        .render(gpu, &prepared, &camera, &options, &state)
        .expect("image")
}

#[test]
fn a_sectioned_fixture_matches_its_golden_image() {
    check_golden("dome-and-cone-iso-section.png", &sectioned_image(&gpu()));
}

/// GL through EGL (llvmpipe) draws the same caps (its front faces and depth conventions
/// differ from Vulkan's underneath); machines without an EGL driver skip, saying so.
#[test]
fn the_gl_backend_draws_the_same_sections() {
    if std::env::var_os("CADRE_BLESS").is_some() {
        return;
    }
    match Gpu::headless_on(cadre_render::wgpu::Backends::GL) {
        Ok(gpu) => check_golden("dome-and-cone-iso-section.png", &sectioned_image(&gpu)),
        Err(e) => eprintln!("skipping: no GL adapter ({e})"),
    }
}
