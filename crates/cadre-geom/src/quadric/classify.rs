//! A quadric's class read from its matrix, and its canonical frame.
//!
//! With Q = xᵀAx + 2bᵀx + c, the eigenvectors R of A (columns) and a centre x₀ that
//! completes the squares along A's non-zero eigenvalues give, in y = Rᵀ(x − x₀),
//! Q = Σ λᵢ yᵢ² + 2 Σ βᵢ yᵢ + k with βᵢ non-zero only along A's null directions. The class
//! follows from the signs of the λᵢ, whether a null direction keeps a linear term (the
//! paraboloids and the parabolic cylinder) and the sign of k: the affine classification of
//! the thesis' tables, decided with tolerances relative to the terms compared (so a transformed
//! cone, whose k is a difference of large numbers, stays a cone).

use glam::{DMat3, DVec3};

use super::Quadric;

/// An eigenvalue below this fraction of the largest is zero.
const ZERO_EIGENVALUE: f64 = 1e-9;
/// The constant k or a null direction's linear term below this fraction of the terms it
/// was computed from is zero.
const ZERO_TERM: f64 = 1e-9;

/// The affine class of a quadric (every class of the thesis' tables, real and imaginary).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum QuadricClass {
    /// x² + y² + z² = 1.
    Ellipsoid,
    /// x² + y² + z² = −1: no real point.
    ImaginaryEllipsoid,
    /// x² + y² − z² = 1.
    HyperboloidOneSheet,
    /// x² + y² − z² = −1.
    HyperboloidTwoSheets,
    /// x² + y² = z².
    Cone,
    /// x² + y² + z² = 0: one real point.
    Point,
    /// x² + y² = z.
    EllipticParaboloid,
    /// x² − y² = z.
    HyperbolicParaboloid,
    /// x² + y² = 1.
    EllipticCylinder,
    /// x² + y² = −1: no real point.
    ImaginaryCylinder,
    /// x² − y² = 1.
    HyperbolicCylinder,
    /// x² = y.
    ParabolicCylinder,
    /// x² = y²: two planes meeting along a line.
    IntersectingPlanes,
    /// x² + y² = 0: one real line.
    Line,
    /// x² = 1.
    ParallelPlanes,
    /// x² = −1: no real point.
    ImaginaryParallelPlanes,
    /// x² = 0: one plane counted twice.
    CoincidentPlanes,
    /// x = 0: A is zero, a plane of degree one.
    Plane,
    /// A and b zero: no surface (empty or all of space).
    Degenerate,
}

impl QuadricClass {
    /// Whether the quadric has real points forming a surface (not an imaginary class, a
    /// point, a line or nothing).
    pub fn is_real_surface(self) -> bool {
        !matches!(
            self,
            QuadricClass::ImaginaryEllipsoid
                | QuadricClass::Point
                | QuadricClass::ImaginaryCylinder
                | QuadricClass::Line
                | QuadricClass::ImaginaryParallelPlanes
                | QuadricClass::Degenerate
        )
    }
}

/// A quadric in its canonical frame: Q(x) = Σ λᵢ yᵢ² + 2 Σ βᵢ yᵢ + k with
/// y = Rᵀ(x − centre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Canonical {
    /// The class.
    pub class: QuadricClass,
    /// R: unit eigenvectors of A as columns, a right-handed frame.
    pub rotation: DMat3,
    /// The origin of y.
    pub centre: DVec3,
    /// λᵢ, eigenvalues of A (exact zeros where below the tolerance).
    pub lambda: DVec3,
    /// βᵢ: the linear terms left, along A's null directions only.
    pub beta: DVec3,
    /// k.
    pub constant: f64,
}

impl Canonical {
    /// Q at the canonical coordinates `y`.
    pub fn value(&self, y: DVec3) -> f64 {
        (self.lambda * y * y + 2.0 * self.beta * y).element_sum() + self.constant
    }

    /// The canonical coordinates of the point `x`.
    pub fn to_canonical(&self, x: DVec3) -> DVec3 {
        self.rotation.transpose() * (x - self.centre)
    }

    /// The point at canonical coordinates `y`.
    pub fn to_world(&self, y: DVec3) -> DVec3 {
        self.centre + self.rotation * y
    }
}

/// The canonical form and class of `q`.
pub fn canonical(q: &Quadric) -> Canonical {
    let (lambda, rotation) = symmetric_eigen(q.quadratic_part());
    let scale = lambda.abs().max_element();
    let zero = |l: f64| l.abs() <= ZERO_EIGENVALUE * scale || scale == 0.0;
    let lambda = DVec3::select(
        glam::BVec3::new(zero(lambda.x), zero(lambda.y), zero(lambda.z)),
        DVec3::ZERO,
        lambda,
    );
    // b in the eigenframe; squares completed along the non-zero λ.
    let b = rotation.transpose() * q.linear_part();
    let mut shift = DVec3::ZERO;
    let mut beta = DVec3::ZERO;
    let mut completed = 0.0;
    for i in 0..3 {
        if lambda[i] != 0.0 {
            shift[i] = -b[i] / lambda[i];
            completed += b[i] * b[i] / lambda[i];
        } else {
            beta[i] = b[i];
        }
    }
    let c = q.constant();
    let mut k = c - completed;
    let reference = c.abs() + completed.abs();
    if k.abs() <= ZERO_TERM * reference {
        k = 0.0;
    }
    // A null direction's linear term is zero next to the whole linear part, or next to
    // √(|λ| |c|) (its own scale when b is zero).
    let linear_scale = b.length() + (scale * reference).sqrt();
    for i in 0..3 {
        if beta[i].abs() <= ZERO_TERM * linear_scale {
            beta[i] = 0.0;
        }
    }
    let centre = rotation * shift;
    Canonical {
        class: class_of(lambda, beta, k),
        rotation,
        centre,
        lambda,
        beta,
        constant: k,
    }
}

/// The class from the canonical terms.
fn class_of(lambda: DVec3, beta: DVec3, k: f64) -> QuadricClass {
    use QuadricClass as C;
    let pos = lambda.to_array().iter().filter(|&&l| l > 0.0).count();
    let neg = lambda.to_array().iter().filter(|&&l| l < 0.0).count();
    let rank = pos + neg;
    let parabolic = beta != DVec3::ZERO;
    // Signs made positive-major (Q and −Q are the same surface).
    let (minor, k) = if pos >= neg { (neg, k) } else { (pos, -k) };
    let definite = minor == 0;
    match rank {
        3 => match (definite, k) {
            (true, k) if k < 0.0 => C::Ellipsoid,
            (true, k) if k > 0.0 => C::ImaginaryEllipsoid,
            (true, _) => C::Point,
            (false, 0.0) => C::Cone,
            // Signs made two positive, one negative (x² + y² − z²): k < 0 is one sheet.
            (false, k) if k < 0.0 => C::HyperboloidOneSheet,
            (false, _) => C::HyperboloidTwoSheets,
        },
        2 if parabolic => {
            if definite {
                C::EllipticParaboloid
            } else {
                C::HyperbolicParaboloid
            }
        }
        2 => match (definite, k) {
            (true, k) if k < 0.0 => C::EllipticCylinder,
            (true, k) if k > 0.0 => C::ImaginaryCylinder,
            (true, _) => C::Line,
            (false, 0.0) => C::IntersectingPlanes,
            (false, _) => C::HyperbolicCylinder,
        },
        1 if parabolic => C::ParabolicCylinder,
        1 => match k {
            k if k < 0.0 => C::ParallelPlanes,
            k if k > 0.0 => C::ImaginaryParallelPlanes,
            _ => C::CoincidentPlanes,
        },
        _ if parabolic => C::Plane,
        _ => C::Degenerate,
    }
}

/// Eigenvalues and unit eigenvectors (columns, a right-handed frame) of the symmetric `a`,
/// by cyclic Jacobi rotations. glam has no eigen-solver, and a 3×3 Jacobi sweep converges to
/// full precision in a handful of sweeps, even for repeated eigenvalues (a sphere's).
pub fn symmetric_eigen(a: DMat3) -> (DVec3, DMat3) {
    let mut m = a.to_cols_array_2d();
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    for _sweep in 0..32 {
        let off = m[0][1].powi(2) + m[0][2].powi(2) + m[1][2].powi(2);
        let diag = m[0][0].powi(2) + m[1][1].powi(2) + m[2][2].powi(2);
        if off <= 1e-32 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // m ← Jᵀ m J, v ← v J for the rotation J in the (p, q) plane.
            for row in &mut m {
                let (mkp, mkq) = (row[p], row[q]);
                row[p] = c * mkp - s * mkq;
                row[q] = s * mkp + c * mkq;
            }
            let (rp, rq) = (m[p], m[q]);
            m[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            m[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in &mut v {
                let (a, b) = (row[p], row[q]);
                row[p] = c * a - s * b;
                row[q] = s * a + c * b;
            }
        }
    }
    // Columns of `v` (glam's cols arrays are columns) are the eigenvectors; the array was
    // updated by rows of the column-major layout, i.e. v[col][row]: transpose back.
    let vectors = DMat3::from_cols_array_2d(&v).transpose();
    let mut rotation = vectors;
    if rotation.determinant() < 0.0 {
        rotation.z_axis = -rotation.z_axis;
    }
    (DVec3::new(m[0][0], m[1][1], m[2][2]), rotation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadric::HalfSpace;
    use glam::{DAffine3, DQuat, EulerRot};

    fn moved(q: Quadric) -> Quadric {
        let m = DAffine3::from_scale_rotation_translation(
            DVec3::new(1.5, 0.7, 2.0),
            DQuat::from_euler(EulerRot::XYZ, 0.4, 1.3, -0.6),
            DVec3::new(1200.0, -40.0, 3.5),
        );
        q.transformed_affine(m).unwrap()
    }

    fn all_classes() -> Vec<(Quadric, QuadricClass)> {
        use QuadricClass as C;
        let flip = |q: Quadric| Quadric { matrix: -q.matrix };
        vec![
            (Quadric::ellipsoid(1.0, 2.0, 3.0), C::Ellipsoid),
            (flip(Quadric::sphere(2.0)), C::Ellipsoid),
            (flip(Quadric::ellipsoid(1.0, 1.0, 1.0)), C::Ellipsoid),
            (
                Quadric::from_coefficients(1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
                C::ImaginaryEllipsoid,
            ),
            (
                Quadric::hyperboloid_one_sheet(1.0, 2.0, 0.5),
                C::HyperboloidOneSheet,
            ),
            (
                flip(Quadric::hyperboloid_one_sheet(1.0, 1.0, 1.0)),
                C::HyperboloidOneSheet,
            ),
            (
                Quadric::hyperboloid_two_sheets(1.0, 2.0, 0.5),
                C::HyperboloidTwoSheets,
            ),
            (
                flip(Quadric::hyperboloid_two_sheets(3.0, 1.0, 1.0)),
                C::HyperboloidTwoSheets,
            ),
            (Quadric::cone(1.0, 2.0, 3.0), C::Cone),
            (
                Quadric::ellipsoid(1.0, 2.0, 3.0).with_constant(0.0),
                C::Point,
            ),
            (
                Quadric::elliptic_paraboloid(1.0, 3.0),
                C::EllipticParaboloid,
            ),
            (
                Quadric::hyperbolic_paraboloid(2.0, 1.0),
                C::HyperbolicParaboloid,
            ),
            (Quadric::elliptic_cylinder(1.0, 4.0), C::EllipticCylinder),
            (
                Quadric::cylinder(1.0).with_constant(1.0),
                C::ImaginaryCylinder,
            ),
            (
                Quadric::hyperbolic_cylinder(1.0, 2.0),
                C::HyperbolicCylinder,
            ),
            (Quadric::parabolic_cylinder(0.5), C::ParabolicCylinder),
            (
                Quadric::intersecting_planes(1.0, 2.0),
                C::IntersectingPlanes,
            ),
            (Quadric::cylinder(1.0).with_constant(0.0), C::Line),
            (Quadric::parallel_planes(2.0), C::ParallelPlanes),
            (
                Quadric::parallel_planes(1.0).with_constant(1.0),
                C::ImaginaryParallelPlanes,
            ),
            (
                Quadric::parallel_planes(1.0).with_constant(0.0),
                C::CoincidentPlanes,
            ),
            (
                Quadric::plane(HalfSpace::through(DVec3::ONE, DVec3::new(1.0, 2.0, 2.0))),
                C::Plane,
            ),
            (
                Quadric::from_coefficients(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
                C::Degenerate,
            ),
        ]
    }

    impl Quadric {
        fn with_constant(mut self, c: f64) -> Quadric {
            self.matrix.w_axis.w = c;
            self
        }
    }

    #[test]
    fn every_class_is_read_from_the_matrix_wherever_it_lies() {
        for (q, class) in all_classes() {
            assert_eq!(q.class(), class, "{q:?}");
            assert_eq!(moved(q).class(), class, "moved {q:?}");
        }
    }

    #[test]
    fn the_canonical_form_gives_the_same_values() {
        for (q, _) in all_classes() {
            let q = moved(q);
            let c = q.canonical();
            for p in [DVec3::new(1.0, 2.0, 3.0), DVec3::new(1199.0, -41.0, 5.0)] {
                let a = q.value(p);
                let b = c.value(c.to_canonical(p));
                assert!(
                    (a - b).abs() <= 1e-6 * (1.0 + a.abs()),
                    "{:?}: {a} vs {b}",
                    c.class
                );
            }
            assert!((c.rotation.determinant() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn jacobi_finds_repeated_and_distinct_eigenvalues() {
        let r = DMat3::from_quat(DQuat::from_euler(EulerRot::XYZ, 0.3, 0.2, 0.1));
        for d in [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(2.0, 2.0, -1.0),
            DVec3::ZERO,
        ] {
            let a = r * DMat3::from_diagonal(d) * r.transpose();
            let (l, v) = symmetric_eigen(a);
            let mut got = l.to_array();
            let mut want = d.to_array();
            got.sort_by(f64::total_cmp);
            want.sort_by(f64::total_cmp);
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).abs() < 1e-12, "{got:?} vs {want:?}");
            }
            for i in 0..3 {
                let col = v.col(i);
                assert!((a * col - l[i] * col).length() < 1e-12);
            }
        }
    }
}
