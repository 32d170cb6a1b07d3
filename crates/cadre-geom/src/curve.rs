//! Parametric curves in model space ([`Curve3`]) and in parameter space ([`Curve2`]).
//!
//! Parameterisations are those of ISO 10303-42 so that trimming parameters and pcurves read
//! from STEP files apply unchanged. Conic parameters are angles in radians.

use crate::bspline::BSplineCurve;
use crate::{Frame, Vec2, Vec3};

/// A curve in 3D model space.
pub type Curve3 = Curve<Vec3>;
/// A curve in a surface's (u, v) parameter space (a pcurve), or in a 2D plane.
pub type Curve2 = Curve<Vec2>;

/// A frame for curves of dimension `P`: in 3D a full [`Frame`]; in 2D an origin and an x axis
/// (y is x rotated by +90°).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveFrame<P> {
    /// Centre of the conic.
    pub origin: P,
    /// Unit x axis (towards parameter 0).
    pub x: P,
    /// Unit y axis (towards parameter π/2).
    pub y: P,
}

impl From<Frame> for CurveFrame<Vec3> {
    fn from(f: Frame) -> Self {
        Self {
            origin: f.origin,
            x: f.x,
            y: f.y,
        }
    }
}

/// A parametric curve. Each variant's parameterisation `C(t)` is given in its doc.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve<P> {
    /// `C(t) = origin + t · direction` (direction keeps the STEP vector's magnitude).
    Line {
        /// A point on the line (t = 0).
        origin: P,
        /// Direction scaled by the STEP vector magnitude.
        direction: P,
    },
    /// `C(t) = o + r (cos t · x + sin t · y)`.
    Circle {
        /// Centre and axes.
        frame: CurveFrame<P>,
        /// Radius (> 0).
        radius: f64,
    },
    /// `C(t) = o + a cos t · x + b sin t · y`.
    Ellipse {
        /// Centre and axes.
        frame: CurveFrame<P>,
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
    },
    /// `C(t) = o + f (t² · x + 2t · y)` (focal distance `f`).
    Parabola {
        /// Apex and axes.
        frame: CurveFrame<P>,
        /// Focal distance.
        focal: f64,
    },
    /// `C(t) = o + a cosh t · x + b sinh t · y`.
    Hyperbola {
        /// Centre and axes.
        frame: CurveFrame<P>,
        /// Real semi-axis.
        a: f64,
        /// Imaginary semi-axis.
        b: f64,
    },
    /// Straight segments; segment `i` has parameter `t ∈ [i, i+1]` (t from 0 to n−1).
    Polyline(Vec<P>),
    /// A B-spline (also Bézier, uniform, quasi-uniform and rational forms).
    BSpline(BSplineCurve<P>),
    /// The basis curve restricted to `[t0, t1]`; when `sense` is false the curve runs from
    /// `t1` to `t0` — its own parameter is still the basis parameter.
    Trimmed {
        /// Underlying curve.
        basis: Box<Curve<P>>,
        /// First parameter.
        t0: f64,
        /// Second parameter.
        t1: f64,
        /// Whether the curve runs from `t0` towards `t1` (STEP `sense_agreement`).
        sense: bool,
    },
    /// Segments joined end to end; segment `k` occupies parameters `[k, k+1]` after
    /// normalising its own range (ISO 10303-42 composite curve parameterisation).
    Composite(Vec<CompositeSegment<P>>),
    /// `C(t) = B(t) + d · N(t)`; in 3D `N = normalize(B'(t) × ref_direction)`, in 2D the left
    /// normal of the tangent.
    Offset {
        /// The curve offset.
        basis: Box<Curve<P>>,
        /// Signed offset distance.
        distance: f64,
        /// Reference direction (3D only; ignored in 2D).
        ref_direction: Vec3,
    },
}

/// One segment of a [`Curve::Composite`].
#[derive(Clone, Debug, PartialEq)]
pub struct CompositeSegment<P> {
    /// The segment's curve (usually bounded: trimmed, B-spline, polyline).
    pub curve: Curve<P>,
    /// Whether the segment is traversed in its own direction.
    pub same_sense: bool,
}

impl<P> Curve<P> {
    /// The STEP-style type name of the curve's kind, as reports show it.
    pub fn type_name(&self) -> &'static str {
        match self {
            Curve::Line { .. } => "Line",
            Curve::Circle { .. } => "Circle",
            Curve::Ellipse { .. } => "Ellipse",
            Curve::Parabola { .. } => "Parabola",
            Curve::Hyperbola { .. } => "Hyperbola",
            Curve::Polyline(_) => "Polyline",
            Curve::BSpline(_) => "BSplineCurve",
            Curve::Trimmed { .. } => "TrimmedCurve",
            Curve::Composite(_) => "CompositeCurve",
            Curve::Offset { .. } => "OffsetCurve",
        }
    }
}
