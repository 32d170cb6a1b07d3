//! Quadric patches in a tetrahedron (the seed's §"carreaux"): the zero set, inside the
//! tetrahedron, of the quadratic Bernstein polynomial f = Σ w_ab B_ab(λ) of its 10 weights,
//! λ the barycentric coordinates. Since λ is affine in x, f is a quadric:
//! f = λᵀ W λ with W_aa = w_aa and W_ab = w_ab, and λ = L (x, 1), so Q = Lᵀ W L.
//!
//! Two patches sharing a face join with continuous gradients (C¹, hence G¹) when the
//! neighbour's weights off the face are the de Casteljau combinations of the first's
//! ([`BernsteinTetrahedron::c1_neighbour`]): their polynomials then differ by c λ_e², which
//! vanishes to first order on the shared face.

use glam::{DMat4, DVec3, DVec4};

use super::{CutKind, CutQuadric, HalfSpace, Quadric};

/// The order of the 10 weights: the vertex pairs (a, b).
pub const WEIGHT_PAIRS: [(usize, usize); 10] = [
    (0, 0),
    (1, 1),
    (2, 2),
    (3, 3),
    (0, 1),
    (0, 2),
    (0, 3),
    (1, 2),
    (1, 3),
    (2, 3),
];

/// A tetrahedron and the quadratic Bernstein weights of its patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BernsteinTetrahedron {
    /// Its four vertices.
    pub vertices: [DVec3; 4],
    /// Weights in [`WEIGHT_PAIRS`] order.
    pub weights: [f64; 10],
}

impl BernsteinTetrahedron {
    /// L: the barycentric coordinates λ = L (x, 1) (rows); `None` for a flat tetrahedron.
    pub fn barycentric_matrix(&self) -> Option<DMat4> {
        let v = &self.vertices;
        let m = DMat4::from_cols(
            v[0].extend(1.0),
            v[1].extend(1.0),
            v[2].extend(1.0),
            v[3].extend(1.0),
        );
        let size = (v[1] - v[0])
            .length()
            .max((v[2] - v[0]).length())
            .max((v[3] - v[0]).length());
        (m.determinant().abs() > 1e-12 * size.powi(3)).then(|| m.inverse())
    }

    /// λ at `p`.
    pub fn barycentric(&self, p: DVec3) -> Option<DVec4> {
        Some(self.barycentric_matrix()? * p.extend(1.0))
    }

    /// W: the weights as a symmetric matrix.
    fn weight_matrix(&self) -> DMat4 {
        let mut w = [[0.0; 4]; 4];
        for (&(a, b), &x) in WEIGHT_PAIRS.iter().zip(&self.weights) {
            w[a][b] = x;
            w[b][a] = x;
        }
        DMat4::from_cols_array_2d(&w)
    }

    /// f at `p`, from the Bernstein form (the reference the quadric is checked against).
    pub fn value(&self, p: DVec3) -> Option<f64> {
        let l = self.barycentric(p)?.to_array();
        Some(
            WEIGHT_PAIRS
                .iter()
                .zip(&self.weights)
                .map(|(&(a, b), w)| {
                    let multinomial = if a == b { 1.0 } else { 2.0 };
                    w * multinomial * l[a] * l[b]
                })
                .sum(),
        )
    }

    /// The quadric f = 0: Q = Lᵀ W L.
    pub fn quadric(&self) -> Option<Quadric> {
        let l = self.barycentric_matrix()?;
        let q = l.transpose() * self.weight_matrix() * l;
        Some(Quadric {
            matrix: (q + q.transpose()) * 0.5,
        })
    }

    /// The patch: the quadric cut by the tetrahedron's four faces (λᵢ ≥ 0).
    pub fn patch(&self) -> Option<CutQuadric> {
        let l = self.barycentric_matrix()?.transpose();
        Some(CutQuadric {
            quadric: self.quadric()?,
            planes: (0..4)
                .map(|i| {
                    // Row i of L (a column of its transpose): −λᵢ ≤ 0.
                    let row = l.col(i);
                    HalfSpace {
                        normal: -row.truncate(),
                        offset: -row.w,
                    }
                })
                .collect(),
            kind: CutKind::Patch,
        })
    }

    /// The tetrahedron across the face opposite vertex `opposite`, with `apex` in place of
    /// that vertex, whose patch joins this one with continuous gradients: the weights on the
    /// shared face are this one's, those of a face vertex with the apex are the de Casteljau
    /// combination Σₖ μₖ w_ak (μ: the apex's barycentric coordinates here), and the apex's
    /// own weight `apex_weight` is free (this polynomial's value there continues it exactly).
    /// `None` when either tetrahedron is flat.
    pub fn c1_neighbour(
        &self,
        opposite: usize,
        apex: DVec3,
        apex_weight: f64,
    ) -> Option<BernsteinTetrahedron> {
        let mu = self.barycentric(apex)?.to_array();
        let w = self.weight_matrix().to_cols_array_2d();
        let mut vertices = self.vertices;
        vertices[opposite] = apex;
        let weights = std::array::from_fn(|i| {
            let (a, b) = WEIGHT_PAIRS[i];
            match (a == opposite, b == opposite) {
                (false, false) => w[a][b],
                (true, true) => apex_weight,
                (true, false) => (0..4).map(|k| mu[k] * w[b][k]).sum(),
                (false, true) => (0..4).map(|k| mu[k] * w[a][k]).sum(),
            }
        });
        let out = BernsteinTetrahedron { vertices, weights };
        out.barycentric_matrix()?;
        Some(out)
    }

    /// The apex weight that makes [`BernsteinTetrahedron::c1_neighbour`] continue this
    /// polynomial exactly (C∞): μᵀ W μ.
    pub fn continued_weight(&self, apex: DVec3) -> Option<f64> {
        let mu = self.barycentric(apex)?;
        Some(mu.dot(self.weight_matrix() * mu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tet() -> BernsteinTetrahedron {
        BernsteinTetrahedron {
            vertices: [
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.3, 1.5, 0.0),
                DVec3::new(0.5, 0.4, 1.8),
            ],
            weights: [1.0, -0.5, 0.7, -1.2, 0.2, 0.9, -0.3, 0.1, 0.6, -0.8],
        }
    }

    #[test]
    fn the_quadric_is_the_bernstein_polynomial() {
        let t = tet();
        let q = t.quadric().unwrap();
        for p in [
            DVec3::new(0.5, 0.3, 0.2),
            DVec3::new(-1.0, 2.0, 0.4),
            DVec3::ONE,
        ] {
            assert!((q.value(p) - t.value(p).unwrap()).abs() < 1e-12);
        }
        // At a vertex f is its weight.
        assert!((q.value(t.vertices[2]) - 0.7).abs() < 1e-12);
    }

    #[test]
    fn the_patch_keeps_the_tetrahedron() {
        let p = tet().patch().unwrap();
        let centroid = tet().vertices.iter().sum::<DVec3>() / 4.0;
        assert!(p.within_planes(centroid, 0.0));
        assert!(!p.within_planes(DVec3::new(-0.1, 0.1, 0.1), 0.0));
    }

    #[test]
    fn neighbours_share_value_and_gradient_on_their_face() {
        let t = tet();
        let apex = DVec3::new(1.2, 1.4, 1.6);
        let n = t.c1_neighbour(0, apex, 3.0).unwrap();
        let (q1, q2) = (t.quadric().unwrap(), n.quadric().unwrap());
        let v = t.vertices;
        for (a, b) in [(0.2, 0.3), (0.5, 0.1), (0.25, 0.25)] {
            // A point of the shared face (vertices 1, 2, 3).
            let p = v[1] * (1.0 - a - b) + v[2] * a + v[3] * b;
            assert!((q1.value(p) - q2.value(p)).abs() < 1e-12);
            assert!((q1.gradient(p) - q2.gradient(p)).length() < 1e-10);
        }
        // Negative control: a neighbour built with other off-face weights breaks the join.
        let mut broken = n;
        broken.weights[4] += 0.5;
        let p = v[1] * 0.5 + v[2] * 0.25 + v[3] * 0.25;
        assert!((broken.quadric().unwrap().gradient(p) - q1.gradient(p)).length() > 1e-3);
        // The continued weight gives the same quadric.
        let same = t
            .c1_neighbour(0, apex, t.continued_weight(apex).unwrap())
            .unwrap();
        let d = same.quadric().unwrap().matrix - q1.matrix;
        assert!(d.abs().to_cols_array().iter().all(|x| *x < 1e-10));
    }
}
