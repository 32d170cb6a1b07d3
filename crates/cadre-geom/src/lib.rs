//! Exact geometry for cadre: points and frames in `f64`, analytic curves and surfaces, rational
//! B-splines, their evaluation, bounds and inversion.
//!
//! Parameterisations follow ISO 10303-42 (STEP part 42), because the parameter-space curves
//! (pcurves) in STEP files refer to exactly those parameters. Angles are always radians here;
//! the STEP mapper converts from the file's plane-angle unit.
//!
//! Accuracy is always an explicit argument ([`Accuracy`]) with a documented default, never a
//! global constant.

mod arc_length;
pub mod bbox;
mod bounds;
pub mod bspline;
mod crease;
pub mod curve;
pub mod eval;
pub mod frame;
mod invert;
pub mod nurbs;
pub mod point;
pub mod quadric;
pub mod surface;
pub mod tolerance;

pub use bbox::BoundingBox;
pub use bspline::{BSplineCurve, BSplineSurface, KnotError};
pub use curve::{Curve, Curve2, Curve3};
pub use eval::curve::CurveDerivs;
pub use eval::surface::SurfaceDerivs;
pub use frame::{Frame, Transform};
pub use point::GeomPoint;
pub use quadric::{CutKind, CutQuadric, HalfSpace, Quadric, QuadricClass};
pub use surface::Surface;
pub use tolerance::Accuracy;

/// A point or vector in model space (millimetres once mapped).
pub type Vec3 = glam::DVec3;
/// A point or vector in a surface's parameter space, or in 2D model space.
pub type Vec2 = glam::DVec2;
