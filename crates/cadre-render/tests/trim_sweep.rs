//! The trim back-end's sweep evaluator (`sweep.wgsl`, run in a compute shader on the
//! adapter the tests draw on) against cadre-geom's exact surfaces of linear extrusion and of
//! revolution: points and normal directions across each face's box, for B-spline (rational,
//! with an interior knot), ellipse, circle and line profiles, a dome's pole included.
//! Negative control: the same answers compared with another sweep disagree.

mod common;

use cadre_geom::bspline::BSplineCurve;
use cadre_geom::curve::CurveFrame;
use cadre_geom::{Curve3, Surface, Vec3};
use cadre_render::trim_surfaces::surface_record;
use cadre_render::trim_sweeps::sweep_surface;

/// Sweeps and the (u, v) boxes of their faces.
fn sweeps() -> Vec<(Surface, [f64; 2], [f64; 2])> {
    let points: Vec<Vec3> = (0..5)
        .map(|i| Vec3::new(10.0 + 3.0 * (i as f64).sin(), 0.0, 4.0 * i as f64))
        .collect();
    let knots = vec![0.0, 0.0, 0.0, 0.0, 1.5, 3.0, 3.0, 3.0, 3.0];
    let weights = Some(vec![1.0, 1.3, 0.8, 1.1, 1.0]);
    let bspline = Curve3::BSpline(BSplineCurve::try_new(3, knots, points, weights).expect("curve"));
    let frame = CurveFrame {
        origin: Vec3::new(1.0, 2.0, 3.0),
        x: Vec3::X,
        y: Vec3::Z,
    };
    let pole = CurveFrame {
        origin: Vec3::new(0.5, -0.5, 0.0),
        x: Vec3::X,
        y: Vec3::Z,
    };
    vec![
        (
            Surface::Extrusion {
                profile: Box::new(bspline.clone()),
                direction: Vec3::new(0.0, 7.0, 1.0),
            },
            [0.2, -1.0],
            [2.6, 3.0],
        ),
        (
            Surface::Extrusion {
                profile: Box::new(Curve3::Ellipse {
                    frame,
                    a: 5.0,
                    b: 2.0,
                }),
                direction: Vec3::new(0.0, 3.0, 0.0),
            },
            [0.5, 0.0],
            [4.0, 2.0],
        ),
        (
            Surface::Revolution {
                profile: Box::new(bspline),
                axis_origin: Vec3::new(0.5, -0.5, 0.0),
                axis_direction: Vec3::Z,
            },
            [0.0, 0.1],
            [5.0, 2.8],
        ),
        (
            // A dome: the circle meets the axis at v = π/2.
            Surface::Revolution {
                profile: Box::new(Curve3::Circle {
                    frame: pole,
                    radius: 4.0,
                }),
                axis_origin: Vec3::new(0.5, -0.5, 0.0),
                axis_direction: Vec3::new(0.0, 0.0, 3.0),
            },
            [0.0, 0.0],
            [6.0, std::f64::consts::FRAC_PI_2],
        ),
    ]
}

#[test]
fn gpu_sweep_points_are_the_exact_surfaces() {
    let gpu = common::gpu();
    let mut data = Vec::new();
    let records: Vec<cadre_render::layout::TrimSurface> = sweeps()
        .iter()
        .enumerate()
        .map(|(k, (s, o, z))| {
            let face = sweep_surface(s, 0, (*o, *z), &mut data).expect("drawn");
            surface_record(
                &face,
                (&data, 0.0),
                k as u32,
                std::iter::empty(),
                Vec3::ZERO,
            )
        })
        .collect();
    let n = 12;
    let mut queries = Vec::new();
    let mut expected = Vec::new();
    for (k, (surface, o, z)) in sweeps().iter().enumerate() {
        for i in 0..=n {
            for j in 0..=n {
                let u = o[0] + z[0] * f64::from(i) / f64::from(n);
                let v = o[1] + z[1] * f64::from(j) / f64::from(n);
                let d = surface.derivs(u, v);
                // At the pole, the normal a step inside the box.
                let near = surface.derivs(u, v.min(o[1] + z[1] * (1.0 - 1e-3)));
                queries.push([k as u32, (u as f32).to_bits(), (v as f32).to_bits(), 0]);
                expected.push((d.point, near.du.cross(near.dv)));
            }
        }
    }
    let shader = format!(
        "@group(0) @binding(0) var<storage, read> trim_bspline: array<f32>;
         @group(0) @binding(1) var<storage, read> records: array<TrimSurface>;
         @group(0) @binding(2) var<storage, read> queries: array<vec4<u32>>;
         @group(0) @binding(3) var<storage, read_write> answers: array<vec4<f32>>;
         {}
         @compute @workgroup_size(64)
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
             if id.x >= arrayLength(&queries) {{ return; }}
             let q = queries[id.x];
             let p = face_point(records[q.x], vec2<f32>(bitcast<f32>(q.y), bitcast<f32>(q.z)) - records[q.x].uv.xy);
             answers[2u * id.x] = vec4<f32>(p.position, 0.0);
             answers[2u * id.x + 1u] = vec4<f32>(p.normal, 0.0);
         }}",
        cadre_render::trim_surfaces::surface_wgsl()
    );
    let count = queries.len() as u32;
    let inputs: [&[u8]; 3] = [
        bytemuck::cast_slice(&data),
        bytemuck::cast_slice(&records),
        bytemuck::cast_slice(&queries),
    ];
    let bytes = common::run_compute(&gpu, &shader, &inputs, (count, 32 * u64::from(count)));
    let floats: &[f32] = bytemuck::cast_slice(&bytes);
    let answers: Vec<(Vec3, Vec3)> = floats
        .chunks_exact(8)
        .map(|c| {
            let v = |k: usize| Vec3::new(f64::from(c[k]), f64::from(c[k + 1]), f64::from(c[k + 2]));
            (v(0), v(4))
        })
        .collect();
    let mut worst: f64 = 0.0;
    let mut turned = 0;
    for ((point, normal), (exact, exact_normal)) in answers.iter().zip(&expected) {
        worst = worst.max((*point - *exact).length());
        if exact_normal.length() > 1e-6
            && normal.normalize_or_zero().dot(exact_normal.normalize()) < 0.999
        {
            turned += 1;
        }
    }
    // f32 parameters and data on sweeps 20 units across: within a thousandth.
    assert!(worst < 1e-3, "worst point error {worst}");
    assert_eq!(turned, 0, "normals off by more than 2.5°");
    // Negative control: the answers set against the next sweep's points disagree.
    let per = ((n + 1) * (n + 1)) as usize;
    let far = answers
        .iter()
        .zip(expected.iter().cycle().skip(per))
        .filter(|((p, _), (e, _))| (*p - *e).length() > 1e-3)
        .count();
    assert!(far > answers.len() / 2, "{far} of {} differ", answers.len());
}
