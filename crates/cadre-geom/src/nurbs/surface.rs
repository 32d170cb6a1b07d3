//! Derivatives of (rational) B-spline surfaces.

use super::basis::{BasisDers, STACK_DEGREE, basis_funs, binomial, ders_rows, find_span};
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
        if order == 0 {
            out[0][0] = self.point_at(u, v);
            return;
        }
        let nu = self.control_points.len();
        let nv = self.control_points[0].len();
        let (p, q) = (self.u_degree, self.v_degree);
        let su = find_span(&self.u_knots, nu, p, u);
        let sv = find_span(&self.v_knots, nv, q, v);
        const W: usize = STACK_DEGREE + 1;
        let spans = (su, u, sv, v);
        // Basis tables sized by the degree (cubic and below: 4 wide), see `ders_rows`.
        match (p, q) {
            (0..4, 0..4) => self.ders_fixed::<4, 4>(spans, order, out),
            (0..4, 4..W) => self.ders_fixed::<4, W>(spans, order, out),
            (4..W, 0..4) => self.ders_fixed::<W, 4>(spans, order, out),
            (4..W, 4..W) => self.ders_fixed::<W, W>(spans, order, out),
            _ => {
                let bu = BasisDers::new(su, u, p, order, &self.u_knots);
                let bv = BasisDers::new(sv, v, q, order, &self.v_knots);
                self.fill_ders(|k| bu.row(k), |l| bv.row(l), (su - p, sv - q), order, out);
            }
        }
    }

    /// [`BSplineSurface::derivatives_into`] on spans `(su, u, sv, v)` with basis tables
    /// `WU` and `WV` wide (`u_degree < WU`, `v_degree < WV`).
    fn ders_fixed<const WU: usize, const WV: usize>(
        &self,
        (su, u, sv, v): (usize, f64, usize, f64),
        order: usize,
        out: &mut [[Vec3; 4]; 4],
    ) {
        let (p, q) = (self.u_degree, self.v_degree);
        let bu = ders_rows::<WU>(su, u, p, order, &self.u_knots);
        let bv = ders_rows::<WV>(sv, v, q, order, &self.v_knots);
        self.fill_ders(
            |k| &bu[k][..=p],
            |l| &bv[l][..=q],
            (su - p, sv - q),
            order,
            out,
        );
    }

    /// The point at `(u, v)` (polynomial extension outside the domain): order-0 basis
    /// functions only, no derivative tables and no allocation for degrees up to
    /// [`STACK_DEGREE`]. Zero for a surface that is not well formed.
    pub fn point_at(&self, u: f64, v: f64) -> Vec3 {
        if !self.is_well_formed() {
            return Vec3::ZERO;
        }
        let nu = self.control_points.len();
        let nv = self.control_points[0].len();
        let (p, q) = (self.u_degree, self.v_degree);
        let su = find_span(&self.u_knots, nu, p, u);
        let sv = find_span(&self.v_knots, nv, q, v);
        let (Some(bu), Some(bv)) = (
            basis_funs(su, u, p, &self.u_knots),
            basis_funs(sv, v, q, &self.v_knots),
        ) else {
            let mut d = [[Vec3::ZERO; 4]; 4];
            let bu = BasisDers::new(su, u, p, 0, &self.u_knots);
            let bv = BasisDers::new(sv, v, q, 0, &self.v_knots);
            self.fill_ders(|k| bu.row(k), |l| bv.row(l), (su - p, sv - q), 0, &mut d);
            return d[0][0];
        };
        let (acc, w) = self.homogeneous(&bu[..=p], &bv[..=q], su - p, sv - q);
        if self.weights.is_some() {
            // As the quotient rule of `rational` does at order 0.
            acc / w
        } else {
            acc
        }
    }

    /// Homogeneous derivatives from basis rows `ru(k)`, `rv(l)` (first non-zero functions
    /// at `first`), then the quotient rule for rational surfaces.
    fn fill_ders<'a, 'b>(
        &self,
        ru: impl Fn(usize) -> &'a [f64],
        rv: impl Fn(usize) -> &'b [f64],
        first: (usize, usize),
        order: usize,
        out: &mut [[Vec3; 4]; 4],
    ) {
        let mut w = [[0.0; 4]; 4];
        for k in 0..=order {
            for l in 0..=(order - k) {
                let (acc, wacc) = self.homogeneous(ru(k), rv(l), first.0, first.1);
                out[k][l] = acc;
                w[k][l] = wacc;
            }
        }
        if self.weights.is_some() {
            rational(out, &w, order);
        }
    }

    /// `Σ Nu Nv w P` and `Σ Nu Nv w` over the non-zero basis functions (for polynomial
    /// surfaces the weight sum is not needed and left at zero).
    fn homogeneous(&self, nu: &[f64], nv: &[f64], i0: usize, j0: usize) -> (Vec3, f64) {
        let mut acc = Vec3::ZERO;
        let mut wacc = 0.0;
        let rows = &self.control_points[i0..i0 + nu.len()];
        let Some(weights) = &self.weights else {
            for (&a, row) in nu.iter().zip(rows) {
                if a == 0.0 {
                    continue;
                }
                for (&b, &pt) in nv.iter().zip(&row[j0..]) {
                    acc += pt * (a * b);
                }
            }
            return (acc, wacc);
        };
        for ((&a, row), wrow) in nu.iter().zip(rows).zip(&weights[i0..]) {
            if a == 0.0 {
                continue;
            }
            for ((&b, &pt), &wij) in nv.iter().zip(&row[j0..]).zip(&wrow[j0..]) {
                let c = a * b * wij;
                acc += pt * c;
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
