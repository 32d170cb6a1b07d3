//! The analytic back-end beside the mesh back-end in one visibility buffer: a meshed model
//! with a ray-cast sphere and rectangle cutting through it, against the CPU ray caster of the
//! exact B-Rep (which casts the same primitives), pixel by pixel, intersections included.

mod common;

use cadre_geom::Frame;
use cadre_render::raycast::RayCaster;
use cadre_render::{
    AnalyticPrimitive, AnalyticShape, Camera, FrameOptions, PreparedScene, RenderScene, Renderer,
    SECTION_CAP, SectionPlane, ViewPreset, ViewState,
};
use common::{gpu, model_and_scene_at};
use glam::DVec3;

const W: u32 = 160;
const H: u32 = 120;

/// Face ids of the primitives, past every STEP id of the fixture.
const SPHERE_ID: u32 = 900_000_001;
const RECTANGLE_ID: u32 = 900_000_002;

fn options() -> FrameOptions {
    FrameOptions {
        width: W,
        height: H,
        supersample: 1,
        ..FrameOptions::default()
    }
}

/// A sphere through the model's centre, sticking out of it, and a tilted rectangle across
/// it: both meet the model's faces along curves.
fn primitives(lo: DVec3, hi: DVec3) -> Vec<AnalyticPrimitive> {
    let centre = 0.5 * (lo + hi);
    let size = (hi - lo).max_element();
    let tilt = DVec3::new(0.3, -0.2, 1.0).normalize();
    let x = tilt.any_orthonormal_vector();
    vec![
        AnalyticPrimitive {
            shape: AnalyticShape::Sphere {
                radius: 0.35 * size,
            },
            frame: Frame {
                origin: centre + DVec3::new(0.25, 0.1, 0.2) * size,
                ..Frame::WORLD
            },
            face_id: SPHERE_ID,
            colour: [0.8, 0.2, 0.1, 1.0],
        },
        AnalyticPrimitive {
            shape: AnalyticShape::Rectangle {
                half_width: 0.6 * size,
                half_height: 0.4 * size,
            },
            frame: Frame {
                origin: centre,
                x,
                y: tilt.cross(x),
                z: tilt,
            },
            face_id: RECTANGLE_ID,
            colour: [0.1, 0.5, 0.8, 1.0],
        },
    ]
}

/// The mixed scene: the fixture's model meshed, the primitives ray cast; the oracle casts
/// both exactly.
struct Mixed {
    scene: RenderScene,
    prepared: PreparedScene,
    caster: RayCaster,
    lo: DVec3,
    hi: DVec3,
    primitives: Vec<AnalyticPrimitive>,
}

impl Mixed {
    /// The STEP id (the oracle's) of the face in visibility texel `g`: the mesh faces' dense
    /// ids looked up in the scene's table, the primitives' own ids as they are.
    fn step_id(&self, g: &[u32; 4]) -> u64 {
        if g[1] == 0 {
            0
        } else if g[1] > self.prepared.primitive_instance(0) {
            u64::from(g[0])
        } else {
            self.scene.face_step_id(g[0])
        }
    }
}

fn mixed(renderer: &Renderer, gpu: &cadre_render::Gpu) -> Mixed {
    // Meshed finely: the comparison is about where the two back-ends meet, not about the
    // mesh's own chords (the golden tests bound those).
    let (model, scene) = model_and_scene_at("dome-and-cone.step", 0.0005);
    let (lo, hi) = scene.bounds().expect("geometry");
    let primitives = primitives(lo, hi);
    let scene = scene.with_primitives(primitives.clone());
    let prepared = renderer.prepare(gpu, &scene);
    let mut caster = RayCaster::new(&model, 0.001);
    assert!(caster.skipped.is_empty(), "{:?}", caster.skipped);
    for p in &primitives {
        caster.add_primitive(p);
    }
    // Frame everything: the model and the primitives' bounding spheres (looser than
    // `RenderScene::bounds` around the tilted rectangle; the golden image is framed so).
    let (lo, hi) = primitives.iter().fold((lo, hi), |(lo, hi), p| {
        let (c, r) = p.bounding_sphere();
        (lo.min(c - r), hi.max(c + r))
    });
    Mixed {
        scene,
        prepared,
        caster,
        lo,
        hi,
        primitives,
    }
}

/// Fraction of the pixels either side covers where the GPU's face id is the oracle's, and
/// how many pixels show each primitive.
fn agreement(
    gpu: &cadre_render::Gpu,
    renderer: &Renderer,
    mixed: &Mixed,
    camera: &Camera,
) -> (f64, [usize; 2]) {
    let ids = renderer
        .render_ids(
            gpu,
            &mixed.prepared,
            camera,
            &options(),
            &ViewState::default(),
        )
        .expect("ids");
    let exact = mixed.caster.face_ids(camera, W, H);
    let (mut covered, mut same) = (0usize, 0usize);
    let mut shown = [0usize; 2];
    for (g, e) in ids.iter().zip(&exact) {
        if g[1] == 0 && *e == 0 {
            continue;
        }
        covered += 1;
        same += usize::from(mixed.step_id(g) == *e && g[1] != 0);
        for (k, id) in [SPHERE_ID, RECTANGLE_ID].into_iter().enumerate() {
            if g[0] == id {
                shown[k] += 1;
                // The primitive's instance comes after the meshes'.
                assert_eq!(g[1] - 1, mixed.prepared.primitive_instance(k));
            }
        }
    }
    (same as f64 / covered.max(1) as f64, shown)
}

fn cameras(mixed: &Mixed) -> Vec<Camera> {
    let aspect = f64::from(W) / f64::from(H);
    let mut out = Vec::new();
    for view in [ViewPreset::Iso, ViewPreset::Top, ViewPreset::Front] {
        out.push(Camera::fit(mixed.lo, mixed.hi, view, false, aspect));
    }
    out.push(Camera::fit(
        mixed.lo,
        mixed.hi,
        ViewPreset::Iso,
        true,
        aspect,
    ));
    out
}

#[test]
fn ray_cast_and_meshed_surfaces_meet_where_the_exact_ray_caster_says() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let mixed = mixed(&renderer, &gpu);
    for camera in cameras(&mixed) {
        let (a, shown) = agreement(&gpu, &renderer, &mixed, &camera);
        eprintln!(
            "{:?} {:?}: {:.3} % agree; sphere {} px, rectangle {} px",
            camera.projection,
            camera.eye,
            100.0 * a,
            shown[0],
            shown[1]
        );
        assert!(shown[0] > 500 && shown[1] > 100, "{shown:?}");
        assert!(a >= 0.999, "{:.3} % of covered pixels agree", 100.0 * a);
    }
}

#[test]
fn a_wrong_ray_cast_depth_is_caught() {
    // Negative control: the back-end writing its proxies' depth (the sphere's bounding cube,
    // nearer than the sphere almost everywhere) wins against the meshed faces in front of
    // the sphere, and the comparison must see it.
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines").with_proxy_depth();
    let mixed = mixed(&renderer, &gpu);
    let worst = cameras(&mixed)
        .iter()
        .map(|c| agreement(&gpu, &renderer, &mixed, c).0)
        .fold(1.0, f64::min);
    eprintln!("proxy depth: worst view {:.3} % agree", 100.0 * worst);
    assert!(
        worst < 0.99,
        "a proxy depth agreed on {:.3} %",
        100.0 * worst
    );
}

#[test]
fn the_hit_gives_the_sphere_its_exact_parameters() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let mixed = mixed(&renderer, &gpu);
    let camera = &cameras(&mixed)[0];
    let ids = renderer
        .render_ids(
            &gpu,
            &mixed.prepared,
            camera,
            &options(),
            &ViewState::default(),
        )
        .expect("ids");
    let uv = renderer
        .render_uv(
            &gpu,
            &mixed.prepared,
            camera,
            &options(),
            &ViewState::default(),
        )
        .expect("uv");
    let hits = mixed.caster.hits(camera, W, H);
    let sphere = &mixed.primitives[0];
    let AnalyticShape::Sphere { radius } = sphere.shape else {
        unreachable!()
    };
    let tau = std::f64::consts::TAU;
    let mut checked = 0;
    for ((g, uv), hit) in ids.iter().zip(&uv).zip(&hits) {
        let Some((id, p)) = hit else { continue };
        if g[0] != SPHERE_ID || *id != u64::from(SPHERE_ID) {
            continue;
        }
        let q = *p - sphere.frame.origin;
        let u = q.y.atan2(q.x).rem_euclid(tau);
        let v = (q.z / radius).clamp(-1.0, 1.0).asin();
        // Longitude compared around the seam.
        let du = (f64::from(uv[0]) - u).rem_euclid(tau);
        let du = du.min(tau - du);
        let dv = (f64::from(uv[1]) - v).abs();
        assert!(du < 1e-2 && dv < 1e-2, "({u}, {v}) vs {uv:?}");
        checked += 1;
    }
    assert!(checked > 500, "{checked} sphere pixels checked");
}

#[test]
fn a_section_plane_cuts_the_ray_cast_sphere_and_caps_it() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let mixed = mixed(&renderer, &gpu);
    let camera = &cameras(&mixed)[0];
    let sphere = mixed.primitives[0].frame.origin;
    // Cut away the half of the sphere facing the camera: its inside shows as a cap.
    let towards_eye = (camera.eye - sphere).normalize();
    let state = ViewState {
        sections: vec![SectionPlane::through(sphere, towards_eye)],
        ..ViewState::default()
    };
    let ids = renderer
        .render_ids(&gpu, &mixed.prepared, camera, &options(), &state)
        .expect("ids");
    let instance = mixed.prepared.primitive_instance(0) + 1;
    let caps = ids
        .iter()
        .filter(|g| g[1] == instance && g[2] & SECTION_CAP != 0)
        .count();
    assert!(caps > 300, "{caps} cap pixels of the sphere");
    // The open rectangle is cut, never capped.
    let rectangle = mixed.prepared.primitive_instance(1) + 1;
    assert!(
        !ids.iter()
            .any(|g| g[1] == rectangle && g[2] & SECTION_CAP != 0)
    );
}

#[test]
fn the_mixed_scene_is_shaded_outlined_and_edged_like_any_other() {
    // Golden image: the ray-cast sphere and rectangle lit by the shade pass, outlined where
    // their depth jumps, the meshed model's B-Rep edges hidden behind them by the shared
    // depth; `CADRE_BLESS=1` rewrites it.
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let mixed = mixed(&renderer, &gpu);
    let camera = &cameras(&mixed)[0];
    let image = renderer
        .render(
            &gpu,
            &mixed.prepared,
            camera,
            &FrameOptions {
                supersample: 2,
                ..common::shaded_edges(W, H)
            },
            &ViewState::default(),
        )
        .expect("image");
    common::check_golden("analytic-mixed.png", &image);
}
