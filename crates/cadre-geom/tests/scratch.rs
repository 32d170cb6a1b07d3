#![allow(missing_docs)]
use cadre_geom::bspline::BSplineSurface;
use cadre_geom::{Accuracy, Surface, Vec3};
use std::time::Instant;
#[test]
fn perf() {
    let n = 23; let p = 3;
    let mut knots = vec![0.0; p + 1];
    for i in 1..(n - p) { knots.push(i as f64); }
    knots.extend(vec![(n - p) as f64; p + 1]);
    let net: Vec<Vec<Vec3>> = (0..n).map(|i| (0..n).map(|j| Vec3::new(i as f64, j as f64, ((i * 7 + j * 13) % 5) as f64 * 0.3)).collect()).collect();
    let s = Surface::BSpline(Box::new(BSplineSurface::try_new(p, p, knots.clone(), knots, net, None).unwrap()));
    let ((u0, u1), (v0, v1)) = s.domain();
    let t = Instant::now();
    let b = s.bbox_over(u0, u1, v0, v1);
    println!("bbox {:?} in {:?}", b, t.elapsed());
    let t = Instant::now();
    let mut worst: f64 = 0.0;
    let m = 200;
    for k in 0..m {
        let (u, v) = (u0 + (u1 - u0) * ((k * 37 % m) as f64 / m as f64), v0 + (v1 - v0) * ((k * 91 % m) as f64 / m as f64));
        let q = s.eval(u, v) + s.normal(u, v).unwrap() * 0.01;
        let (pu, pv) = s.project(q, None, Accuracy::default()).unwrap();
        worst = worst.max((s.eval(pu, pv) - q).length() - 0.01);
    }
    println!("{m} cold projections in {:?}, worst excess {worst:e}", t.elapsed());
    let t = Instant::now();
    let mut hint = (u0, v0);
    for k in 0..m {
        let u = u0 + (u1 - u0) * k as f64 / m as f64;
        let q = s.eval(u, 3.3);
        hint = s.project(q, Some(hint), Accuracy::default()).unwrap();
    }
    println!("{m} hinted projections in {:?}", t.elapsed());
}
