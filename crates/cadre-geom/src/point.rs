//! The point-type abstraction that lets one implementation of curve evaluation, bounds and
//! inversion serve both model-space curves ([`Vec3`]) and parameter-space pcurves ([`Vec2`]).

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use crate::bspline::ControlPoint;
use crate::{Vec2, Vec3};

/// Vector-space operations shared by [`Vec2`] and [`Vec3`], as needed by the generic curve
/// algorithms.
pub trait GeomPoint:
    ControlPoint
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + Send
    + Sync
    + 'static
{
    /// The zero vector.
    const ZERO: Self;
    /// Number of coordinates (2 or 3).
    const DIM: usize;
    /// Euclidean dot product.
    fn dot_p(self, other: Self) -> f64;
    /// Euclidean length.
    fn length_p(self) -> f64 {
        self.dot_p(self).sqrt()
    }
    /// Coordinate `i` (`0..DIM`).
    fn coord(self, i: usize) -> f64;
    /// The point in 3D (2D points get `z = 0`), for bounding boxes.
    fn to_vec3(self) -> Vec3;
    /// The (unnormalised) offset direction of a curve with tangent `tangent`: in 3D
    /// `tangent × ref_direction` (ISO 10303-42 `offset_curve_3d`), in 2D the tangent turned
    /// by +90° (the left normal, `offset_curve_2d`). Linear in `tangent`, which the offset
    /// derivative formulas rely on.
    fn offset_direction(tangent: Self, ref_direction: Vec3) -> Self;
}

impl GeomPoint for Vec3 {
    const ZERO: Self = Vec3::ZERO;
    const DIM: usize = 3;
    fn dot_p(self, other: Self) -> f64 {
        Vec3::dot(self, other)
    }
    fn coord(self, i: usize) -> f64 {
        self[i]
    }
    fn to_vec3(self) -> Vec3 {
        self
    }
    fn offset_direction(tangent: Self, ref_direction: Vec3) -> Self {
        tangent.cross(ref_direction)
    }
}

impl GeomPoint for Vec2 {
    const ZERO: Self = Vec2::ZERO;
    const DIM: usize = 2;
    fn dot_p(self, other: Self) -> f64 {
        Vec2::dot(self, other)
    }
    fn coord(self, i: usize) -> f64 {
        self[i]
    }
    fn to_vec3(self) -> Vec3 {
        self.extend(0.0)
    }
    fn offset_direction(tangent: Self, _ref_direction: Vec3) -> Self {
        tangent.perp()
    }
}
