//! Derivatives of (rational) B-spline surfaces.

use super::basis::{BasisDers, binomial, find_span};
use crate::Vec3;
use crate::bspline::BSplineSurface;

impl BSplineSurface {
    /// Partial derivatives up to total order `order` at `(u, v)`: `result[k][l]` is
    /// `∂ᵏ⁺ˡS/∂uᵏ∂vˡ` for `k + l ≤ order` (other entries zero). Rational surfaces use the
    /// quotient rule on homogeneous derivatives (*The NURBS Book* A4.4).
    ///
    /// A hand-built surface that is not [well formed](BSplineSurface::is_well_formed)
    /// evaluates to zero rather than panicking.
    pub fn derivatives(&self, u: f64, v: f64, order: usize) -> Vec<Vec<Vec3>> {
        let mut d = [[Vec3::ZERO; 4]; 4];
        if order <= 3 {
            self.derivatives_into(u, v, order, &mut d);
            return (0..=order).map(|k| d[k][..=order].to_vec()).collect();
        }
        self.derivatives_general(u, v, order)
    }

    /// [`BSplineSurface::derivatives`] for `order ≤ 3` into a fixed array, without
    /// allocating for usual degrees (the inner loop of bounds and inversion).
    pub fn derivatives_into(&self, u: f64, v: f64, order: usize, out: &mut [[Vec3; 4]; 4]) {
        *out = [[Vec3::ZERO; 4]; 4];
        let order = order.min(3);
        if !self.is_well_formed() {
            return;
        }
        let nu = self.control_points.len();
        let nv = self.control_points[0].len();
        let (p, q) = (self.u_degree, self.v_degree);
        let su = find_span(&self.u_knots, nu, p, u);
        let sv = find_span(&self.v_knots, nv, q, v);
        let bu = BasisDers::new(su, u, p, order, &self.u_knots);
        let bv = BasisDers::new(sv, v, q, order, &self.v_knots);
        let mut w = [[0.0; 4]; 4];
        for k in 0..=order {
            for l in 0..=(order - k) {
                let (acc, wacc) = self.homogeneous(bu.row(k), bv.row(l), su - p, sv - q);
                out[k][l] = acc;
                w[k][l] = wacc;
            }
        }
        if self.weights.is_none() {
            return;
        }
        rational(out, &w, order);
    }

    /// `Σ Nu Nv w P` and `Σ Nu Nv w` over the non-zero basis functions.
    fn homogeneous(&self, nu: &[f64], nv: &[f64], i0: usize, j0: usize) -> (Vec3, f64) {
        let mut acc = Vec3::ZERO;
        let mut wacc = 0.0;
        for (r, &a) in nu.iter().enumerate() {
            if a == 0.0 {
                continue;
            }
            let i = i0 + r;
            let row = &self.control_points[i];
            let wrow = self.weights.as_ref().map(|w| &w[i]);
            for (s, &b) in nv.iter().enumerate() {
                let j = j0 + s;
                let wij = wrow.map_or(1.0, |w| w[j]);
                let c = a * b * wij;
                acc += row[j] * c;
                wacc += c;
            }
        }
        (acc, wacc)
    }

    /// Arbitrary-order derivatives (allocating), for `order > 3`.
    fn derivatives_general(&self, u: f64, v: f64, order: usize) -> Vec<Vec<Vec3>> {
        let mut a = vec![vec![Vec3::ZERO; order + 1]; order + 1];
        if !self.is_well_formed() {
            return a;
        }
        let nu = self.control_points.len();
        let nv = self.control_points[0].len();
        let (p, q) = (self.u_degree, self.v_degree);
        let su = find_span(&self.u_knots, nu, p, u);
        let sv = find_span(&self.v_knots, nv, q, v);
        let bu = BasisDers::new(su, u, p, order, &self.u_knots);
        let bv = BasisDers::new(sv, v, q, order, &self.v_knots);
        let mut w = vec![vec![0.0; order + 1]; order + 1];
        for k in 0..=order {
            for l in 0..=(order - k) {
                let (acc, wacc) = self.homogeneous(bu.row(k), bv.row(l), su - p, sv - q);
                a[k][l] = acc;
                w[k][l] = wacc;
            }
        }
        if self.weights.is_none() {
            return a;
        }
        let mut skl = vec![vec![Vec3::ZERO; order + 1]; order + 1];
        for k in 0..=order {
            for l in 0..=(order - k) {
                let mut v = a[k][l];
                for j in 1..=l {
                    v -= binomial(l, j) * w[0][j] * skl[k][l - j];
                }
                for i in 1..=k {
                    v -= binomial(k, i) * w[i][0] * skl[k - i][l];
                    let mut v2 = Vec3::ZERO;
                    for j in 1..=l {
                        v2 += binomial(l, j) * w[i][j] * skl[k - i][l - j];
                    }
                    v -= binomial(k, i) * v2;
                }
                skl[k][l] = v / w[0][0];
            }
        }
        skl
    }

    /// Whether the fields have the layout evaluation relies on (see
    /// [`crate::bspline::BSplineCurve::is_well_formed`]), with a rectangular net and, if
    /// rational, weights of the net's shape.
    pub fn is_well_formed(&self) -> bool {
        let nu = self.control_points.len();
        let nv = self.control_points.first().map_or(0, Vec::len);
        let (p, q) = (self.u_degree, self.v_degree);
        p >= 1
            && q >= 1
            && nu > p
            && nv > q
            && self.control_points.iter().all(|r| r.len() == nv)
            && self.u_knots.len() == nu + p + 1
            && self.v_knots.len() == nv + q + 1
            && self.u_knots[p] < self.u_knots[nu]
            && self.v_knots[q] < self.v_knots[nv]
            && self
                .weights
                .as_ref()
                .is_none_or(|w| w.len() == nu && w.iter().all(|r| r.len() == nv))
    }

    /// Distinct u knots strictly inside `(u0, u1)`.
    pub fn u_breaks_within(&self, u0: f64, u1: f64) -> Vec<f64> {
        distinct_within(&self.u_knots, u0, u1)
    }

    /// Distinct v knots strictly inside `(v0, v1)`.
    pub fn v_breaks_within(&self, v0: f64, v1: f64) -> Vec<f64> {
        distinct_within(&self.v_knots, v0, v1)
    }
}

/// In place: homogeneous derivatives `a` and weight derivatives `w` to the rational
/// surface's derivatives (*The NURBS Book* A4.4).
fn rational(a: &mut [[Vec3; 4]; 4], w: &[[f64; 4]; 4], order: usize) {
    let src = *a;
    for k in 0..=order {
        for l in 0..=(order - k) {
            let mut v = src[k][l];
            for j in 1..=l {
                v -= binomial(l, j) * w[0][j] * a[k][l - j];
            }
            for i in 1..=k {
                v -= binomial(k, i) * w[i][0] * a[k - i][l];
                let mut v2 = Vec3::ZERO;
                for j in 1..=l {
                    v2 += binomial(l, j) * w[i][j] * a[k - i][l - j];
                }
                v -= binomial(k, i) * v2;
            }
            a[k][l] = v / w[0][0];
        }
    }
}

fn distinct_within(knots: &[f64], a: f64, b: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for &k in knots {
        if k > a && k < b && out.last() != Some(&k) {
            out.push(k);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::Vec3;
    use crate::bspline::BSplineSurface;

    #[test]
    fn bilinear_patch() {
        let s = BSplineSurface::bezier(
            vec![
                vec![Vec3::ZERO, Vec3::Y],
                vec![Vec3::X, Vec3::new(1.0, 1.0, 1.0)],
            ],
            None,
        )
        .unwrap();
        let d = s.derivatives(0.5, 0.5, 2);
        assert!((d[0][0] - Vec3::new(0.5, 0.5, 0.25)).length() < 1e-15);
        assert!((d[1][1] - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-14);
        assert_eq!(d[2][0], Vec3::ZERO);
    }
}
