//! Arc length of curves: adaptive Gauss–Legendre integration of the speed `|C'(t)|`.

use crate::curve::Curve;
use crate::point::GeomPoint;
use crate::tolerance::Accuracy;

impl<P: GeomPoint> Curve<P> {
    /// The length of the curve between parameters `t0` and `t1` (in either order), to within
    /// `accuracy.distance` (absolute, model units): adaptive Gauss–Legendre integration
    /// (10 points, each interval compared with its two halves) of `|C'(t)|`, split first where
    /// the derivative may jump (B-spline knots, polyline and composite joints). Each interval
    /// is bisected at most `accuracy.max_iterations` times (capped at 60) and the total work is
    /// bounded; a curve that needs more gets the best estimate reached.
    ///
    /// `None` for non-finite parameters or a curve that does not evaluate finitely there.
    pub fn arc_length(&self, t0: f64, t1: f64, accuracy: Accuracy) -> Option<f64> {
        if !t0.is_finite() || !t1.is_finite() {
            return None;
        }
        let (a, b) = (t0.min(t1), t0.max(t1));
        if a == b {
            return Some(0.0);
        }
        let mut cuts = vec![a, b];
        breakpoints(self, a, b, &mut cuts, 0);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let speed = |t: f64| self.derivs(t).d1.length_p();
        let pieces: Vec<(f64, f64, f64)> = cuts
            .windows(2)
            .map(|w| (w[0], w[1], gauss_legendre(&speed, w[0], w[1])))
            .collect();
        let estimate: f64 = pieces.iter().map(|p| p.2).sum();
        if !estimate.is_finite() {
            return None;
        }
        // A tenth of the target: the two-halves estimate is far better than the one it checks.
        let tol = 0.1 * accuracy.distance.abs().max(f64::MIN_POSITIVE);
        let depth = accuracy.max_iterations.min(MAX_DEPTH);
        let mut budget = MAX_SPLITS;
        let total: f64 = pieces
            .iter()
            .map(|&(lo, hi, whole)| {
                let share = tol * (hi - lo) / (b - a);
                adapt(&speed, lo, hi, whole, share, depth, &mut budget)
            })
            .sum();
        total.is_finite().then_some(total)
    }
}

/// Deepest bisection of one interval in [`Curve::arc_length`], whatever the accuracy's
/// iteration budget: 2⁻⁶⁰ of an interval is below an `f64`'s resolution of its parameter.
const MAX_DEPTH: u32 = 60;
/// Most bisections in one [`Curve::arc_length`] (each costs 20 derivative evaluations).
const MAX_SPLITS: usize = 20_000;
/// Most breakpoints collected from knots and joints.
const MAX_BREAKPOINTS: usize = 1_000_000;

/// Abscissae and weights of the 10-point Gauss–Legendre rule on [−1, 1] (positive half).
const GL_X: [f64; 5] = [
    0.148_874_338_981_631_21,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];
const GL_W: [f64; 5] = [
    0.295_524_224_714_752_87,
    0.269_266_719_309_996_36,
    0.219_086_362_515_982_04,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_14,
];

/// `∫ f` over `[a, b]` by the 10-point Gauss–Legendre rule.
fn gauss_legendre(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    h * GL_X
        .iter()
        .zip(GL_W)
        .map(|(x, w)| w * (f(m - h * x) + f(m + h * x)))
        .sum::<f64>()
}

/// Adaptive refinement of `whole ≈ ∫ f` over `[a, b]` to `tol`.
fn adapt(
    f: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
    budget: &mut usize,
) -> f64 {
    let m = 0.5 * (a + b);
    if depth == 0 || *budget == 0 || m <= a || m >= b {
        return whole;
    }
    *budget -= 1;
    let left = gauss_legendre(f, a, m);
    let right = gauss_legendre(f, m, b);
    let halves = left + right;
    let err = (halves - whole).abs();
    // A curve that stops evaluating (NaN) ends the refinement there.
    if err <= tol || err.is_nan() {
        return halves;
    }
    adapt(f, a, m, left, 0.5 * tol, depth - 1, budget)
        + adapt(f, m, b, right, 0.5 * tol, depth - 1, budget)
}

/// Parameters strictly inside `(a, b)` where `|C'|` may be discontinuous.
fn breakpoints<P: GeomPoint>(curve: &Curve<P>, a: f64, b: f64, out: &mut Vec<f64>, depth: u32) {
    if depth > 16 || out.len() >= MAX_BREAKPOINTS {
        return;
    }
    let mut push = |t: f64| {
        if t > a && t < b && out.len() < MAX_BREAKPOINTS {
            out.push(t);
        }
    };
    match curve {
        Curve::BSpline(s) => {
            // `domain` is `None` for a malformed spline, which then has no knots to trust.
            let Some((d0, d1)) = curve.domain() else {
                return;
            };
            let (shifts, period) = match curve.period().filter(|p| *p > 0.0) {
                Some(p) if (b - a) / p < 1e3 => (
                    ((a - d0) / p).floor() as i64..=((b - d0) / p).ceil() as i64,
                    p,
                ),
                _ => (0..=0, 0.0),
            };
            for k in shifts {
                let shift = k as f64 * period;
                let mut last = f64::NAN;
                for &knot in &s.knots {
                    if knot != last && (d0..=d1).contains(&knot) {
                        push(knot + shift);
                    }
                    last = knot;
                }
            }
        }
        Curve::Polyline(_) | Curve::Composite(_) => {
            // Counted, not stepped: `t + 1` may round back to `t` far from 0.
            let first = a.floor() + 1.0;
            let count = ((b - first).ceil().max(0.0) as usize).min(MAX_BREAKPOINTS);
            for i in 0..count {
                push(first + i as f64);
            }
        }
        Curve::Trimmed { basis, .. } | Curve::Offset { basis, .. } => {
            breakpoints(basis, a, b, out, depth + 1)
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BSplineCurve, Curve3, Frame, Vec3};
    use std::f64::consts::{PI, TAU};

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    fn length(c: &Curve3, t0: f64, t1: f64) -> Option<f64> {
        c.arc_length(t0, t1, Accuracy::default())
    }

    fn line(a: Vec3, b: Vec3) -> Curve3 {
        Curve::Line {
            origin: a,
            direction: b - a,
        }
    }

    #[test]
    fn gauss_legendre_is_exact_to_degree_19() {
        assert!(close(GL_W.iter().sum::<f64>() * 2.0, 2.0, 1e-15));
        let i = gauss_legendre(&|x: f64| x.powi(18) + x.powi(19), -1.0, 1.0);
        assert!(close(i, 2.0 / 19.0, 1e-13), "{i}");
        let i = gauss_legendre(&|x: f64| x.powi(6), 0.0, 2.0);
        assert!(close(i, 128.0 / 7.0, 1e-13), "{i}");
    }

    #[test]
    fn lengths_of_analytic_curves() {
        let c = Curve::Circle {
            frame: Frame::WORLD.into(),
            radius: 3.0,
        };
        assert!(close(length(&c, 0.0, TAU).unwrap(), 6.0 * PI, 1e-14));
        assert!(close(length(&c, 2.0, 0.5).unwrap(), 4.5, 1e-14));
        let l = line(Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0));
        assert!(close(length(&l, -1.0, 1.0).unwrap(), 10.0, 1e-14));
        assert_eq!(length(&l, 1.0, 1.0), Some(0.0));
        assert_eq!(length(&l, f64::NAN, 1.0), None);
        // Ellipse a = 2, b = 1: 4·a·E(e²) with E the complete elliptic integral of the second
        // kind, E(0.75) = 1.2110560275684595.
        let e = Curve::Ellipse {
            frame: Frame::WORLD.into(),
            a: 2.0,
            b: 1.0,
        };
        let len = length(&e, 0.0, TAU).unwrap();
        assert!(close(len, 8.0 * 1.211_056_027_568_459_5, 1e-12), "{len}");
    }

    #[test]
    fn the_accuracy_bounds_the_error_and_a_coarse_one_does_less_work() {
        // An eccentric ellipse (a = 10, b = 0.1) needs refinement: the default accuracy meets
        // 1e-7 mm, a coarse one (1 mm) stops early and is further off, within its bound.
        let e = Curve::Ellipse {
            frame: Frame::WORLD.into(),
            a: 10.0,
            b: 0.1,
        };
        // 4·a·E(1 − b²/a²) with E(0.9999) = 1.0001098… (series to 1e-13 below).
        let exact = fine_ellipse_length(10.0, 0.1);
        let fine = length(&e, 0.0, TAU).unwrap();
        assert!((fine - exact).abs() <= 1e-7, "{fine} vs {exact}");
        let coarse = e.arc_length(0.0, TAU, Accuracy::new(1.0)).unwrap();
        assert!((coarse - exact).abs() <= 1.0, "{coarse} vs {exact}");
        assert!(
            (coarse - exact).abs() > (fine - exact).abs(),
            "{coarse} {fine}"
        );
    }

    /// The perimeter of an ellipse by the midpoint rule on 2²⁰ intervals of the smooth,
    /// periodic speed (exponentially accurate for periodic integrands).
    fn fine_ellipse_length(a: f64, b: f64) -> f64 {
        let n = 1 << 20;
        let h = TAU / n as f64;
        (0..n)
            .map(|i| {
                let t = (i as f64 + 0.5) * h;
                (a * a * t.sin().powi(2) + b * b * t.cos().powi(2)).sqrt() * h
            })
            .sum()
    }

    #[test]
    fn polyline_and_kinked_bspline_lengths_split_at_joints() {
        let p = Curve::Polyline(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 2.0, 0.0)]);
        assert!(close(length(&p, 0.0, 2.0).unwrap(), 3.0, 1e-14));
        assert!(close(length(&p, 0.5, 1.5).unwrap(), 1.5, 1e-14));
        // Degree 1 B-spline with a kink at knot 0.3: two straight pieces.
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
        ];
        let s = BSplineCurve::try_new(1, vec![0.0, 0.0, 0.3, 1.0, 1.0], pts, None).unwrap();
        let len = length(&Curve::BSpline(s), 0.0, 1.0).unwrap();
        assert!(close(len, 7.0, 1e-14), "{len}");
    }

    #[test]
    fn cubic_bspline_length_matches_a_fine_polyline() {
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(3.0, -1.0, 1.0),
            Vec3::new(4.0, 1.0, 0.0),
            Vec3::new(6.0, 0.0, 2.0),
        ];
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
        let c = Curve::BSpline(BSplineCurve::try_new(3, knots, pts, None).unwrap());
        let len = length(&c, 0.0, 1.0).unwrap();
        let n = 200_000;
        let poly: f64 = (0..n)
            .map(|i| (c.eval((i + 1) as f64 / n as f64) - c.eval(i as f64 / n as f64)).length())
            .sum();
        // A polyline of n chords falls short by O(1/n²).
        assert!(len > poly && (len - poly) / len < 1e-8, "{len} vs {poly}");
    }

    #[test]
    fn a_pcurve_has_a_length_in_parameter_space() {
        let c: crate::Curve2 = Curve::Line {
            origin: crate::Vec2::ZERO,
            direction: crate::Vec2::new(3.0, 4.0),
        };
        assert!(close(
            c.arc_length(0.0, 2.0, Accuracy::default()).unwrap(),
            10.0,
            1e-14
        ));
    }
}
