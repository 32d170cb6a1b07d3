//! The see-through phases answered by every surface back-end: a ray-cast sphere in x-ray
//! mode is blended like a meshed part (both its layers, once each), and a see-through sphere
//! of an opaque view is blended over the shaded image, hidden behind the opaque depth and
//! left out of the visibility buffer, as see-through meshes are.

mod common;

use cadre_geom::Frame;
use cadre_render::{
    AnalyticPrimitive, AnalyticShape, Camera, DisplayMode, FrameOptions, InstanceStyle,
    RenderScene, Renderer, ViewPreset, ViewState,
};
use common::{gpu, scene};
use glam::DVec3;

const W: u32 = 96;
const H: u32 = 72;

fn options(mode: DisplayMode) -> FrameOptions {
    FrameOptions {
        width: W,
        height: H,
        supersample: 1,
        mode,
        background: [1.0; 4],
        ..FrameOptions::default()
    }
}

fn sphere(origin: DVec3, radius: f64, colour: [f32; 4]) -> AnalyticPrimitive {
    AnalyticPrimitive {
        shape: AnalyticShape::Sphere { radius },
        frame: Frame {
            origin,
            ..Frame::WORLD
        },
        face_id: 7,
        colour,
    }
}

/// sRGB byte → linear.
fn linear(byte: u8) -> f64 {
    let c = f64::from(byte) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// `layers` x-ray layers of a surface seen face-on (`xray_colour`: the base colour, opacity
/// 0.06) blended over a white background, in linear light.
fn face_on_layers(base: f64, layers: u32) -> f64 {
    (0..layers).fold(1.0, |under, _| base * 0.06 + under * 0.94)
}

#[test]
fn x_ray_blends_a_ray_cast_sphere_once_per_layer() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let base = [0.2f32, 0.5, 0.05, 1.0];
    let scene = RenderScene::default().with_primitives(vec![sphere(DVec3::ZERO, 1.0, base)]);
    let (lo, hi) = scene.bounds().expect("the sphere");
    let camera = Camera::fit(lo, hi, ViewPreset::Front, true, f64::from(W) / f64::from(H));
    let prepared = renderer.prepare(&gpu, &scene);
    let state = ViewState::default();
    let image = renderer
        .render(
            &gpu,
            &prepared,
            &camera,
            &options(DisplayMode::XRay),
            &state,
        )
        .expect("x-ray");
    // At the centre both layers face the eye: two blends of the base colour over white.
    let centre = image.get_pixel(W / 2, H / 2).0;
    for c in 0..3 {
        let got = linear(centre[c]);
        let two = face_on_layers(f64::from(base[c]), 2);
        assert!(
            (got - two).abs() < 0.01,
            "channel {c}: {got:.4}, two layers give {two:.4}"
        );
        // Negative control: the tolerance tells two layers from one and from four (a cube
        // proxy's both sides each blending).
        for wrong in [1, 4] {
            assert!((face_on_layers(f64::from(base[c]), wrong) - two).abs() > 0.01);
        }
    }
    // Near the rim the sphere is seen edge-on: more opaque, darker than at the centre.
    let edge = (W / 2..W)
        .take_while(|&x| image.get_pixel(x, H / 2).0 != [255, 255, 255, 255])
        .last()
        .expect("the sphere covers the centre");
    assert!(
        edge > W / 2 + 10,
        "the sphere is {} pixels wide",
        2 * (edge - W / 2)
    );
    let rim = image.get_pixel(edge - 1, H / 2).0;
    assert!(linear(rim[1]) < linear(centre[1]), "{rim:?} vs {centre:?}");
    // Hidden, it is not drawn: the background everywhere.
    let hidden = ViewState {
        instances: vec![InstanceStyle {
            visible: false,
            colour: None,
        }],
        ..ViewState::default()
    };
    let nothing = renderer
        .render(
            &gpu,
            &prepared,
            &camera,
            &options(DisplayMode::XRay),
            &hidden,
        )
        .expect("x-ray");
    assert!(nothing.pixels().all(|p| p.0 == [255, 255, 255, 255]));
}

#[test]
fn a_see_through_sphere_is_blended_behind_the_opaque_depth() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let pins = scene("pin-assembly.step");
    let (lo, hi) = pins.bounds().expect("geometry");
    // A sphere around the first pin's end, half in front of the model and half inside it.
    let radius = 0.2 * (hi - lo).max_element();
    let scene = pins.with_primitives(vec![sphere(0.5 * (lo + hi), radius, [0.9, 0.1, 0.1, 1.0])]);
    let prepared = renderer.prepare(&gpu, &scene);
    let sphere_instance = prepared.primitive_instance(0) as usize;
    let (lo, hi) = scene.bounds().expect("geometry");
    let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, f64::from(W) / f64::from(H));
    let styled = |style: InstanceStyle| {
        let mut instances = vec![InstanceStyle::default(); sphere_instance + 1];
        instances[sphere_instance] = style;
        ViewState {
            instances,
            ..ViewState::default()
        }
    };
    let opaque = styled(InstanceStyle::default());
    let see_through = styled(InstanceStyle {
        visible: true,
        colour: Some([0.9, 0.1, 0.1, 0.4]),
    });
    let hidden = styled(InstanceStyle {
        visible: false,
        colour: None,
    });
    let shaded = options(DisplayMode::Shaded);
    let ids = |state: &ViewState| {
        renderer
            .render_ids(&gpu, &prepared, &camera, &shaded, state)
            .expect("ids")
    };
    let image = |state: &ViewState| {
        renderer
            .render(&gpu, &prepared, &camera, &shaded, state)
            .expect("image")
    };
    // Where the opaque sphere is the nearest surface.
    let on_sphere: Vec<usize> = ids(&opaque)
        .iter()
        .enumerate()
        .filter(|(_, g)| g[1] as usize == sphere_instance + 1)
        .map(|(i, _)| i)
        .collect();
    assert!(on_sphere.len() > 200, "{} sphere pixels", on_sphere.len());
    // See-through, it is not in the visibility buffer: what is behind it is.
    let behind = ids(&see_through);
    assert!(behind.iter().all(|g| g[1] as usize != sphere_instance + 1));
    assert_eq!(behind, ids(&hidden));
    // It is blended: its pixels are neither the opaque sphere's nor those without it.
    let (with, without, solid) = (image(&see_through), image(&hidden), image(&opaque));
    let differs = |a: &image::RgbaImage, b: &image::RgbaImage, i: usize| {
        let (x, y) = (i as u32 % W, i as u32 / W);
        let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
        (0..3).any(|c| p[c].abs_diff(q[c]) > 8)
    };
    let blended = on_sphere
        .iter()
        .filter(|&&i| differs(&with, &without, i) && differs(&with, &solid, i))
        .count();
    assert!(
        blended * 10 >= on_sphere.len() * 9,
        "{blended} of {} sphere pixels blended",
        on_sphere.len()
    );
    // Behind the opaque model it does not show: where the model is nearer than the sphere
    // (their depths drawn apart; reverse Z, nearer is larger), the see-through image is the
    // one without it.
    let mut alone = vec![
        InstanceStyle {
            visible: false,
            colour: None,
        };
        sphere_instance + 1
    ];
    alone[sphere_instance] = InstanceStyle::default();
    let sphere_alone = ids(&ViewState {
        instances: alone,
        ..ViewState::default()
    });
    let model_alone = ids(&hidden);
    let depth = |g: &[u32; 4]| f32::from_bits(g[3]);
    let covered: Vec<usize> = (0..model_alone.len())
        .filter(|&i| {
            sphere_alone[i][1] != 0
                && model_alone[i][1] != 0
                && depth(&model_alone[i]) > depth(&sphere_alone[i]) * 1.001
        })
        .collect();
    assert!(
        covered.len() > 20,
        "{} pixels of sphere behind the model",
        covered.len()
    );
    let leaked = covered
        .iter()
        .filter(|&&i| differs(&with, &without, i))
        .count();
    assert!(
        leaked * 20 <= covered.len(),
        "{leaked} of {} pixels show the sphere through the model",
        covered.len()
    );
}
