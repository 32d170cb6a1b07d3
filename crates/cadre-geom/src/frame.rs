//! Right-handed orthonormal frames (STEP axis placements) and affine transforms.

use crate::Vec3;

/// A right-handed orthonormal frame: STEP's `AXIS2_PLACEMENT_3D` after normalisation.
///
/// `z` is the axis, `x` the reference direction (made perpendicular to `z`), `y = z × x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Origin of the frame.
    pub origin: Vec3,
    /// Unit x axis (reference direction).
    pub x: Vec3,
    /// Unit y axis, `z × x`.
    pub y: Vec3,
    /// Unit z axis.
    pub z: Vec3,
}

impl Frame {
    /// The world frame at the origin.
    pub const WORLD: Frame = Frame {
        origin: Vec3::ZERO,
        x: Vec3::X,
        y: Vec3::Y,
        z: Vec3::Z,
    };

    /// Builds a frame from an origin, an axis and an optional reference direction, as
    /// ISO 10303-42 does: the reference direction is projected onto the plane normal to the
    /// axis; when absent or parallel to the axis an arbitrary perpendicular is chosen.
    /// Returns `None` when `axis` has zero or non-finite length.
    pub fn from_axis(origin: Vec3, axis: Vec3, ref_dir: Option<Vec3>) -> Option<Frame> {
        let z = axis.try_normalize()?;
        let x = ref_dir
            .and_then(|r| (r - z * r.dot(z)).try_normalize())
            .unwrap_or_else(|| z.any_orthonormal_vector());
        let y = z.cross(x);
        Some(Frame { origin, x, y, z })
    }

    /// Maps a point given in this frame's coordinates to world coordinates.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.origin + self.x * local.x + self.y * local.y + self.z * local.z
    }

    /// Maps a world point into this frame's coordinates.
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        let d = world - self.origin;
        Vec3::new(d.dot(self.x), d.dot(self.y), d.dot(self.z))
    }

    /// The affine transform taking local coordinates of this frame to world coordinates.
    pub fn to_transform(&self) -> Transform {
        Transform::from_cols(self.x, self.y, self.z, self.origin)
    }
}

/// An affine transform in `f64`: placements of assembly instances, STEP's
/// `CARTESIAN_TRANSFORMATION_OPERATOR` (which may scale and mirror).
pub type Transform = glam::DAffine3;
