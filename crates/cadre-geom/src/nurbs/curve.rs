//! Derivatives of (rational) B-spline curves.

use super::basis::{BasisDers, STACK_DEGREE, basis_funs, binomial, ders_rows, find_span};
use crate::bspline::BSplineCurve;
use crate::point::GeomPoint;

impl<P: GeomPoint> BSplineCurve<P> {
    /// The point and derivatives up to `order` at `t` (`result[k]` is the `k`-th
    /// derivative). Rational curves are differentiated exactly: homogeneous derivatives
    /// first, then the quotient rule (*The NURBS Book* A4.2). Outside the domain the end
    /// pieces are extended polynomially.
    ///
    /// A hand-built curve that is not [well formed](BSplineCurve::is_well_formed) evaluates
    /// to zero rather than panicking.
    pub fn derivatives(&self, t: f64, order: usize) -> Vec<P> {
        let mut out = vec![P::ZERO; order + 1];
        self.derivatives_into(t, &mut out);
        out
    }

    /// [`BSplineCurve::derivatives`] up to order `out.len() − 1`, written into `out` (no
    /// allocation for usual degrees).
    pub fn derivatives_into(&self, t: f64, out: &mut [P]) {
        if out.is_empty() || !self.is_well_formed() {
            out.fill(P::ZERO);
            return;
        }
        let t = self.wrap(t);
        let span = find_span(&self.knots, self.control_points.len(), self.degree, t);
        self.derivatives_on_span(span, t, out);
    }

    /// `t` moved into the domain by whole periods when the curve is [closed]
    /// (BSplineCurve::closed); unchanged otherwise or inside the domain.
    fn wrap(&self, t: f64) -> f64 {
        if !self.closed {
            return t;
        }
        let (a, b) = self.domain();
        if (a..=b).contains(&t) || !t.is_finite() {
            t
        } else {
            a + (t - a).rem_euclid(b - a)
        }
    }

    /// Whether the curve ends where it starts (within 1e-9 of its control polygon's size):
    /// then it may be evaluated as periodic (see [`BSplineCurve::closed`]).
    pub fn ends_meet(&self) -> bool {
        if !self.is_well_formed() {
            return false;
        }
        let (a, b) = self.domain();
        let mut ends = [P::ZERO];
        let mut end = [P::ZERO];
        self.derivatives_on_span(
            find_span(&self.knots, self.control_points.len(), self.degree, a),
            a,
            &mut ends,
        );
        self.derivatives_on_span(
            find_span(&self.knots, self.control_points.len(), self.degree, b),
            b,
            &mut end,
        );
        let first = self.control_points[0];
        let size = self
            .control_points
            .iter()
            .map(|&q| (q - first).length_p())
            .fold(0.0, f64::max);
        (ends[0] - end[0]).length_p() <= 1e-9 * size.max(1e-300)
    }

    /// [`BSplineCurve::derivatives_into`] using the polynomial piece of knot span `span`
    /// (as returned by [`find_span`]; `degree ≤ span < n`), for callers that sample one
    /// span repeatedly and so need not search for it each time. Only the orders asked for
    /// are computed; order 0 uses the point-only basis ([`basis_funs`]).
    ///
    /// # Panics
    ///
    /// If the curve is not [well formed](BSplineCurve::is_well_formed) or `span` is out of
    /// range.
    pub fn derivatives_on_span(&self, span: usize, t: f64, out: &mut [P]) {
        let Some(order) = out.len().checked_sub(1) else {
            return;
        };
        let p = self.degree;
        assert!(span >= p && span < self.control_points.len());
        let first = span - p;
        if order == 0
            && let Some(n) = basis_funs(span, t, p, &self.knots)
        {
            self.combine(first, |_| &n[..=p], out);
        } else if order <= 3 && p < 4 {
            let rows = ders_rows::<4>(span, t, p, order, &self.knots);
            self.combine(first, |k| &rows[k][..=p], out);
        } else if order <= 3 && p <= STACK_DEGREE {
            let rows = ders_rows::<{ STACK_DEGREE + 1 }>(span, t, p, order, &self.knots);
            self.combine(first, |k| &rows[k][..=p], out);
        } else {
            let basis = BasisDers::new(span, t, p, order, &self.knots);
            self.combine(first, |k| basis.row(k), out);
        }
    }

    /// Combines the control points with basis rows `row(k)` (of the points from `first`)
    /// into `out[k]`, dividing out the weight for rational curves.
    fn combine<'a>(&self, first: usize, row: impl Fn(usize) -> &'a [f64], out: &mut [P]) {
        let pts = &self.control_points[first..];
        // Homogeneous derivatives: A⁽ᵏ⁾ = Σ N⁽ᵏ⁾ w P, w⁽ᵏ⁾ = Σ N⁽ᵏ⁾ w.
        let Some(weights) = &self.weights else {
            for (k, slot) in out.iter_mut().enumerate() {
                let mut acc = P::ZERO;
                for (&b, &pt) in row(k).iter().zip(pts) {
                    acc += pt * b;
                }
                *slot = acc;
            }
            return;
        };
        let ws = &weights[first..];
        let mut w = [0.0; 8];
        for (k, slot) in out.iter_mut().enumerate() {
            let mut acc = P::ZERO;
            let mut wk = 0.0;
            for ((&b, &pt), &wi) in row(k).iter().zip(pts).zip(ws) {
                acc += pt * (b * wi);
                wk += b * wi;
            }
            *slot = acc;
            if k < w.len() {
                w[k] = wk;
            }
        }
        // Quotient rule: C⁽ᵏ⁾ = (A⁽ᵏ⁾ − Σᵢ C(k,i) w⁽ⁱ⁾ C⁽ᵏ⁻ⁱ⁾) / w (orders ≤ 7 kept).
        for k in 0..out.len().min(w.len()) {
            let mut v = out[k];
            for i in 1..=k {
                v -= out[k - i] * (binomial(k, i) * w[i]);
            }
            out[k] = v * (1.0 / w[0]);
        }
    }

    /// Whether the fields have the layout evaluation relies on: degree ≥ 1, more control
    /// points than the degree, `n + degree + 1` knots spanning a non-empty domain, and one
    /// weight per point if rational. [`BSplineCurve::try_new`] guarantees it; the fields are
    /// public, so evaluation checks rather than trusts it.
    pub fn is_well_formed(&self) -> bool {
        let (n, p) = (self.control_points.len(), self.degree);
        p >= 1
            && n > p
            && self.knots.len() == n + p + 1
            && self.knots[p] < self.knots[n]
            && self.weights.as_ref().is_none_or(|w| w.len() == n)
    }

    /// The point at `t` (polynomial extension outside the domain).
    pub fn point_at(&self, t: f64) -> P {
        let mut out = [P::ZERO];
        self.derivatives_into(t, &mut out);
        out[0]
    }

    /// Distinct interior knots strictly inside `(t0, t1)`: where the curve may lose
    /// smoothness, so samplers split there.
    /// For a [closed](BSplineCurve::closed) curve the knots repeat every period.
    pub fn breaks_within(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        let (a, b) = self.domain();
        let (first, last) =
            if self.closed && self.is_well_formed() && t0.is_finite() && t1.is_finite() {
                let p = b - a;
                // At most a few periods: a range is never much longer than one.
                let lo = ((t0 - b) / p).floor().max(-4.0) as i64;
                let hi = ((t1 - a) / p).ceil().min(4.0) as i64;
                (lo, hi)
            } else {
                (0, 0)
            };
        for m in first..=last {
            let shift = m as f64 * (b - a);
            for &k in &self.knots {
                let k = k + shift;
                if k > t0 && k < t1 && out.last().is_none_or(|&l| k > l) {
                    out.push(k);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::bspline::BSplineCurve;
    use crate::{Vec2, Vec3};

    #[test]
    fn closed_curves_wrap_and_open_ones_extend() {
        let square = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(0.0, 0.0),
        ];
        let knots = vec![0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0];
        let mut c = BSplineCurve::try_new(1, knots.clone(), square, None).unwrap();
        assert!(c.ends_meet());
        // Not flagged: the last piece extends linearly.
        assert!((c.point_at(4.5) - Vec2::new(0.0, -0.5)).length() < 1e-12);
        c.closed = true;
        assert!((c.point_at(4.5) - Vec2::new(0.5, 0.0)).length() < 1e-12);
        assert!((c.point_at(-0.5) - Vec2::new(0.0, 0.5)).length() < 1e-12);
        assert_eq!(c.breaks_within(3.5, 5.5), vec![4.0, 5.0]);
        assert_eq!(crate::Curve::BSpline(c).period(), Some(4.0));
        let open = vec![Vec2::ZERO, Vec2::X, Vec2::ONE];
        let open = BSplineCurve::try_new(1, vec![0.0, 0.0, 1.0, 2.0, 2.0], open, None).unwrap();
        assert!(!open.ends_meet());
    }

    #[test]
    fn rational_quarter_circle_is_on_circle() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = BSplineCurve::bezier(
            vec![
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
            Some(vec![1.0, s, 1.0]),
        )
        .unwrap();
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let d = c.derivatives(t, 2);
            assert!((d[0].length() - 1.0).abs() < 1e-14);
            // Tangent is perpendicular to the radius on a circle.
            assert!(d[0].dot(d[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn cubic_bezier_derivative() {
        let c = BSplineCurve::bezier(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(2.0, 1.0, 0.0),
                Vec3::new(3.0, 0.0, 1.0),
            ],
            None,
        )
        .unwrap();
        let d = c.derivatives(0.0, 3);
        assert_eq!(d[0], Vec3::ZERO);
        assert!((d[1] - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-14);
        assert!((d[2] - 6.0 * (Vec3::new(2.0, 1.0, 0.0) - 2.0 * Vec3::X)).length() < 1e-12);
    }
}
