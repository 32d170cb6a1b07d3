//! The lines pass (issue 19): the GPU segmented scan of the screen arc length against the
//! `f64` reference (a 100,000-segment spiral of sub-pixel segments, thousands of short
//! polylines across scan blocks, a polyline through the near plane), dash ends against the
//! reference on screen, joins, caps, widths, hidden parts, the travel shown and the clip box,
//! and a golden image. Seen orthographically, one model unit is one pixel.

mod common;

use cadre_render::lines::reference;
use cadre_render::{
    Camera, Cap, FrameOptions, Hidden, Join, LineSet, LineStyle, LineView, LineWidth, Polyline,
    Projection, RenderScene, Renderer, Stipple, ViewState,
};
use common::{check_golden, gpu};
use glam::DVec3;
use image::RgbaImage;

/// Looking down −z at the origin, `height` model units high (orthographic).
fn ortho(height: f64) -> Camera {
    Camera {
        eye: DVec3::new(0.0, 0.0, 50.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height },
        near: 1.0,
        far: 100.0,
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

/// A solid black line style of `width` pixels.
fn black(width: f32) -> LineStyle {
    LineStyle {
        width: LineWidth::Pixels(width),
        ..LineStyle::default()
    }
}

fn render(set: LineSet, camera: &Camera, size: (u32, u32), view: LineView) -> RgbaImage {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let prepared = renderer.prepare(&gpu, &RenderScene::default().with_lines(set));
    let state = ViewState {
        lines: view,
        ..ViewState::default()
    };
    renderer
        .render(&gpu, &prepared, camera, &options(size.0, size.1), &state)
        .expect("image")
}

/// The coverage of black on white at a pixel: 1 − its linear luminance.
fn coverage(image: &RgbaImage, x: u32, y: u32) -> f64 {
    let c = f64::from(image.get_pixel(x, y)[1]) / 255.0;
    let linear = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    1.0 - linear
}

/// The pixels darker than mid-grey.
fn dark_pixels(image: &RgbaImage) -> usize {
    image.pixels().filter(|p| p[1] < 128).count()
}

fn polyline(points: &[(f64, f64)], style: u32) -> Polyline {
    Polyline {
        points: points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect(),
        style,
        colours: Vec::new(),
    }
}

/// A spiral of `n` segments from radius 5 to 45 over `turns` turns (40: segments of ≈ 0.07
/// pixel at 100,000).
fn spiral(n: usize, turns: f64) -> Polyline {
    let points = (0..=n)
        .map(|k| {
            let f = k as f64 / n as f64;
            let angle = f * turns * std::f64::consts::TAU;
            let r = 5.0 + 40.0 * f;
            DVec3::new(r * angle.cos(), r * angle.sin(), 0.0)
        })
        .collect();
    Polyline {
        points,
        ..Polyline::default()
    }
}

#[test]
fn the_gpu_scan_matches_the_f64_arc_lengths() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let mut polylines = vec![spiral(100_000, 40.0)];
    // 3,000 short zigzags: many polyline starts in every scan block, and single points.
    for k in 0..3000 {
        let x = -45.0 + (k % 60) as f64 * 1.5;
        let y = -45.0 + (k / 60) as f64 * 1.8;
        let n = 1 + k % 7;
        polylines.push(Polyline {
            points: (0..n)
                .map(|j| DVec3::new(x + 0.3 * j as f64, y + 0.7 * (j % 2) as f64, 0.2))
                .collect(),
            ..Polyline::default()
        });
    }
    let set = LineSet {
        polylines,
        styles: vec![],
    };
    let size = (200, 160);
    let prepared = renderer.prepare(&gpu, &RenderScene::default().with_lines(set.clone()));
    let perspective = Camera {
        eye: DVec3::new(0.0, -30.0, 60.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
        projection: Projection::Perspective { fov_y: 0.8 },
        near: 0.5,
        far: 500.0,
    };
    for camera in [ortho(100.0), perspective] {
        let gpu_arc = renderer
            .line_arc_lengths(&gpu, &prepared, &camera, size)
            .expect("scan");
        let cpu_arc = reference::arc_lengths(&set, &camera, size);
        assert_eq!(gpu_arc.len(), cpu_arc.len());
        let worst = gpu_arc
            .iter()
            .zip(&cpu_arc)
            .map(|(g, c)| (f64::from(*g) - c).abs())
            .fold(0.0, f64::max);
        let total = cpu_arc[100_000];
        eprintln!("spiral {total:.1} px on screen; worst |GPU − f64| {worst:.2e} px");
        assert!(total > 5000.0, "{total}");
        assert!(worst < 0.05, "{worst}");
        // Negative control: the reference for a view 1 % larger is told apart.
        let mut zoomed = camera;
        zoomed.projection = match camera.projection {
            Projection::Orthographic { height } => Projection::Orthographic {
                height: 0.99 * height,
            },
            Projection::Perspective { fov_y } => Projection::Perspective {
                fov_y: 0.99 * fov_y,
            },
        };
        let other = reference::arc_lengths(&set, &zoomed, size);
        let off = gpu_arc
            .iter()
            .zip(&other)
            .map(|(g, c)| (f64::from(*g) - c).abs())
            .fold(0.0, f64::max);
        assert!(off > 0.5, "{off}");
    }
}

#[test]
fn a_polyline_through_the_eye_is_measured_and_drawn_in_front_of_it() {
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let camera = Camera {
        eye: DVec3::new(0.0, -20.0, 0.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
        projection: Projection::Perspective { fov_y: 1.0 },
        near: 0.5,
        far: 200.0,
    };
    // From in front of the eye to behind it and back, below the view axis.
    let set = LineSet {
        polylines: vec![Polyline {
            points: vec![
                DVec3::new(-5.0, 10.0, -2.0),
                DVec3::new(0.0, -40.0, -2.0),
                DVec3::new(5.0, 10.0, -2.0),
            ],
            ..Polyline::default()
        }],
        styles: vec![black(3.0)],
    };
    let size = (120, 90);
    let prepared = renderer.prepare(&gpu, &RenderScene::default().with_lines(set.clone()));
    let gpu_arc = renderer
        .line_arc_lengths(&gpu, &prepared, &camera, size)
        .expect("scan");
    let cpu_arc = reference::arc_lengths(&set, &camera, size);
    eprintln!("through the eye: GPU {gpu_arc:?}, f64 {cpu_arc:?}");
    assert!(cpu_arc.iter().all(|s| s.is_finite()));
    for (g, c) in gpu_arc.iter().zip(&cpu_arc) {
        assert!((f64::from(*g) - c).abs() < 0.05 * c.max(1.0), "{g} vs {c}");
    }
    let image = renderer
        .render(
            &gpu,
            &prepared,
            &camera,
            &options(size.0, size.1),
            &ViewState::default(),
        )
        .expect("image");
    let dark = dark_pixels(&image);
    eprintln!("{dark} pixels drawn");
    assert!(dark > 100, "the parts in front are drawn: {dark}");
}

/// Where the coverage along row `y` crosses ½ between columns, by linear interpolation:
/// each dash end seen on screen, in pixels.
fn crossings(image: &RgbaImage, y: u32) -> Vec<f64> {
    let mut out = Vec::new();
    for x in 0..image.width() - 1 {
        let (a, b) = (coverage(image, x, y), coverage(image, x + 1, y));
        if (a - 0.5) * (b - 0.5) < 0.0 {
            out.push(f64::from(x) + 0.5 + (0.5 - a) / (b - a));
        }
    }
    out
}

/// The fewest bits in a run of equal bits of a 16-bit pattern, read cyclically.
fn shortest_run(pattern: u16) -> u32 {
    let bit = |k: u32| pattern >> (k % 16) & 1;
    let starts: Vec<u32> = (0..16).filter(|k| bit(*k) != bit(k + 15)).collect();
    if starts.is_empty() {
        return 16;
    }
    starts
        .iter()
        .zip(starts.iter().cycle().skip(1))
        .map(|(a, b)| (b + 16 - a - 1) % 16 + 1)
        .min()
        .unwrap_or(16)
}

#[test]
fn dash_ends_land_within_half_a_pixel_of_the_reference() {
    // A horizontal polyline from x = −93.3 to 93.3 in joints every 7.3 pixels (dashes run
    // across them), one row per preset × factor; its screen arc length is x + 93.3 + 100.
    let width = 200u32;
    let mut worst = 0.0f64;
    let mut worst_coverage = 0.0f64;
    let mut shifted_worst = 0.0f64;
    let mut checked = 0;
    for (name, _) in Stipple::PRESETS.iter().skip(1) {
        let mut rows = Vec::new();
        let mut styles = Vec::new();
        for (row, factor) in [1u32, 2, 4].into_iter().enumerate() {
            let stipple = Stipple::parse(name, factor).expect("preset");
            let y = 10.0 - 10.0 * row as f64;
            let xs: Vec<(f64, f64)> = (0..=26)
                .map(|k| (-93.3 + 7.3 * f64::from(k as u8), y + 0.5))
                .map(|(x, y): (f64, f64)| (x.min(93.3), y))
                .collect();
            rows.push(polyline(&xs, row as u32));
            styles.push(LineStyle {
                stipple,
                ..black(4.0)
            });
        }
        let image = render(
            LineSet {
                polylines: rows,
                styles,
            },
            &ortho(40.0),
            (width, 40),
            LineView::default(),
        );
        for (row, factor) in [1u32, 2, 4].into_iter().enumerate() {
            let stipple = Stipple::parse(name, factor).expect("preset");
            // Row 0 at y = 10.5 (model) → pixel row 9; then 19, 29.
            let pixel_row = 9 + 10 * row as u32;
            let start = 100.0 - 93.3;
            let expected: Vec<f64> = reference::dash_ends(stipple, 186.6)
                .into_iter()
                .map(|s| start + s)
                .filter(|x| (x - start).abs() > 1.0 && (x - (start + 186.6)).abs() > 1.0)
                .collect();
            // The pixels' coverage is the pattern's box filter: each pixel's share of drawn
            // arc length, integrated in f64 (for every factor, also where bits are a pixel).
            for x in 3..width - 3 {
                let samples = 400;
                let want = (0..samples)
                    .filter(|k| {
                        let s = f64::from(x) + (f64::from(*k) + 0.5) / f64::from(samples) - start;
                        (0.0..=186.6).contains(&s) && stipple.drawn_at(s)
                    })
                    .count() as f64
                    / f64::from(samples);
                let got = coverage(&image, x, pixel_row);
                if (got - want).abs() > worst_coverage {
                    eprintln!("{name} ×{factor} x {x}: {got:.3} vs {want:.3}");
                }
                worst_coverage = worst_coverage.max((got - want).abs());
            }
            // Dash ends where the runs are wider than a pixel: where the coverage crosses ½.
            if shortest_run(stipple.pattern) * factor < 2 {
                continue;
            }
            let seen = crossings(&image, pixel_row);
            // Every dash end is seen once, and nothing else (the line's own two ends aside).
            let inner: Vec<f64> = seen
                .iter()
                .copied()
                .filter(|x| (x - start).abs() > 1.0 && (x - (start + 186.6)).abs() > 1.0)
                .collect();
            assert_eq!(
                inner.len(),
                expected.len(),
                "{name} ×{factor}: {inner:?} vs {expected:?}"
            );
            for (a, b) in inner.iter().zip(&expected) {
                worst = worst.max((a - b).abs());
                checked += 1;
            }
            // Negative control: the dash ends of the pattern started one pixel later are
            // told apart.
            for (a, b) in inner.iter().zip(&expected) {
                shifted_worst = shifted_worst.max((a - (b + 1.0)).abs());
            }
        }
    }
    assert!(shifted_worst > 0.5, "{shifted_worst}");
    eprintln!(
        "{checked} dash ends, worst {worst:.3} px from the f64 reference; \
         worst pixel coverage {worst_coverage:.3} from the pattern's box filter"
    );
    assert!(checked > 100 && worst <= 0.5, "{worst}");
    assert!(worst_coverage < 0.05, "{worst_coverage}");
}

/// Dark pixels of a V with a 60° turn at the origin, 14 pixels wide, joined by `join`.
fn v_join(join: Join) -> usize {
    let style = LineStyle {
        join,
        ..black(14.0)
    };
    let v = polyline(&[(-30.0, -25.0), (0.0, 27.0), (30.0, -25.0)], 0);
    dark_pixels(&render(
        LineSet {
            polylines: vec![v],
            styles: vec![style],
        },
        &ortho(100.0),
        (100, 100),
        LineView::default(),
    ))
}

#[test]
fn joins_fill_the_outer_corner_as_asked() {
    let miter = v_join(Join::Miter { limit: 4.0 });
    let round = v_join(Join::Round);
    let bevel = v_join(Join::Bevel);
    // Past its limit (the 60° turn's miter is 2 half widths) a miter is a bevel.
    let limited = v_join(Join::Miter { limit: 1.5 });
    eprintln!("miter {miter}, round {round}, bevel {bevel}, limited miter {limited}");
    assert!(miter > round && round > bevel, "{miter} {round} {bevel}");
    assert!(limited.abs_diff(bevel) <= 2, "{limited} vs {bevel}");
    // The legs meet at 60°: the turn is 120°. Beyond the bevel's cut (hw cos 60° from the
    // joint), the miter adds the triangle up to its point (2 hw from the joint) and the
    // round join the disc's segment of half-angle 60°.
    let hw = 7.0f64;
    let chord = 2.0 * hw * 60f64.to_radians().sin();
    let tip = 0.5 * chord * (2.0 * hw - 0.5 * hw);
    let segment = 0.5 * hw * hw * (120f64.to_radians() - 120f64.to_radians().sin());
    eprintln!("tip {tip:.1}, segment {segment:.1}");
    let near = |got: usize, want: f64| (got as f64 - want).abs() < 0.15 * want + 3.0;
    assert!(near(miter - bevel, tip), "{} vs {tip}", miter - bevel);
    assert!(
        near(round - bevel, segment),
        "{} vs {segment}",
        round - bevel
    );
}

/// Dark pixels of a horizontal 14-pixel line 60 long with `cap`.
fn capped(cap: Cap) -> usize {
    let style = LineStyle { cap, ..black(14.0) };
    dark_pixels(&render(
        LineSet {
            polylines: vec![polyline(&[(-30.0, 0.0), (30.0, 0.0)], 0)],
            styles: vec![style],
        },
        &ortho(100.0),
        (100, 100),
        LineView::default(),
    ))
}

#[test]
fn caps_reach_past_the_ends_as_asked() {
    let butt = capped(Cap::Butt) as f64;
    let square = capped(Cap::Square) as f64;
    let round = capped(Cap::Round) as f64;
    eprintln!("butt {butt}, square {square}, round {round}");
    assert!((butt - 60.0 * 14.0).abs() < 30.0, "{butt}");
    // Two half squares and two half discs of radius 7.
    assert!((square - butt - 2.0 * 7.0 * 14.0).abs() < 20.0, "{square}");
    assert!(
        (round - butt - std::f64::consts::PI * 49.0).abs() < 20.0,
        "{round}"
    );
}

#[test]
fn a_polyline_of_many_collinear_pieces_has_no_seams() {
    // Joints at fractional pixels along a 5-pixel line: every pixel of its middle row is
    // fully covered once (no gap, and no fringe drawn twice at a joint: the rows beside it
    // are the same all along).
    let xs: Vec<(f64, f64)> = (0..40)
        .map(|k| (-40.0 + 2.13 * f64::from(k as u8), 0.5))
        .collect();
    let image = render(
        LineSet {
            polylines: vec![polyline(&xs, 0)],
            styles: vec![black(5.0)],
        },
        &ortho(40.0),
        (100, 40),
        LineView::default(),
    );
    let row = |y: u32| {
        (15..85)
            .map(|x| image.get_pixel(x, y)[1])
            .collect::<Vec<_>>()
    };
    let middle = row(19);
    assert!(middle.iter().all(|v| *v < 10), "{middle:?}");
    let above = row(17);
    assert!(above.iter().all(|v| v.abs_diff(above[0]) <= 2), "{above:?}");
}

/// The summed coverage of an image (black on white): a line's area in pixels.
fn area(image: &RgbaImage) -> f64 {
    let (w, h) = image.dimensions();
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| coverage(image, x, y))
        .sum()
}

#[test]
fn a_model_unit_width_scales_with_the_view_and_keeps_a_pixel() {
    let style = LineStyle {
        width: LineWidth::World(6.0),
        cap: Cap::Butt,
        ..LineStyle::default()
    };
    // A line 60 pixels long in each view, 6 units wide.
    let drawn = |height: f64| {
        let half = 0.3 * height;
        area(&render(
            LineSet {
                polylines: vec![polyline(&[(-half, 0.0), (half, 0.0)], 0)],
                styles: vec![style],
            },
            &ortho(height),
            (100, 100),
            LineView::default(),
        ))
    };
    let (near, far, tiny) = (drawn(100.0), drawn(200.0), drawn(10_000.0));
    eprintln!(
        "6-unit line 60 px long: {near:.1} px² at 1 px/unit, {far:.1} at ½, {tiny:.1} at 1/100"
    );
    assert!((near - 360.0).abs() < 12.0, "{near}");
    assert!((far - 180.0).abs() < 8.0, "{far}");
    // 0.06 pixel wide at this scale: drawn one pixel wide.
    assert!((tiny - 60.0).abs() < 5.0, "{tiny}");
}

#[test]
fn the_travel_shown_and_the_clip_box_cut_the_set() {
    let set = || LineSet {
        polylines: vec![
            polyline(&[(-40.0, 0.0), (0.0, 0.0)], 0),
            polyline(&[(0.0, 10.0), (40.0, 10.0)], 0),
        ],
        styles: vec![black(3.0)],
    };
    assert_eq!(set().travel(), 80.0);
    assert_eq!(
        set().point_at_travel(60.0),
        Some(DVec3::new(20.0, 10.0, 0.0))
    );
    let columns = |image: &RgbaImage, y: u32| {
        (0..100)
            .filter(|x| image.get_pixel(*x, y)[1] < 128)
            .collect::<Vec<u32>>()
    };
    let all = render(set(), &ortho(100.0), (100, 100), LineView::default());
    let half = render(
        set(),
        &ortho(100.0),
        (100, 100),
        LineView {
            up_to: Some(60.0),
            ..LineView::default()
        },
    );
    let boxed = render(
        set(),
        &ortho(100.0),
        (100, 100),
        LineView {
            clip_box: Some((DVec3::new(-20.0, -5.0, -1.0), DVec3::new(30.0, 5.0, 1.0))),
            ..LineView::default()
        },
    );
    // Row 49/50 holds y = 0, row 39/40 y = 10.
    let first = columns(&all, 50);
    let second = columns(&all, 40);
    assert_eq!(
        (first.len(), second.len()),
        (40, 40),
        "{first:?} {second:?}"
    );
    assert_eq!(columns(&half, 50).len(), 40);
    let cut = columns(&half, 40);
    assert_eq!((cut.first(), cut.last()), (Some(&50), Some(&69)), "{cut:?}");
    let clipped = columns(&boxed, 50);
    assert_eq!(
        (clipped.first(), clipped.last()),
        (Some(&30), Some(&49)),
        "{clipped:?}"
    );
    assert!(columns(&boxed, 40).is_empty());
    // A style that does not follow the view (an annotation's) is drawn whole and does not
    // count along the travel: the same cuts leave it alone.
    let mixed = || {
        let mut s = set();
        s.polylines
            .insert(0, polyline(&[(-40.0, -20.0), (40.0, -20.0)], 1));
        s.styles.push(LineStyle {
            follows_view: false,
            ..black(3.0)
        });
        s
    };
    assert_eq!(mixed().travel(), 80.0);
    assert_eq!(
        mixed().point_at_travel(60.0),
        Some(DVec3::new(20.0, 10.0, 0.0))
    );
    let cut_both = LineView {
        up_to: Some(60.0),
        clip_box: Some((DVec3::new(-20.0, -5.0, -1.0), DVec3::new(30.0, 15.0, 1.0))),
    };
    let image = render(mixed(), &ortho(100.0), (100, 100), cut_both);
    // Row 69/70 holds y = −20: all 80 columns; the toolpath's rows are cut as before.
    assert_eq!(columns(&image, 70).len(), 80);
    assert_eq!(columns(&image, 40).len(), 20);
    // Negative control: following the view, the same polyline is cut by the box.
    let mut follows = mixed();
    follows.styles[1].follows_view = true;
    let image = render(follows, &ortho(100.0), (100, 100), cut_both);
    assert!(columns(&image, 70).is_empty());
}

#[test]
fn hidden_parts_are_hidden_shown_or_styled() {
    use cadre_geom::{CutKind, CutQuadric, Frame, Quadric};
    use cadre_render::{AnalyticPrimitive, AnalyticShape, QuadricShape};
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let sphere = AnalyticPrimitive {
        shape: AnalyticShape::Quadric(
            QuadricShape::new(CutQuadric {
                quadric: Quadric::sphere(20.0),
                planes: vec![],
                kind: CutKind::Patch,
            })
            .expect("bounded"),
        ),
        frame: Frame::WORLD,
        face_id: 1,
        colour: [0.9, 0.9, 0.9, 1.0],
    };
    let red = [1.0, 0.0, 0.0, 1.0];
    let count = |hidden: Hidden| {
        // Behind the sphere (z = −30), across it.
        let line = Polyline {
            points: vec![DVec3::new(-45.0, 0.0, -30.0), DVec3::new(45.0, 0.0, -30.0)],
            ..Polyline::default()
        };
        let scene = RenderScene::default()
            .with_primitives(vec![sphere.clone()])
            .with_lines(LineSet {
                polylines: vec![line],
                styles: vec![LineStyle {
                    colour: [0.0, 0.0, 1.0, 1.0],
                    hidden,
                    ..black(3.0)
                }],
            });
        let prepared = renderer.prepare(&gpu, &scene);
        let image = renderer
            .render(
                &gpu,
                &prepared,
                &ortho(100.0),
                &options(100, 100),
                &ViewState::default(),
            )
            .expect("image");
        // Inside the sphere's disc on the line's row.
        let inside = (35..65).map(|x| *image.get_pixel(x, 50));
        let blue = inside.clone().filter(|p| p[2] > 200 && p[0] < 60).count();
        let reds = inside.filter(|p| p[0] > 200 && p[2] < 60).count();
        let outside_blue = (5..25)
            .filter(|x| {
                let p = image.get_pixel(*x, 50);
                p[2] > 200 && p[0] < 60
            })
            .count();
        (blue, reds, outside_blue)
    };
    let hide = count(Hidden::Hide);
    let show = count(Hidden::Show);
    let styled = count(Hidden::Styled {
        colour: red,
        stipple: Stipple::SOLID,
    });
    eprintln!("hide {hide:?}, show {show:?}, styled {styled:?}");
    assert_eq!((hide.0, hide.1), (0, 0));
    assert_eq!(show.0, 30);
    assert_eq!((styled.0, styled.1), (0, 30));
    // Outside the sphere the line is seen in every mode.
    assert!(hide.2 == 20 && show.2 == 20 && styled.2 == 20);
}

#[test]
fn line_patterns_match_their_golden_image() {
    // Every preset at factors 1, 2, 4 along spirals of sub-pixel segments (0.05 pixel), the three
    // joins and caps on zigzags, 2× supersampled.
    let mut polylines = Vec::new();
    let mut styles = Vec::new();
    for (k, (name, _)) in Stipple::PRESETS.iter().enumerate() {
        for (j, factor) in [1u32, 2, 4].into_iter().enumerate() {
            let centre = DVec3::new(-105.0 + 30.0 * k as f64, 40.0 - 30.0 * j as f64, 0.0);
            let mut s = spiral(4000, 3.0);
            for p in &mut s.points {
                *p = centre + 0.3 * *p;
            }
            s.style = styles.len() as u32;
            polylines.push(s);
            styles.push(LineStyle {
                stipple: Stipple::parse(name, factor).expect("preset"),
                width: LineWidth::Pixels(1.5),
                ..LineStyle::default()
            });
        }
    }
    for (k, (join, cap)) in [
        (Join::Miter { limit: 4.0 }, Cap::Butt),
        (Join::Round, Cap::Round),
        (Join::Bevel, Cap::Square),
    ]
    .into_iter()
    .enumerate()
    {
        let y = -55.0;
        let x = -100.0 + 70.0 * k as f64;
        let zig = polyline(
            &[
                (x, y),
                (x + 12.0, y + 14.0),
                (x + 24.0, y - 6.0),
                (x + 36.0, y + 14.0),
                (x + 50.0, y),
            ],
            styles.len() as u32,
        );
        polylines.push(zig);
        styles.push(LineStyle {
            join,
            cap,
            colour: [0.1, 0.3, 0.8, 1.0],
            ..black(8.0)
        });
    }
    let gpu = gpu();
    let renderer = Renderer::new(&gpu).expect("pipelines");
    let prepared = renderer.prepare(
        &gpu,
        &RenderScene::default().with_lines(LineSet { polylines, styles }),
    );
    let image = renderer
        .render(
            &gpu,
            &prepared,
            &ortho(140.0),
            &FrameOptions {
                supersample: 2,
                ..options(240, 140)
            },
            &ViewState::default(),
        )
        .expect("image");
    check_golden("lines-patterns.png", &image);
}
