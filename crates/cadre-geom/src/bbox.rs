//! Axis-aligned bounding boxes in `f64`.

use crate::{Transform, Vec3};

/// An axis-aligned box; [`BoundingBox::EMPTY`] contains nothing and is the identity of
/// [`BoundingBox::union`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingBox {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl BoundingBox {
    /// The empty box.
    pub const EMPTY: BoundingBox = BoundingBox {
        min: Vec3::splat(f64::INFINITY),
        max: Vec3::splat(f64::NEG_INFINITY),
    };

    /// The box of a set of points (empty for no points). Non-finite points are skipped.
    pub fn from_points<I: IntoIterator<Item = Vec3>>(points: I) -> Self {
        let mut b = Self::EMPTY;
        for p in points {
            b.add_point(p);
        }
        b
    }

    /// Whether the box contains nothing.
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// Grows the box to contain `p` (ignored when not finite).
    pub fn add_point(&mut self, p: Vec3) {
        if p.is_finite() {
            self.min = self.min.min(p);
            self.max = self.max.max(p);
        }
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &BoundingBox) -> BoundingBox {
        if other.is_empty() {
            return *self;
        }
        if self.is_empty() {
            return *other;
        }
        BoundingBox {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Length of the diagonal (0 for an empty box). Finite whenever the box's sides are: a
    /// side past 1e154 mm (a corrupt coordinate) would overflow the squared sum, so such a box
    /// is measured scaled by its longest side.
    pub fn diagonal(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.max - self.min;
        let length = d.length();
        if length.is_finite() {
            return length;
        }
        let longest = d.abs().max_element();
        if longest.is_finite() && longest > 0.0 {
            longest * (d / longest).length()
        } else {
            length
        }
    }

    /// The eight corners (meaningless for an empty box).
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box of this box's corners after `t` (a conservative box for rotations).
    pub fn transformed(&self, t: &Transform) -> BoundingBox {
        if self.is_empty() {
            return *self;
        }
        BoundingBox::from_points(self.corners().map(|c| t.transform_point3(c)))
    }

    /// `[xmin, ymin, zmin, xmax, ymax, zmax]`, the layout used by reports and the corpus.
    pub fn to_array(&self) -> [f64; 6] {
        [
            self.min.x, self.min.y, self.min.z, self.max.x, self.max.y, self.max.z,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::BoundingBox;
    use crate::Vec3;

    /// A corrupt 1e202 coordinate made the diagonal infinite, and a relative deflection of it
    /// fell back to a unit diagonal (0.001 mm on a 700 mm part, 7·10⁵ triangles); it is
    /// finite and about the longest side. An ordinary box is measured as before.
    #[test]
    fn diagonal_of_a_huge_box_is_finite() {
        let huge = BoundingBox::from_points([Vec3::ZERO, Vec3::new(700.0, 200.0, 1e202)]);
        let d = huge.diagonal();
        assert!(d.is_finite() && (d / 1e202 - 1.0).abs() < 1e-12, "{d}");
        let plain = BoundingBox::from_points([Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0)]);
        assert_eq!(plain.diagonal(), 5.0);
    }
}
