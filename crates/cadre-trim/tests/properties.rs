//! Property tests of the trim pieces: fits stay within their (u, v) tolerances, implicit forms
//! tell the two sides of a piece apart, monotone parts retrace their piece. Each has a negative
//! control: a piece moved by a few tolerances fails the distance check, a reversed piece flips
//! every side.

use cadre_trim::{QuadPiece, Uv, UvTolerance, fit_points};
use proptest::prelude::*;

/// The smallest distance, in tolerances, from `p` to the pieces (each sampled densely, then
/// refined by a few Newton steps from its nearest sample).
fn distance(pieces: &[QuadPiece], p: Uv, tol: UvTolerance) -> f64 {
    let mut best = f64::INFINITY;
    for piece in pieces {
        let n = 512;
        let d: Vec<f64> = (0..=n)
            .map(|k| tol.scaled(piece.eval(f64::from(k) / f64::from(n)) - p))
            .collect();
        // Refine each sampled local minimum by ternary search around it: near a sharp turn
        // the two branches of a piece lie close, and the best sample may sit on the wrong one.
        for k in 0..=n as usize {
            let left = if k > 0 { d[k - 1] } else { f64::INFINITY };
            let right = if k < n as usize {
                d[k + 1]
            } else {
                f64::INFINITY
            };
            if d[k] > left || d[k] > right {
                continue;
            }
            let t = k as f64 / f64::from(n);
            let (mut lo, mut hi) = (
                (t - 1.0 / f64::from(n)).max(0.0),
                (t + 1.0 / f64::from(n)).min(1.0),
            );
            for _ in 0..60 {
                let a = lo + (hi - lo) / 3.0;
                let b = hi - (hi - lo) / 3.0;
                if tol.scaled(piece.eval(a) - p) < tol.scaled(piece.eval(b) - p) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            best = best
                .min(d[k])
                .min(tol.scaled(piece.eval(0.5 * (lo + hi)) - p));
        }
    }
    best
}

/// Samples of an elliptic arc: centre, radii, rotation, start and sweep.
fn ellipse_arc(c: Uv, r: Uv, rot: f64, start: f64, sweep: f64, n: usize) -> Vec<Uv> {
    (0..=n)
        .map(|k| {
            let a = start + sweep * k as f64 / n as f64;
            let local = Uv::new(r.x * a.cos(), r.y * a.sin());
            c + Uv::from_angle(rot).rotate(local)
        })
        .collect()
}

/// Samples of a cubic Bézier curve.
fn cubic(p: [Uv; 4], n: usize) -> Vec<Uv> {
    (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let s = 1.0 - t;
            s * s * s * p[0] + 3.0 * s * s * t * p[1] + 3.0 * s * t * t * p[2] + t * t * t * p[3]
        })
        .collect()
}

fn uv() -> impl Strategy<Value = Uv> {
    (-10.0..10.0f64, -10.0..10.0f64).prop_map(|(u, v)| Uv::new(u, v))
}

/// An elliptic arc: centre, radii, rotation, start and sweep.
fn arc() -> impl Strategy<Value = (Uv, Uv, f64, f64, f64)> {
    use std::f64::consts::TAU;
    (
        uv(),
        0.05..5.0f64,
        0.05..5.0f64,
        0.0..TAU,
        0.0..TAU,
        0.1..6.2f64,
    )
        .prop_map(|(c, rx, ry, rot, start, sweep)| (c, Uv::new(rx, ry), rot, start, sweep))
}

fn tolerance() -> impl Strategy<Value = UvTolerance> {
    (-5.0..-2.0f64, -5.0..-2.0f64).prop_map(|(u, v)| UvTolerance {
        u: 10f64.powf(u),
        v: 10f64.powf(v),
    })
}

/// The pieces join end to end from the first sample to the last, and every sample lies
/// within the tolerance of them.
fn check_fit(points: &[Uv], tol: UvTolerance) -> Result<Vec<QuadPiece>, TestCaseError> {
    let pieces = fit_points(points, tol);
    prop_assert!(!pieces.is_empty());
    prop_assert_eq!(pieces[0].p[0], points[0]);
    prop_assert_eq!(pieces[pieces.len() - 1].p[2], points[points.len() - 1]);
    for pair in pieces.windows(2) {
        prop_assert_eq!(pair[0].p[2], pair[1].p[0]);
    }
    for p in points {
        let d = distance(&pieces, *p, tol);
        prop_assert!(d <= 1.0 + 1e-6, "sample {} lies {} tolerances away", p, d);
    }
    Ok(pieces)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn fitted_arcs_stay_within_tolerance(
        (c, r, rot, start, sweep) in arc(),
        n in 40usize..600,
        tol in tolerance(),
    ) {
        let points = ellipse_arc(c, r, rot, start, sweep, n);
        check_fit(&points, tol)?;
    }

    #[test]
    fn fitted_cubics_stay_within_tolerance(
        a in uv(), b in uv(), c in uv(), d in uv(),
        n in 40usize..600,
        tol in tolerance(),
    ) {
        let points = cubic([a, b, c, d], n);
        let pieces = check_fit(&points, tol)?;
        // Negative control: the piece spanning the most samples, its control point moved
        // across its chord so that its middle moves by three tolerances, leaves some of its
        // samples outside (the check above can fail).
        let spanned = |piece: &QuadPiece| {
            points.iter().filter(|p| distance(std::slice::from_ref(piece), **p, tol) <= 1.0).count()
        };
        let Some(k) = (0..pieces.len()).max_by_key(|&k| spanned(&pieces[k])) else {
            return Ok(());
        };
        if spanned(&pieces[k]) >= 5 {
            let chord = pieces[k].p[2] - pieces[k].p[0];
            let across = Uv::new(chord.x / tol.u, chord.y / tol.v).perp().normalize();
            let mut moved = pieces.clone();
            moved[k].p[1] += 6.0 * Uv::new(across.x * tol.u, across.y * tol.v);
            let worst = points
                .iter()
                .map(|p| distance(&moved, *p, tol))
                .fold(0.0, f64::max);
            prop_assert!(worst > 1.0, "a piece moved by 3 tolerances still fits ({})", worst);
        }
    }

    /// The pieces follow the curve, not the polyline through its samples: every point of an
    /// elliptic arc (eight between each two samples) lies within 1.15 tolerances of them
    /// where the samples' chords sag by up to 2/3 of the tolerance (as `model_trees` samples
    /// its edges: to ε/2, against a fit within 0.75 ε). Negative control: the pieces moved
    /// by two tolerances along u are farther.
    #[test]
    fn fitted_pieces_follow_the_curve_between_samples(
        (c, r, rot, start, sweep) in arc(),
        tol in (-4.0..-2.0f64, -4.0..-2.0f64),
    ) {
        let tol = UvTolerance { u: 10f64.powf(tol.0), v: 10f64.powf(tol.1) };
        // Samples about as dense as a sag of 0.6 tolerance asks.
        let reach = r.max_element() / tol.u.min(tol.v);
        let n = ((sweep * (reach / 4.8).sqrt()).ceil() as usize).clamp(8, 20_000);
        let points = ellipse_arc(c, r, rot, start, sweep, n);
        let dense = ellipse_arc(c, r, rot, start, sweep, 8 * n);
        let sag = (0..n)
            .map(|k| tol.scaled(dense[8 * k + 4] - 0.5 * (points[k] + points[k + 1])))
            .fold(0.0, f64::max);
        prop_assume!(sag <= 2.0 / 3.0);
        let pieces = fit_points(&points, tol);
        let worst = dense.iter().map(|p| distance(&pieces, *p, tol)).fold(0.0, f64::max);
        prop_assert!(worst <= 1.15, "the curve lies {} tolerances from its pieces (sag {})", worst, sag);
        let moved: Vec<QuadPiece> = pieces
            .iter()
            .map(|q| QuadPiece { p: q.p.map(|p| p + Uv::new(2.0 * tol.u, 0.0)) })
            .collect();
        let moved_worst = dense.iter().map(|p| distance(&moved, *p, tol)).fold(0.0, f64::max);
        prop_assert!(moved_worst > 1.15, "moved pieces still within {}", moved_worst);
    }

    #[test]
    fn implicit_forms_tell_left_from_right(
        p0 in uv(), p1 in uv(), p2 in uv(),
        t in 0.05..0.95f64,
    ) {
        let piece = QuadPiece { p: [p0, p1, p2] };
        let size = (p1 - p0).length().max((p2 - p0).length());
        let tangent = piece.derivative(t);
        prop_assume!(tangent.length() > 1e-3 * size && size > 1e-3);
        // A step small against the curvature radius at t and against the width of the
        // control triangle (a nearly folded piece's two branches lie that close).
        let second = 2.0 * (p0 - 2.0 * p1 + p2);
        let radius = tangent.length().powi(3) / tangent.perp_dot(second).abs().max(1e-300);
        let width = (p1 - p0).perp_dot(p2 - p0).abs() / size;
        let step = 1e-3 * radius.min(size).min(width.max(1e-9 * size));
        let left = tangent.normalize().perp();
        let on = piece.eval(t);
        let f = piece.implicit();
        prop_assert!(f.value(on + step * left) > 0.0, "left side of {:?} at {}", piece, t);
        prop_assert!(f.value(on - step * left) < 0.0, "right side of {:?} at {}", piece, t);
        // Negative control: the piece reversed has its sides swapped.
        let back = QuadPiece { p: [p2, p1, p0] }.implicit();
        prop_assert!(back.value(on + step * left) < 0.0);
        prop_assert!(back.value(on - step * left) > 0.0);
    }

    #[test]
    fn monotone_parts_retrace_their_piece(p0 in uv(), p1 in uv(), p2 in uv()) {
        let piece = QuadPiece { p: [p0, p1, p2] };
        let parts = piece.monotone_parts();
        // Every part's points lie on the piece.
        for part in &parts {
            for k in 0..=8 {
                let q = part.eval(f64::from(k) / 8.0);
                let d = distance(&[piece], q, UvTolerance { u: 1.0, v: 1.0 });
                prop_assert!(d < 1e-7, "{} off the piece by {}", q, d);
            }
        }
    }
}
