//! Surfaces in model space. Parameterisations `S(u, v)` follow ISO 10303-42; angles in radians.

use crate::bspline::BSplineSurface;
use crate::{Curve3, Frame, Vec3};

/// A parametric surface. Each variant's `S(u, v)` is given in its doc.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// `S = o + u·x + v·y`.
    Plane {
        /// Position; `z` is the normal.
        frame: Frame,
    },
    /// `S = o + r (cos u·x + sin u·y) + v·z`.
    Cylinder {
        /// Position; `z` is the axis.
        frame: Frame,
        /// Radius.
        radius: f64,
    },
    /// `S = o + (r + v tan α)(cos u·x + sin u·y) + v·z`; `r` is the radius at `v = 0`.
    Cone {
        /// Position; `z` is the axis.
        frame: Frame,
        /// Radius at the frame origin.
        radius: f64,
        /// Semi-angle α in radians (0 < α < π/2).
        semi_angle: f64,
    },
    /// `S = o + r cos v (cos u·x + sin u·y) + r sin v·z`, `v ∈ [−π/2, π/2]`.
    Sphere {
        /// Centre and axes.
        frame: Frame,
        /// Radius.
        radius: f64,
    },
    /// `S = o + (R + r cos v)(cos u·x + sin u·y) + r sin v·z`; `r > R` is a degenerate
    /// (spindle) torus, allowed.
    Torus {
        /// Centre and axes.
        frame: Frame,
        /// Major radius R.
        major_radius: f64,
        /// Minor radius r.
        minor_radius: f64,
    },
    /// A (possibly rational) B-spline or Bézier surface.
    BSpline(Box<BSplineSurface>),
    /// Sweep of `profile` about an axis: `u` is the rotation angle and `v` the profile's
    /// parameter (ISO 10303-42 and OCCT order, so the file's pcurves and its face senses
    /// apply as written):
    /// `S = c + ((P(v)−c)·a)a + cos u ((P(v)−c) − ((P(v)−c)·a)a) + sin u (a × (P(v)−c))`.
    Revolution {
        /// Swept curve.
        profile: Box<Curve3>,
        /// A point on the axis.
        axis_origin: Vec3,
        /// Unit axis direction.
        axis_direction: Vec3,
    },
    /// `S = P(u) + v·d` (d keeps the STEP vector's magnitude).
    Extrusion {
        /// Swept curve.
        profile: Box<Curve3>,
        /// Extrusion vector.
        direction: Vec3,
    },
    /// `S = B(u, v) + d·N(u, v)` with `N` the unit normal of the basis.
    Offset {
        /// The surface offset.
        basis: Box<Surface>,
        /// Signed distance along the normal.
        distance: f64,
    },
    /// The basis restricted to `[u0, u1] × [v0, v1]` (STEP `RECTANGULAR_TRIMMED_SURFACE`);
    /// the parameters are those of the basis.
    Trimmed {
        /// Underlying surface.
        basis: Box<Surface>,
        /// First u.
        u0: f64,
        /// Second u.
        u1: f64,
        /// First v.
        v0: f64,
        /// Second v.
        v1: f64,
    },
}

impl Surface {
    /// A short type name, as used in reports (`"Plane"`, `"Cylinder"`, …). The names match
    /// the keys of `surface_types` in `../shared/corpus/reference.jsonl` (OCCT's class names
    /// without the `Geom_` prefix).
    pub fn type_name(&self) -> &'static str {
        match self {
            Surface::Plane { .. } => "Plane",
            Surface::Cylinder { .. } => "Cylinder",
            Surface::Cone { .. } => "Cone",
            Surface::Sphere { .. } => "Sphere",
            Surface::Torus { .. } => "Torus",
            Surface::BSpline(_) => "BSplineSurface",
            Surface::Revolution { .. } => "SurfaceOfRevolution",
            Surface::Extrusion { .. } => "SurfaceOfExtrusion",
            Surface::Offset { .. } => "OffsetSurface",
            Surface::Trimmed { .. } => "RectangularTrimmedSurface",
        }
    }
}
