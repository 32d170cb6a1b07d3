//! Hot paths of B-spline geometry as `cadre info` exercises them on large assemblies:
//! curve and surface point evaluation, the sampled bounding box of a curve arc, and point
//! projection onto a surface.

// `criterion_group!` generates an undocumented function.
#![allow(missing_docs)]

use std::hint::black_box;

use cadre_geom::{Accuracy, BSplineCurve, BSplineSurface, Curve, Curve3, Surface, Vec3};
use criterion::{Criterion, criterion_group, criterion_main};

/// A wavy cubic through 24 control points on a non-uniform knot vector; rational when
/// `rational` (weights between 0.6 and 1.4).
fn curve(rational: bool) -> Curve3 {
    let n = 24;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let x = i as f64;
            Vec3::new(x, (0.7 * x).sin() * 3.0, (0.3 * x).cos() * 2.0)
        })
        .collect();
    let mut knots = vec![0.0; 4];
    let mut k = 0.0;
    for i in 0..(n - 4) {
        k += 1.0 + 0.3 * (i % 3) as f64;
        knots.push(k);
    }
    knots.extend([k + 1.0; 4]);
    let weights = rational.then(|| (0..n).map(|i| 1.0 + 0.4 * (i as f64).sin()).collect());
    Curve::BSpline(BSplineCurve::try_new(3, knots, pts, weights).unwrap())
}

/// A bicubic 10 × 10 bump surface, rational when asked.
fn surface(rational: bool) -> Surface {
    let n = 10;
    let pts: Vec<Vec<Vec3>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    Vec3::new(x, y, (0.5 * x).sin() * (0.4 * y).cos() * 2.0)
                })
                .collect()
        })
        .collect();
    let mut knots = vec![0.0; 4];
    knots.extend((1..(n - 3)).map(|i| i as f64));
    knots.extend([(n - 3) as f64; 4]);
    let weights = rational.then(|| {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| 1.0 + 0.3 * ((i + 2 * j) as f64).sin())
                    .collect()
            })
            .collect()
    });
    Surface::BSpline(Box::new(
        BSplineSurface::try_new(3, 3, knots.clone(), knots, pts, weights).unwrap(),
    ))
}

fn bench(c: &mut Criterion) {
    for rational in [false, true] {
        let tag = if rational { "rational" } else { "poly" };
        let cv = curve(rational);
        let (t0, t1) = cv.domain().unwrap();
        let ts: Vec<f64> = (0..1000)
            .map(|i| t0 + (t1 - t0) * i as f64 / 999.0)
            .collect();
        c.bench_function(&format!("curve_eval_{tag}_x1000"), |b| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for &t in &ts {
                    acc += cv.eval(black_box(t));
                }
                acc
            })
        });
        c.bench_function(&format!("curve_bbox_between_{tag}"), |b| {
            b.iter(|| cv.bbox_between(black_box(t0 + 0.1), black_box(t1 - 0.2)))
        });

        let sf = surface(rational);
        let ((u0, u1), (v0, v1)) = sf.domain();
        let uvs: Vec<(f64, f64)> = (0..1000)
            .map(|i| {
                let (a, b) = ((i % 37) as f64 / 36.0, (i / 37) as f64 / 27.0);
                (u0 + (u1 - u0) * a, v0 + (v1 - v0) * b)
            })
            .collect();
        c.bench_function(&format!("surface_eval_{tag}_x1000"), |b| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for &(u, v) in &uvs {
                    acc += sf.eval(black_box(u), black_box(v));
                }
                acc
            })
        });
        let probes: Vec<Vec3> = (0..16)
            .map(|i| {
                let (u, v) = uvs[i * 61];
                sf.eval(u, v) + Vec3::new(0.1, -0.05, 0.3)
            })
            .collect();
        c.bench_function(&format!("surface_project_{tag}_x16"), |b| {
            b.iter(|| {
                probes
                    .iter()
                    .filter_map(|&p| sf.project(black_box(p), None, Accuracy::default()))
                    .count()
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(1));
    targets = bench
}
criterion_main!(benches);
