//! Backgrounds and the ground grid (issue 19 item 4): a gradient runs from its top colour to
//! its bottom one, an image is stretched over the view, the grid's lines land where the
//! plane's coordinates are multiples of the spacing (seen from above, one unit a pixel), its
//! adaptive spacing keeps lines a few pixels apart at any zoom, and a surface in front hides
//! it. Negative controls: no grid, no lines; a grid under the surface does not show through.

mod common;

use std::sync::Arc;

use cadre_render::{
    Background, Camera, FrameOptions, GroundGrid, Projection, RenderScene, Renderer, ViewState,
};
use common::gpu;
use glam::DVec3;
use image::RgbaImage;

fn top_view(height: f64) -> Camera {
    Camera {
        eye: DVec3::new(0.0, 0.0, 50.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height },
        near: 1.0,
        far: 200.0,
    }
}

fn render(scene: &RenderScene, camera: &Camera, options: &FrameOptions) -> RgbaImage {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let prepared = renderer.prepare(&gpu, scene);
    renderer
        .render(&gpu, &prepared, camera, options, &ViewState::default())
        .expect("image")
}

fn options() -> FrameOptions {
    FrameOptions {
        width: 100,
        height: 100,
        supersample: 1,
        ..FrameOptions::default()
    }
}

#[test]
fn a_gradient_runs_from_top_to_bottom_and_an_image_fills_the_view() {
    let gradient = FrameOptions {
        backdrop: Background::Gradient {
            top: [1.0, 0.0, 0.0, 1.0],
            bottom: [0.0, 0.0, 1.0, 1.0],
        },
        ..options()
    };
    let image = render(&RenderScene::default(), &top_view(100.0), &gradient);
    let (top, bottom) = (image.get_pixel(50, 0), image.get_pixel(50, 99));
    assert!(top[0] > 240 && top[2] < 40, "{top:?}");
    assert!(bottom[2] > 240 && bottom[0] < 40, "{bottom:?}");
    let middle = image.get_pixel(50, 50);
    assert!(middle[0] > 100 && middle[2] > 100, "{middle:?}");
    // A 2 × 2 image: each quarter of the view its texel's colour.
    let mut texels = RgbaImage::new(2, 2);
    texels.put_pixel(0, 0, image::Rgba([255, 0, 0, 255]));
    texels.put_pixel(1, 0, image::Rgba([0, 255, 0, 255]));
    texels.put_pixel(0, 1, image::Rgba([0, 0, 255, 255]));
    texels.put_pixel(1, 1, image::Rgba([255, 255, 0, 255]));
    let pictured = FrameOptions {
        backdrop: Background::Image(Arc::new(texels)),
        ..options()
    };
    let image = render(&RenderScene::default(), &top_view(100.0), &pictured);
    assert_eq!(image.get_pixel(5, 5).0, [255, 0, 0, 255]);
    assert_eq!(image.get_pixel(94, 5).0, [0, 255, 0, 255]);
    assert_eq!(image.get_pixel(5, 94).0, [0, 0, 255, 255]);
    assert_eq!(image.get_pixel(94, 94).0, [255, 255, 0, 255]);
}

/// The columns of row `y` darker than the white background.
fn dark_columns(image: &RgbaImage, y: u32) -> Vec<u32> {
    darker_columns(image, y, 200)
}

/// The columns of row `y` darker than `level`.
fn darker_columns(image: &RgbaImage, y: u32, level: u8) -> Vec<u32> {
    (0..image.width())
        .filter(|x| image.get_pixel(*x, y)[0] < level)
        .collect()
}

#[test]
fn grid_lines_land_on_multiples_of_the_spacing_and_surfaces_hide_them() {
    let grid = GroundGrid {
        height: Some(0.0),
        spacing: Some(10.0),
        colour: [0.0, 0.0, 0.0, 1.0],
        axes: false,
    };
    let with_grid = FrameOptions {
        grid: Some(grid),
        ..options()
    };
    // Seen from above, 100 units over 100 pixels: x = −50 at column 0.
    let image = render(&RenderScene::default(), &top_view(100.0), &with_grid);
    let columns = dark_columns(&image, 25);
    eprintln!("grid columns {columns:?}");
    // Lines at x = −40, −30, …, 40 → pixel edges 10, 20, … 90: each darkens the two columns
    // beside its edge.
    for x in (10..=90).step_by(10) {
        assert!(
            columns.contains(&(x - 1)) && columns.contains(&x),
            "line at column {x}: {columns:?}"
        );
    }
    assert!(columns.len() <= 2 * 9 + 2, "{columns:?}");
    // Negative control: without the grid, nothing.
    let plain = render(&RenderScene::default(), &top_view(100.0), &options());
    assert!(dark_columns(&plain, 25).is_empty());
    // A grid below a surface does not show through it.
    let below = FrameOptions {
        grid: Some(GroundGrid {
            height: Some(-5.0),
            ..grid
        }),
        ..options()
    };
    let plate = cadre_render::AnalyticPrimitive {
        shape: cadre_render::AnalyticShape::Quadric(
            cadre_render::QuadricShape::new(cadre_geom::CutQuadric {
                quadric: cadre_geom::Quadric::cylinder(30.0),
                planes: vec![
                    cadre_geom::HalfSpace::through(DVec3::ZERO, DVec3::Z),
                    cadre_geom::HalfSpace::through(DVec3::new(0.0, 0.0, -1.0), -DVec3::Z),
                ],
                kind: cadre_geom::CutKind::Volume,
            })
            .expect("bounded"),
        ),
        frame: cadre_geom::Frame::WORLD,
        face_id: 1,
        colour: [1.0, 1.0, 1.0, 1.0],
    };
    let scene = RenderScene::default().with_primitives(vec![plate]);
    let image = render(&scene, &top_view(100.0), &below);
    // Row 50 crosses the disc (radius 30: columns 20–80) in the middle.
    let columns = dark_columns(&image, 50);
    assert!(columns.iter().all(|c| !(25..75).contains(c)), "{columns:?}");
    assert!(columns.iter().any(|c| *c < 20), "{columns:?}");
}

#[test]
fn the_adaptive_grid_keeps_its_lines_a_few_pixels_apart_at_any_zoom() {
    let grid = GroundGrid {
        height: Some(0.0),
        colour: [0.0, 0.0, 0.0, 1.0],
        axes: false,
        ..GroundGrid::default()
    };
    let with_grid = FrameOptions {
        grid: Some(grid),
        ..options()
    };
    for view in [1.0, 37.0, 100.0, 2500.0, 1e5] {
        let image = render(&RenderScene::default(), &top_view(view), &with_grid);
        // Lines drawn (the finest faint), at least the major ones every few pixels, but
        // never a solid fill.
        let lines = darker_columns(&image, 25, 250);
        let strong = darker_columns(&image, 25, 200);
        eprintln!(
            "view {view}: {} columns with lines, {} strong",
            lines.len(),
            strong.len()
        );
        let widest = lines
            .windows(2)
            .map(|w| w[1] - w[0])
            .chain([
                lines.first().copied().unwrap_or(100),
                100 - lines.last().copied().unwrap_or(0),
            ])
            .max()
            .unwrap_or(100);
        // Once the finest level fades out (its lines under ~3 pixels apart) the next one's
        // are under 100 pixels apart: some line in every 100 columns.
        assert!(widest <= 60, "{view}: {lines:?}");
        assert!(lines.len() <= 70, "{view}: {lines:?}");
        assert!(!strong.is_empty(), "{view}");
    }
}
