//! The trim back-end's B-spline evaluator (`bspline.wgsl`, run in a compute shader on the
//! adapter the tests draw on) against cadre-geom's exact B-spline surfaces: points and
//! normal directions of polynomial and rational surfaces of several degrees with interior
//! knots (simple and repeated), at parameters across and just outside their domains.
//! Negative control: the same answers compared with another surface disagree.

mod common;

use cadre_geom::Vec3;
use cadre_geom::bspline::BSplineSurface;
use cadre_render::trim_surfaces::{pack_bspline, surface_wgsl};

/// A surface of degrees `(p, q)` over a `nu × nv` wavy net, with interior knots (one of them
/// repeated), rational when `rational`.
fn surface(p: usize, q: usize, (nu, nv): (usize, usize), rational: bool) -> BSplineSurface {
    let knots = |n: usize, d: usize| -> Vec<f64> {
        let interior = n - d - 1;
        let mut k = vec![0.0; d + 1];
        for i in 1..=interior {
            // Uneven spacing; the middle knot twice when there is room.
            let t = (i as f64 / (interior + 1) as f64).powf(1.3) * 4.0;
            k.push(t);
        }
        if interior >= 3 {
            let mid = k[d + interior / 2];
            k[d + interior / 2 + 1] = mid;
        }
        k.extend(vec![4.0; d + 1]);
        k
    };
    let net: Vec<Vec<Vec3>> = (0..nu)
        .map(|i| {
            (0..nv)
                .map(|j| {
                    let (x, y) = (i as f64 * 10.0, j as f64 * 7.0);
                    Vec3::new(x, y, 5.0 * (0.7 * i as f64).sin() * (0.5 * j as f64).cos())
                })
                .collect()
        })
        .collect();
    let weights = rational.then(|| {
        (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| 1.0 + 0.4 * ((i + 2 * j) % 3) as f64)
                    .collect()
            })
            .collect()
    });
    BSplineSurface::try_new(p, q, knots(nu, p), knots(nv, q), net, weights).expect("surface")
}

/// The GPU's point and S_u × S_v of the surface packed at each query's offset.
fn gpu_points(gpu: &cadre_render::Gpu, data: &[f32], queries: &[(u32, [f32; 2])]) -> Vec<[f32; 8]> {
    let shader = format!(
        "@group(0) @binding(0) var<storage, read> trim_bspline: array<f32>;
         @group(0) @binding(1) var<storage, read> queries: array<vec4<u32>>;
         @group(0) @binding(2) var<storage, read_write> answers: array<vec4<f32>>;
         {}
         @compute @workgroup_size(64)
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
             if id.x >= arrayLength(&queries) {{ return; }}
             let q = queries[id.x];
             let p = bspline_point(q.x, vec2<f32>(bitcast<f32>(q.y), bitcast<f32>(q.z)));
             answers[2u * id.x] = vec4<f32>(p.position, 0.0);
             answers[2u * id.x + 1u] = vec4<f32>(p.normal, 0.0);
         }}",
        surface_wgsl()
    );
    let words: Vec<u32> = queries
        .iter()
        .flat_map(|(at, q)| [*at, q[0].to_bits(), q[1].to_bits(), 0])
        .collect();
    let count = queries.len() as u32;
    let inputs: [&[u8]; 2] = [bytemuck::cast_slice(data), bytemuck::cast_slice(&words)];
    let bytes = common::run_compute(gpu, &shader, &inputs, (count, 32 * u64::from(count)));
    let floats: &[f32] = bytemuck::cast_slice(&bytes);
    floats
        .chunks_exact(8)
        .map(|c| c.try_into().expect("8 floats"))
        .collect()
}

#[test]
fn gpu_bspline_points_are_the_exact_surfaces() {
    let gpu = common::gpu();
    let surfaces: Vec<BSplineSurface> = [
        (1, 1, (2, 2), false),
        (3, 3, (7, 6), false),
        (2, 3, (9, 5), true),
        (5, 2, (8, 4), true),
        (9, 3, (12, 6), false),
        (3, 11, (5, 14), true),
    ]
    .into_iter()
    .map(|(p, q, n, r)| surface(p, q, n, r))
    .collect();
    let mut data = Vec::new();
    let offsets: Vec<u32> = surfaces
        .iter()
        .map(|s| pack_bspline(s, Vec3::ZERO, &mut data).expect("packs"))
        .collect();
    // Across the domain [0, 4]², on knots, and a little outside it.
    let ts: Vec<f64> = (0..=16)
        .map(|k| f64::from(k) * 0.25)
        .chain([-0.01, 4.01, 1.999, 2.0001])
        .collect();
    let mut queries = Vec::new();
    let mut expected = Vec::new();
    for (s, &at) in surfaces.iter().zip(&offsets) {
        for &u in &ts {
            for &v in &ts {
                let d = s.derivatives(u, v, 1);
                queries.push((at, [u as f32, v as f32]));
                expected.push((d[0][0], d[1][0].cross(d[0][1])));
            }
        }
    }
    let answers = gpu_points(&gpu, &data, &queries);
    let mut worst: f64 = 0.0;
    let mut turned = 0;
    for (a, (point, normal)) in answers.iter().zip(&expected) {
        let p = Vec3::new(f64::from(a[0]), f64::from(a[1]), f64::from(a[2]));
        let n = Vec3::new(f64::from(a[4]), f64::from(a[5]), f64::from(a[6]));
        worst = worst.max((p - *point).length());
        if normal.length() > 1e-6 && n.normalize_or_zero().dot(normal.normalize()) < 0.999 {
            turned += 1;
        }
    }
    // f32 parameters and data on a net 100 units wide: within a thousandth.
    assert!(worst < 1e-3, "worst point error {worst}");
    assert!(turned == 0, "{turned} normals off by more than 2.5°");
    // Negative control: the answers set against the next surface's points disagree.
    let shifted = expected.iter().cycle().skip(ts.len() * ts.len());
    let far = answers
        .iter()
        .zip(shifted)
        .filter(|(a, (point, _))| {
            let p = Vec3::new(f64::from(a[0]), f64::from(a[1]), f64::from(a[2]));
            (p - *point).length() > 1e-3
        })
        .count();
    assert!(far > answers.len() / 2, "{far} of {} differ", answers.len());
}
