//! Quadrics as exact display primitives (seed 001): the surface PᵀQP = 0 of a symmetric 4×4
//! matrix Q over homogeneous points P = (x, y, z, 1), cut by oriented planes, as a surface
//! patch or as the volume Q ≤ 0.
//!
//! - [`Quadric`]: the matrix, its constructors for every class of the thesis' tables, its
//!   value and gradient, and its transform Q' = M⁻ᵀ Q M⁻¹.
//! - [`classify`]: the class read from the matrix (not from how it was built) and the
//!   canonical frame in which it is Σ λᵢ yᵢ² + 2 Σ βᵢ yᵢ + k.
//! - [`CutQuadric`]: a quadric cut by [`HalfSpace`]s, its `f64` ray intersection (the oracle
//!   of the GPU ray caster) and its bounds ([`bounds`]).
//! - [`tetra`]: quadric patches in a tetrahedron from 10 Bernstein weights.

pub mod bounds;
pub mod classify;
mod ray;
pub mod tetra;

use glam::{DAffine3, DMat3, DMat4, DVec3, DVec4};

pub use bounds::{QuadricBounds, QuadricBoundsError};
pub use classify::{Canonical, QuadricClass};
pub use ray::{HitBoundary, QuadricHit};

/// A quadric surface: the points P = (x, y, z, 1) with PᵀQP = 0, Q symmetric.
///
/// Its inside is Q ≤ 0 (a sphere's is its ball); negate the matrix to swap sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    /// The symmetric matrix (column-major, as glam stores it).
    pub matrix: DMat4,
}

impl Quadric {
    /// The quadric a x² + b y² + c z² + 2d xy + 2e xz + 2f yz + 2g x + 2h y + 2i z + j = 0
    /// (the seed's coefficients, in its order).
    #[allow(clippy::too_many_arguments)]
    pub fn from_coefficients(
        a: f64,
        b: f64,
        c: f64,
        d: f64,
        e: f64,
        f: f64,
        g: f64,
        h: f64,
        i: f64,
        j: f64,
    ) -> Quadric {
        Quadric {
            matrix: DMat4::from_cols(
                DVec4::new(a, d, e, g),
                DVec4::new(d, b, f, h),
                DVec4::new(e, f, c, i),
                DVec4::new(g, h, i, j),
            ),
        }
    }

    /// The quadric of a symmetric matrix; `None` when `matrix` is not symmetric within
    /// 1e-12 of its largest entry, or has a non-finite entry.
    pub fn from_matrix(matrix: DMat4) -> Option<Quadric> {
        let scale = matrix.abs().to_cols_array().into_iter().fold(0.0, f64::max);
        if !scale.is_finite() {
            return None;
        }
        let asym = (matrix - matrix.transpose()).abs().to_cols_array();
        asym.into_iter()
            .all(|x| x <= 1e-12 * scale)
            .then(|| Quadric {
                // Exactly symmetric from here on.
                matrix: (matrix + matrix.transpose()) * 0.5,
            })
    }

    /// x²/a² + y²/b² + z²/c² = 1 (`a = b = c`: a sphere).
    pub fn ellipsoid(a: f64, b: f64, c: f64) -> Quadric {
        diagonal([1.0 / (a * a), 1.0 / (b * b), 1.0 / (c * c)], -1.0)
    }

    /// The sphere of `radius` about the origin.
    pub fn sphere(radius: f64) -> Quadric {
        Quadric::ellipsoid(radius, radius, radius)
    }

    /// x²/a² + y²/b² − z²/c² = 1.
    pub fn hyperboloid_one_sheet(a: f64, b: f64, c: f64) -> Quadric {
        diagonal([1.0 / (a * a), 1.0 / (b * b), -1.0 / (c * c)], -1.0)
    }

    /// z²/c² − x²/a² − y²/b² = 1 (inside: the two sheets' insides).
    pub fn hyperboloid_two_sheets(a: f64, b: f64, c: f64) -> Quadric {
        diagonal([1.0 / (a * a), 1.0 / (b * b), -1.0 / (c * c)], 1.0)
    }

    /// x²/a² + y²/b² = z²/c² (the double cone of axis z; inside: about the axis).
    pub fn cone(a: f64, b: f64, c: f64) -> Quadric {
        diagonal([1.0 / (a * a), 1.0 / (b * b), -1.0 / (c * c)], 0.0)
    }

    /// x²/a² + y²/b² = 1, along z.
    pub fn elliptic_cylinder(a: f64, b: f64) -> Quadric {
        diagonal([1.0 / (a * a), 1.0 / (b * b), 0.0], -1.0)
    }

    /// The circular cylinder of `radius` about the z axis.
    pub fn cylinder(radius: f64) -> Quadric {
        Quadric::elliptic_cylinder(radius, radius)
    }

    /// x²/a² − y²/b² = 1, along z.
    pub fn hyperbolic_cylinder(a: f64, b: f64) -> Quadric {
        diagonal([1.0 / (a * a), -1.0 / (b * b), 0.0], -1.0)
    }

    /// x² = 2p y, along z (inside: the side holding its focus).
    pub fn parabolic_cylinder(p: f64) -> Quadric {
        Quadric::from_coefficients(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -p, 0.0, 0.0)
    }

    /// x²/a² + y²/b² = z (inside: about the axis, z above the surface).
    pub fn elliptic_paraboloid(a: f64, b: f64) -> Quadric {
        let mut q = diagonal([1.0 / (a * a), 1.0 / (b * b), 0.0], 0.0);
        q.matrix.z_axis.w = -0.5;
        q.matrix.w_axis.z = -0.5;
        q
    }

    /// x²/a² − y²/b² = z (the saddle).
    pub fn hyperbolic_paraboloid(a: f64, b: f64) -> Quadric {
        let mut q = diagonal([1.0 / (a * a), -1.0 / (b * b), 0.0], 0.0);
        q.matrix.z_axis.w = -0.5;
        q.matrix.w_axis.z = -0.5;
        q
    }

    /// The planes y = ±(b/a) x meeting along z (inside: the wedges about the x axis).
    pub fn intersecting_planes(a: f64, b: f64) -> Quadric {
        diagonal([-1.0 / (a * a), 1.0 / (b * b), 0.0], 0.0)
    }

    /// The planes x = ±a (inside: between them).
    pub fn parallel_planes(a: f64) -> Quadric {
        diagonal([1.0, 0.0, 0.0], -a * a)
    }

    /// The plane n·x + d = 0 as a quadric of rank 2 (the plane and the plane at infinity;
    /// inside: n·x + d ≤ 0).
    pub fn plane(plane: HalfSpace) -> Quadric {
        let n = 0.5 * plane.normal;
        Quadric::from_coefficients(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, n.x, n.y, n.z, plane.offset)
    }

    /// Q(p) = PᵀQP at the point `p`.
    pub fn value(&self, p: DVec3) -> f64 {
        let h = p.extend(1.0);
        h.dot(self.matrix * h)
    }

    /// ∇Q at `p` (pointing to the outside, Q > 0).
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        2.0 * (self.matrix * p.extend(1.0)).truncate()
    }

    /// The upper-left 3×3 block A (the quadratic part).
    pub fn quadratic_part(&self) -> DMat3 {
        DMat3::from_mat4(self.matrix)
    }

    /// The linear part b (Q = xᵀAx + 2bᵀx + c).
    pub fn linear_part(&self) -> DVec3 {
        self.matrix.w_axis.truncate()
    }

    /// The constant c.
    pub fn constant(&self) -> f64 {
        self.matrix.w_axis.w
    }

    /// The quadric carried by the projective map `m` (points P' = mP): Q' = m⁻ᵀ Q m⁻¹.
    /// The true inverse is used, never the adjugate, so the inside stays the inside when
    /// `m` mirrors (det < 0). `None` when `m` is singular.
    pub fn transformed(&self, m: DMat4) -> Option<Quadric> {
        let inv = invert(m)?;
        let q = inv.transpose() * self.matrix * inv;
        Some(Quadric {
            matrix: (q + q.transpose()) * 0.5,
        })
    }

    /// [`Quadric::transformed`] by an affine map.
    pub fn transformed_affine(&self, m: DAffine3) -> Option<Quadric> {
        self.transformed(DMat4::from(m))
    }

    /// The class of this quadric and its canonical frame ([`classify::canonical`]).
    pub fn canonical(&self) -> Canonical {
        classify::canonical(self)
    }

    /// The class of this quadric, read from its matrix.
    pub fn class(&self) -> QuadricClass {
        self.canonical().class
    }
}

/// `diag(a0, a1, a2) x` + constant `c`.
fn diagonal(a: [f64; 3], c: f64) -> Quadric {
    Quadric {
        matrix: DMat4::from_diagonal(DVec4::new(a[0], a[1], a[2], c)),
    }
}

/// The inverse of `m`, `None` when its determinant is zero or not finite relative to its
/// entries' scale.
fn invert(m: DMat4) -> Option<DMat4> {
    let scale = m.abs().to_cols_array().into_iter().fold(0.0, f64::max);
    let det = m.determinant();
    (det.is_finite() && scale > 0.0 && det.abs() > 1e-14 * scale.powi(4)).then(|| m.inverse())
}

/// The half-space n·x + d ≤ 0: what a cutting plane keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    /// The plane's normal, pointing out of what is kept (need not be unit).
    pub normal: DVec3,
    /// d in n·x + d.
    pub offset: f64,
}

impl HalfSpace {
    /// The half-space behind the plane through `point` with outward `normal`.
    pub fn through(point: DVec3, normal: DVec3) -> HalfSpace {
        HalfSpace {
            normal,
            offset: -normal.dot(point),
        }
    }

    /// n·p + d: negative inside, positive outside.
    pub fn value(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.offset
    }

    /// The half-space carried by the projective map `m`: the row vector π' = π m⁻¹, so
    /// (m⁻ᵀ applied to (n, d)). With the true inverse its sign is kept when `m` mirrors (the
    /// adjugate would flip it). `None` when `m` is singular.
    pub fn transformed(&self, m: DMat4) -> Option<HalfSpace> {
        let inv = invert(m)?;
        let p = inv.transpose() * self.normal.extend(self.offset);
        Some(HalfSpace {
            normal: p.truncate(),
            offset: p.w,
        })
    }
}

/// What a cut quadric is: the surface, or the solid it bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutKind {
    /// The surface Q = 0 within every half-space: where the front sheet is cut away the
    /// back sheet shows.
    Patch,
    /// The solid Q ≤ 0 within every half-space: where a plane cuts it, the plane is its
    /// boundary (and gives the normal).
    Volume,
}

impl CutKind {
    /// `Volume` when `volume`, else `Patch`.
    pub fn volume_if(volume: bool) -> CutKind {
        if volume {
            CutKind::Volume
        } else {
            CutKind::Patch
        }
    }
}

/// A quadric cut by planes: the thesis' primitive.
#[derive(Clone, Debug, PartialEq)]
pub struct CutQuadric {
    /// The quadric.
    pub quadric: Quadric,
    /// What it keeps: points with every half-space's value ≤ 0.
    pub planes: Vec<HalfSpace>,
    /// Surface patch or volume.
    pub kind: CutKind,
}

impl CutQuadric {
    /// Whether `p` is kept by every plane (within `tolerance` of their zero sets).
    pub fn within_planes(&self, p: DVec3, tolerance: f64) -> bool {
        self.planes
            .iter()
            .all(|h| h.value(p) <= tolerance * h.normal.length())
    }

    /// This primitive carried by the map `m` (quadric and planes alike); `None` when `m` is
    /// singular.
    pub fn transformed(&self, m: DMat4) -> Option<CutQuadric> {
        Some(CutQuadric {
            quadric: self.quadric.transformed(m)?,
            planes: self
                .planes
                .iter()
                .map(|h| h.transformed(m))
                .collect::<Option<_>>()?,
            kind: self.kind,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coefficients_are_the_seed_s() {
        // x² + 2y² + 3z² + 2·4xy + 2·5xz + 2·6yz + 2·7x + 2·8y + 2·9z + 10.
        let q = Quadric::from_coefficients(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0);
        let p = DVec3::new(0.3, -1.2, 2.0);
        let (x, y, z) = (p.x, p.y, p.z);
        let direct = x * x
            + 2.0 * y * y
            + 3.0 * z * z
            + 8.0 * x * y
            + 10.0 * x * z
            + 12.0 * y * z
            + 14.0 * x
            + 16.0 * y
            + 18.0 * z
            + 10.0;
        assert!((q.value(p) - direct).abs() < 1e-12);
        let h = 1e-6;
        let fd = DVec3::new(
            q.value(p + DVec3::X * h) - q.value(p - DVec3::X * h),
            q.value(p + DVec3::Y * h) - q.value(p - DVec3::Y * h),
            q.value(p + DVec3::Z * h) - q.value(p - DVec3::Z * h),
        ) / (2.0 * h);
        assert!((fd - q.gradient(p)).length() < 1e-6);
    }

    #[test]
    fn a_transformed_quadric_holds_the_transformed_points() {
        let q = Quadric::hyperboloid_one_sheet(1.0, 2.0, 0.5);
        let m = DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, 0.5, -1.5),
            glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
            DVec3::new(100.0, -3.0, 7.0),
        );
        let moved = q.transformed_affine(m).unwrap();
        for &(u, z) in &[(0.0, 0.0), (1.0, 0.3), (2.5, -2.0)] {
            let s = (1.0f64 + (z / 0.5f64).powi(2)).sqrt();
            let p = DVec3::new(s * f64::cos(u), 2.0 * s * f64::sin(u), z);
            assert!(q.value(p).abs() < 1e-12);
            assert!(moved.value(m.transform_point3(p)).abs() < 1e-9);
        }
    }

    #[test]
    fn a_mirror_keeps_the_inside_inside() {
        let solid = CutQuadric {
            quadric: Quadric::sphere(1.0),
            planes: vec![HalfSpace::through(DVec3::new(0.0, 0.0, 0.5), DVec3::Z)],
            kind: CutKind::Volume,
        };
        let mirror = DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0))
            * DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0));
        assert!(mirror.determinant() < 0.0);
        let moved = solid.transformed(mirror).unwrap();
        let inside = DVec3::new(0.2, 0.1, 0.0);
        let cut_away = DVec3::new(0.0, 0.0, 0.8);
        for (p, kept) in [(inside, true), (cut_away, false)] {
            let q = mirror.transform_point3(p);
            assert_eq!(moved.quadric.value(q) <= 0.0, solid.quadric.value(p) <= 0.0);
            assert_eq!(moved.within_planes(q, 0.0), kept, "{p}");
        }
    }
}
