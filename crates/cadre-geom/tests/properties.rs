//! Property tests: derivatives against finite differences, bounding boxes against dense
//! sampling, and (in `inversion`) projection round trips, for every curve and surface kind.

mod common;

use cadre_geom::curve::Curve;
use cadre_geom::{Accuracy, BoundingBox, Curve3, GeomPoint, Surface, Vec3};
use common::{
    CURVE_KINDS, SURFACE_KINDS, Src, curve_range, curve2, curve3, surface, surface_range,
};
use proptest::prelude::*;

fn numbers() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.0..1.0f64, 96)
}

/// A parameter in `(a, b)` at least `margin` from every break (None when there is none).
fn smooth_param(x: f64, a: f64, b: f64, breaks: &[f64], margin: f64) -> Option<f64> {
    let t = a + (b - a) * (0.02 + 0.96 * x);
    breaks.iter().all(|&k| (k - t).abs() > margin).then_some(t)
}

fn check_curve_derivs<P: GeomPoint>(c: &Curve<P>, x: f64) -> Result<(), TestCaseError> {
    let (a, b) = curve_range(c);
    let Some(t) = smooth_param(x, a, b, &c.breaks_within(a, b), 1e-3) else {
        return Ok(());
    };
    let h = 1e-5 * t.abs().max(1.0);
    let d = c.derivs3(t);
    let (p, m) = (c.derivs3(t + h), c.derivs3(t - h));
    let scale = 1.0 + d.iter().map(|x| x.length_p()).fold(0.0, f64::max);
    for k in 0..3 {
        let fd = (p[k] - m[k]) * (0.5 / h);
        let err = (fd - d[k + 1]).length_p();
        // The offset's third derivative is itself a difference quotient: looser.
        let offset = matches!(c, Curve::Offset { .. });
        let tol = if k == 2 && offset { 2e-2 } else { 1e-5 } * scale;
        prop_assert!(
            err <= tol,
            "order {} at t={t}: fd {fd:?} vs {:?} ({c:?})",
            k + 1,
            d[k + 1]
        );
    }
    let cd = c.derivs(t);
    prop_assert_eq!((cd.point, cd.d1, cd.d2), (d[0], d[1], d[2]));
    prop_assert_eq!(c.eval(t), d[0]);
    Ok(())
}

fn check_surface_derivs(s: &Surface, x: f64, y: f64) -> Result<(), TestCaseError> {
    let ((u0, u1), (v0, v1)) = surface_range(s);
    let Some(u) = smooth_param(x, u0, u1, &s.u_breaks_within(u0, u1), 1e-3) else {
        return Ok(());
    };
    let Some(v) = smooth_param(y, v0, v1, &s.v_breaks_within(v0, v1), 1e-3) else {
        return Ok(());
    };
    let hu = 1e-5 * u.abs().max(1.0);
    let hv = 1e-5 * v.abs().max(1.0);
    let d = s.derivs(u, v);
    let (up, um) = (s.derivs(u + hu, v), s.derivs(u - hu, v));
    let (vp, vm) = (s.derivs(u, v + hv), s.derivs(u, v - hv));
    let scale = 1.0
        + [d.point, d.du, d.dv, d.duu, d.duv, d.dvv]
            .iter()
            .map(|x| x.length())
            .fold(0.0, f64::max);
    let checks = [
        ("du", (up.point - um.point) / (2.0 * hu), d.du),
        ("dv", (vp.point - vm.point) / (2.0 * hv), d.dv),
        ("duu", (up.du - um.du) / (2.0 * hu), d.duu),
        ("duv", (vp.du - vm.du) / (2.0 * hv), d.duv),
        ("dvu", (up.dv - um.dv) / (2.0 * hu), d.duv),
        ("dvv", (vp.dv - vm.dv) / (2.0 * hv), d.dvv),
    ];
    for (name, fd, exact) in checks {
        prop_assert!(
            (fd - exact).length() <= 1e-5 * scale,
            "{name} at ({u}, {v}): fd {fd} vs {exact} ({s:?})"
        );
    }
    prop_assert_eq!(s.eval(u, v), d.point);
    if let Some(n) = s.normal(u, v) {
        prop_assert!((n.length() - 1.0).abs() < 1e-12);
        prop_assert!(n.dot(d.du).abs() <= 1e-9 * d.du.length().max(1e-300));
    }
    Ok(())
}

/// Every sample lies in `b`, and `b` exceeds the samples' box by at most 0.1 % of its size.
fn check_box(b: &BoundingBox, samples: &[Vec3], what: &str) -> Result<(), TestCaseError> {
    let s = BoundingBox::from_points(samples.iter().copied());
    prop_assert!(!b.is_empty(), "{what}: empty box");
    prop_assert!(b.min.is_finite() && b.max.is_finite());
    let diag = s.diagonal();
    let inside = 1e-6 * diag + 1e-9;
    prop_assert!(
        b.min.cmple(s.min + Vec3::splat(inside)).all()
            && b.max.cmpge(s.max - Vec3::splat(inside)).all(),
        "{what}: box {b:?} misses samples {s:?}"
    );
    let slack = 1e-3 * diag + 1e-9;
    prop_assert!(
        b.min.cmpge(s.min - Vec3::splat(slack)).all()
            && b.max.cmple(s.max + Vec3::splat(slack)).all(),
        "{what}: box {b:?} too big for samples {s:?}"
    );
    Ok(())
}

/// `n + 1` evenly spaced parameters from `a` to `b`, plus the breaks (where kinks are).
fn dense(a: f64, b: f64, n: usize, breaks: &[f64]) -> Vec<f64> {
    let mut ts: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
    ts.extend_from_slice(breaks);
    ts
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn curve3_derivatives_match_differences(kind in 0..CURVE_KINDS, xs in numbers(), x in 0.0..1.0f64) {
        check_curve_derivs(&curve3(kind, &mut Src::new(&xs)), x)?;
    }

    #[test]
    fn curve2_derivatives_match_differences(kind in 0..CURVE_KINDS, xs in numbers(), x in 0.0..1.0f64) {
        check_curve_derivs(&curve2(kind, &mut Src::new(&xs)), x)?;
    }

    #[test]
    fn surface_derivatives_match_differences(
        kind in 0..SURFACE_KINDS, xs in numbers(), x in 0.0..1.0f64, y in 0.0..1.0f64,
    ) {
        check_surface_derivs(&surface(kind, &mut Src::new(&xs)), x, y)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn curve_boxes_are_tight(kind in 0..CURVE_KINDS, xs in numbers(), x in 0.0..1.0f64, y in 0.0..1.0f64) {
        let c = curve3(kind, &mut Src::new(&xs));
        let (a, b) = curve_range(&c);
        let (t0, t1) = (a + (b - a) * x, a + (b - a) * y);
        let ts = dense(t0, t1, 4000, &c.breaks_within(t0.min(t1), t0.max(t1)));
        let samples: Vec<Vec3> = ts.iter().map(|&t| c.eval(t)).collect();
        check_box(&c.bbox_between(t0, t1), &samples, &format!("{c:?} on [{t0}, {t1}]"))?;
        let c2 = curve2(kind, &mut Src::new(&xs));
        let ts = dense(t0, t1, 4000, &c2.breaks_within(t0.min(t1), t0.max(t1)));
        let samples: Vec<Vec3> = ts.iter().map(|&t| c2.eval(t).extend(0.0)).collect();
        check_box(&c2.bbox_between(t0, t1), &samples, &format!("{c2:?} on [{t0}, {t1}]"))?;
    }

    #[test]
    fn surface_boxes_are_tight(
        kind in 0..SURFACE_KINDS, xs in numbers(), r in prop::array::uniform4(0.0..1.0f64),
    ) {
        let s = surface(kind, &mut Src::new(&xs));
        let ((a0, a1), (b0, b1)) = surface_range(&s);
        let (u0, u1) = (a0 + (a1 - a0) * r[0], a0 + (a1 - a0) * r[1]);
        let (v0, v1) = (b0 + (b1 - b0) * r[2], b0 + (b1 - b0) * r[3]);
        let us = dense(u0, u1, 150, &s.u_breaks_within(u0.min(u1), u0.max(u1)));
        let vs = dense(v0, v1, 150, &s.v_breaks_within(v0.min(v1), v0.max(v1)));
        let mut samples = Vec::new();
        for &u in &us {
            for &v in &vs {
                samples.push(s.eval(u, v));
            }
        }
        check_box(&s.bbox_over(u0, u1, v0, v1), &samples, &format!("{s:?} on [{u0}, {u1}]x[{v0}, {v1}]"))?;
    }
}

fn check_curve_roundtrip<P: GeomPoint>(
    c: &Curve<P>,
    x: f64,
    shift: i32,
) -> Result<(), TestCaseError> {
    let acc = Accuracy::default();
    let (a, b) = curve_range(c);
    let t = a + (b - a) * x;
    let p = c.eval(t);
    let tol = 1e-6 * (1.0 + p.length_p());
    let t1 = c.project(p, None, acc);
    prop_assert!(t1.is_some(), "no projection for {c:?} at {t}");
    let t1 = t1.unwrap();
    prop_assert!((c.eval(t1) - p).length_p() <= tol, "{c:?}: t={t} gave {t1}");
    if let Some((lo, hi)) = c.domain() {
        prop_assert!(
            t1 >= lo - 1e-12 && t1 <= hi + 1e-12,
            "{t1} outside [{lo}, {hi}]"
        );
    }
    // With a hint (shifted by whole periods on periodic curves) the answer follows it.
    let hint = t + c.period().unwrap_or(0.0) * shift as f64;
    let t2 = c.project(p, Some(hint), acc).unwrap();
    prop_assert!((c.eval(t2) - p).length_p() <= tol);
    if c.period().is_some() {
        prop_assert!(
            (t2 - hint).abs() <= 1e-6 * (1.0 + hint.abs()),
            "{t2} not at hint {hint}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn curve_projection_round_trips(kind in 0..CURVE_KINDS, xs in numbers(), x in 0.0..1.0f64, shift in -2..3i32) {
        check_curve_roundtrip(&curve3(kind, &mut Src::new(&xs)), x, shift)?;
        check_curve_roundtrip(&curve2(kind, &mut Src::new(&xs)), x, shift)?;
    }

    #[test]
    fn surface_projection_round_trips(
        kind in 0..SURFACE_KINDS, xs in numbers(), x in 0.0..1.0f64, y in 0.0..1.0f64,
        lift in -1.0..1.0f64, shift in -2..3i32,
    ) {
        let s = surface(kind, &mut Src::new(&xs));
        let acc = Accuracy::default();
        let ((u0, u1), (v0, v1)) = surface_range(&s);
        let (u, v) = (u0 + (u1 - u0) * x, v0 + (v1 - v0) * y);
        let p = s.eval(u, v);
        let tol = 1e-6 * (1.0 + p.length());
        let r = s.project(p, None, acc);
        prop_assert!(r.is_some(), "no projection for {s:?} at ({u}, {v})");
        let (pu, pv) = r.unwrap();
        prop_assert!((s.eval(pu, pv) - p).length() <= tol, "{s:?}: ({u}, {v}) gave ({pu}, {pv})");
        // With a hint shifted by whole periods, periodic parameters follow the hint.
        let hint = (
            u + s.u_period().unwrap_or(0.0) * shift as f64,
            v + s.v_period().unwrap_or(0.0) * shift as f64,
        );
        let (hu, hv) = s.project(p, Some(hint), acc).unwrap();
        prop_assert!((s.eval(hu, hv) - p).length() <= tol, "{s:?}: hinted ({u}, {v}) gave ({hu}, {hv})");
        if let Some(n) = s.normal(u, v) {
            let periodic_near = |a: f64, b: f64, per: Option<f64>| per.is_none() || (a - b).abs() < 1e-3;
            // Away from poles the hinted answer is the same point, so periodic
            // parameters equal the (shifted) hint's.
            prop_assert!(periodic_near(hu, hint.0, s.u_period()) || (s.eval(hu, hv) - p).length() <= tol);
            // A point lifted off the surface along the normal, by less than the radii of
            // curvature, projects back to a point no farther than the lift.
            let d = s.derivs(u, v);
            let size = 1.0 + d.du.length().max(d.dv.length());
            let h = 1e-3 * lift * size;
            let q = p + n * h;
            if let Some((qu, qv)) = s.project(q, Some((u, v)), acc) {
                prop_assert!((s.eval(qu, qv) - q).length() <= h.abs() + tol, "{s:?}: lifted ({u}, {v}) gave ({qu}, {qv})");
            } else {
                prop_assert!(false, "no projection of lifted point");
            }
        }
    }
}

/// Degenerate but finite entities: zero radii and directions, coincident points, empty
/// lists, hand-built splines with a broken layout.
fn degenerate_curves(s: &mut Src) -> Vec<Curve3> {
    let f: cadre_geom::curve::CurveFrame<Vec3> = s.frame().into();
    let zero_frame = cadre_geom::curve::CurveFrame {
        origin: Vec3::ZERO,
        x: Vec3::ZERO,
        y: Vec3::ZERO,
    };
    let p = s.vec3(5.0);
    let mut broken = s.bspline3();
    broken.knots.pop();
    vec![
        Curve::Line {
            origin: p,
            direction: Vec3::ZERO,
        },
        Curve::Circle {
            frame: f,
            radius: 0.0,
        },
        Curve::Circle {
            frame: zero_frame,
            radius: 1.0,
        },
        Curve::Ellipse {
            frame: f,
            a: 0.0,
            b: 0.0,
        },
        Curve::Parabola {
            frame: f,
            focal: 0.0,
        },
        Curve::Hyperbola {
            frame: f,
            a: 0.0,
            b: 0.0,
        },
        Curve::Polyline(vec![]),
        Curve::Polyline(vec![p]),
        Curve::Polyline(vec![p, p, p]),
        Curve::BSpline(cadre_geom::bspline::BSplineCurve::bezier(vec![p, p, p], None).unwrap()),
        Curve::BSpline(broken),
        Curve::Trimmed {
            basis: Box::new(Curve::Circle {
                frame: f,
                radius: 1.0,
            }),
            t0: 1.0,
            t1: 1.0,
            sense: false,
        },
        Curve::Composite(vec![]),
        Curve::Offset {
            basis: Box::new(Curve::Line {
                origin: p,
                direction: Vec3::ZERO,
            }),
            distance: 1.0,
            ref_direction: Vec3::ZERO,
        },
        Curve::Offset {
            basis: Box::new(Curve::Line {
                origin: p,
                direction: Vec3::X,
            }),
            distance: 1.0,
            ref_direction: Vec3::X,
        },
    ]
}

fn degenerate_surfaces(s: &mut Src) -> Vec<Surface> {
    let f = s.frame();
    let zero = cadre_geom::Frame {
        origin: Vec3::ZERO,
        x: Vec3::ZERO,
        y: Vec3::ZERO,
        z: Vec3::ZERO,
    };
    let p = s.vec3(5.0);
    let mut broken = s.bspline_surface();
    broken.control_points.clear();
    let flat =
        cadre_geom::bspline::BSplineSurface::bezier(vec![vec![p, p], vec![p, p]], None).unwrap();
    vec![
        Surface::Plane { frame: zero },
        Surface::Cylinder {
            frame: f,
            radius: 0.0,
        },
        Surface::Cone {
            frame: f,
            radius: 0.0,
            semi_angle: 0.0,
        },
        Surface::Cone {
            frame: f,
            radius: 1.0,
            semi_angle: std::f64::consts::FRAC_PI_2,
        },
        Surface::Sphere {
            frame: f,
            radius: 0.0,
        },
        Surface::Torus {
            frame: f,
            major_radius: 0.0,
            minor_radius: 0.0,
        },
        Surface::Torus {
            frame: f,
            major_radius: 1.0,
            minor_radius: 2.0,
        },
        Surface::BSpline(Box::new(flat)),
        Surface::BSpline(Box::new(broken)),
        Surface::Revolution {
            profile: Box::new(Curve::Line {
                origin: f.origin,
                direction: f.z,
            }),
            axis_origin: f.origin,
            axis_direction: f.z,
        },
        Surface::Revolution {
            profile: Box::new(Curve::Polyline(vec![])),
            axis_origin: p,
            axis_direction: Vec3::ZERO,
        },
        Surface::Extrusion {
            profile: Box::new(Curve::Circle {
                frame: f.into(),
                radius: 1.0,
            }),
            direction: Vec3::ZERO,
        },
        Surface::Offset {
            basis: Box::new(Surface::Sphere {
                frame: f,
                radius: 0.0,
            }),
            distance: 1.0,
        },
        Surface::Offset {
            basis: Box::new(Surface::Sphere {
                frame: f,
                radius: 1.0,
            }),
            distance: -1.0,
        },
        Surface::Trimmed {
            basis: Box::new(Surface::Plane { frame: f }),
            u0: 1.0,
            u1: 1.0,
            v0: 2.0,
            v1: -2.0,
        },
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Nothing panics on degenerate finite input, and what comes back is finite (or an
    /// explicit `None` / empty box).
    #[test]
    fn degenerate_inputs_do_not_panic(xs in numbers(), t in -20.0..20.0f64, w in -20.0..20.0f64) {
        let acc = Accuracy::default();
        let q = Src::new(&xs).vec3(20.0);
        for c in degenerate_curves(&mut Src::new(&xs)) {
            let d = c.derivs3(t);
            prop_assert!(d.iter().all(|x| x.is_finite()), "{c:?} at {t}: {d:?}");
            let b = c.bbox_between(t, w);
            prop_assert!(b.is_empty() || (b.min.is_finite() && b.max.is_finite()));
            if let Some(x) = c.project(q, Some(t), acc) {
                prop_assert!(x.is_finite());
            }
            let _ = (c.domain(), c.period(), c.start_end_params(), c.breaks_within(t.min(w), t.max(w)));
        }
        for s in degenerate_surfaces(&mut Src::new(&xs)) {
            let d = s.derivs(t, w);
            prop_assert!(
                [d.point, d.du, d.dv, d.duu, d.duv, d.dvv].iter().all(|x| x.is_finite()),
                "{s:?} at ({t}, {w}): {d:?}"
            );
            if let Some(n) = s.normal(t, w) {
                prop_assert!(n.is_finite());
            }
            let b = s.bbox_over(t, t + 1.0, w, w + 2.0);
            prop_assert!(b.is_empty() || (b.min.is_finite() && b.max.is_finite()));
            if let Some((u, v)) = s.project(q, Some((t, w)), acc) {
                prop_assert!(u.is_finite() && v.is_finite());
            }
            let _ = s.project(q, None, acc);
            let _ = (s.domain(), s.u_period(), s.v_period());
        }
    }
}
