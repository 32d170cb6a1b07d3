//! Rational and polynomial B-spline curves and surfaces (STEP's `B_SPLINE_*_WITH_KNOTS`,
//! Bézier and uniform forms, rational forms given as complex instances).
//!
//! Knots are stored expanded (each value repeated by its multiplicity), the classic
//! `n + p + 1` layout. Weights are `None` for polynomial splines.

use crate::{Vec2, Vec3};

/// Why a B-spline's definition is not usable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KnotError {
    /// Degree zero, or too large for the number of control points.
    #[error("degree {degree} does not fit {control_points} control points")]
    Degree {
        /// The degree given.
        degree: usize,
        /// The number of control points.
        control_points: usize,
    },
    /// Expanded knot count is not `control_points + degree + 1`.
    #[error(
        "{knots} knots for {control_points} control points of degree {degree} (expected {expected})"
    )]
    KnotCount {
        /// Knots after expansion.
        knots: usize,
        /// Number of control points.
        control_points: usize,
        /// Degree.
        degree: usize,
        /// The count expected.
        expected: usize,
    },
    /// Knots decrease somewhere, or are not finite.
    #[error("knot vector is not non-decreasing finite numbers")]
    KnotOrder,
    /// Knot values and multiplicities lists differ in length, or a multiplicity is zero.
    #[error("knot multiplicities do not match knot values")]
    Multiplicities,
    /// Weights count differs from control points, or a weight is not positive and finite.
    #[error("weights must be positive, finite, one per control point")]
    Weights,
    /// A control point is not finite.
    #[error("control point is not finite")]
    ControlPoint,
    /// Control net rows differ in length (surfaces).
    #[error("control net is not rectangular")]
    Net,
}

/// Expands STEP's (knot values, multiplicities) pair into a flat knot vector.
pub fn expand_knots(values: &[f64], multiplicities: &[usize]) -> Result<Vec<f64>, KnotError> {
    if values.len() != multiplicities.len() || multiplicities.contains(&0) {
        return Err(KnotError::Multiplicities);
    }
    let total: usize = multiplicities.iter().sum();
    let mut knots = Vec::with_capacity(total);
    for (&v, &m) in values.iter().zip(multiplicities) {
        knots.extend(std::iter::repeat_n(v, m));
    }
    Ok(knots)
}

fn check_knots(knots: &[f64], n: usize, degree: usize) -> Result<(), KnotError> {
    if degree == 0 || n <= degree {
        return Err(KnotError::Degree {
            degree,
            control_points: n,
        });
    }
    let expected = n + degree + 1;
    if knots.len() != expected {
        return Err(KnotError::KnotCount {
            knots: knots.len(),
            control_points: n,
            degree,
            expected,
        });
    }
    if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
        return Err(KnotError::KnotOrder);
    }
    if knots[degree] >= knots[n] {
        return Err(KnotError::KnotOrder);
    }
    Ok(())
}

fn check_weights(weights: &Option<Vec<f64>>, n: usize) -> Result<(), KnotError> {
    if let Some(w) = weights
        && (w.len() != n || w.iter().any(|w| !(w.is_finite() && *w > 0.0)))
    {
        return Err(KnotError::Weights);
    }
    Ok(())
}

/// A (possibly rational) B-spline curve with control points of type `P`
/// ([`Vec3`] in model space, [`Vec2`] in a surface's parameter space).
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve<P> {
    /// Polynomial degree (≥ 1).
    pub degree: usize,
    /// Expanded knot vector, `control_points.len() + degree + 1` values, non-decreasing.
    pub knots: Vec<f64>,
    /// Control points.
    pub control_points: Vec<P>,
    /// One positive weight per control point, or `None` when polynomial.
    pub weights: Option<Vec<f64>>,
    /// Whether the curve is closed and evaluated as periodic: parameters outside the domain
    /// wrap into it, and [`Curve::period`](crate::Curve::period) is the domain's length.
    /// Readers set it where the ends meet ([`BSplineCurve::ends_meet`]), not from a file's
    /// flag (files flag closed curves open: trj5_k1-md-203.stp).
    pub closed: bool,
}

/// Control points a B-spline may have: finite checks shared by 2D and 3D.
pub trait ControlPoint: Copy {
    /// Whether every coordinate is finite.
    fn finite(&self) -> bool;
}
impl ControlPoint for Vec3 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}
impl ControlPoint for Vec2 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl<P: ControlPoint> BSplineCurve<P> {
    /// Builds a curve after checking degree, knot count and order, weights and points.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        control_points: Vec<P>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self, KnotError> {
        check_knots(&knots, control_points.len(), degree)?;
        check_weights(&weights, control_points.len())?;
        if control_points.iter().any(|p| !p.finite()) {
            return Err(KnotError::ControlPoint);
        }
        Ok(Self {
            degree,
            knots,
            control_points,
            weights,
            closed: false,
        })
    }

    /// A Bézier curve: one span, clamped knots on [0, 1].
    pub fn bezier(control_points: Vec<P>, weights: Option<Vec<f64>>) -> Result<Self, KnotError> {
        let n = control_points.len();
        let degree = n.saturating_sub(1);
        let mut knots = vec![0.0; n];
        knots.extend(std::iter::repeat_n(1.0, n));
        Self::try_new(degree, knots, control_points, weights)
    }

    /// The parameter range `[knots[degree], knots[n]]` on which the curve is defined.
    pub fn domain(&self) -> (f64, f64) {
        (
            self.knots[self.degree],
            self.knots[self.control_points.len()],
        )
    }
}

/// A (possibly rational) tensor-product B-spline surface.
///
/// `control_points[i][j]`: `i` runs along u, `j` along v (STEP's list-of-lists order).
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurface {
    /// Degree in u (≥ 1).
    pub u_degree: usize,
    /// Degree in v (≥ 1).
    pub v_degree: usize,
    /// Expanded knots in u.
    pub u_knots: Vec<f64>,
    /// Expanded knots in v.
    pub v_knots: Vec<f64>,
    /// Control net, rows along u.
    pub control_points: Vec<Vec<Vec3>>,
    /// Weights with the same shape as the net, or `None` when polynomial.
    pub weights: Option<Vec<Vec<f64>>>,
    /// Whether the file declared the surface closed in u.
    pub u_closed: bool,
    /// Whether the file declared the surface closed in v.
    pub v_closed: bool,
}

impl BSplineSurface {
    /// Builds a surface after checking degrees, knots, the net's shape, weights and points.
    pub fn try_new(
        u_degree: usize,
        v_degree: usize,
        u_knots: Vec<f64>,
        v_knots: Vec<f64>,
        control_points: Vec<Vec<Vec3>>,
        weights: Option<Vec<Vec<f64>>>,
    ) -> Result<Self, KnotError> {
        let nu = control_points.len();
        let nv = control_points.first().map_or(0, Vec::len);
        if control_points.iter().any(|row| row.len() != nv) {
            return Err(KnotError::Net);
        }
        check_knots(&u_knots, nu, u_degree)?;
        check_knots(&v_knots, nv, v_degree)?;
        if let Some(w) = &weights {
            if w.len() != nu {
                return Err(KnotError::Weights);
            }
            for row in w {
                check_weights(&Some(row.clone()), nv)?;
            }
        }
        if control_points.iter().flatten().any(|p| !p.is_finite()) {
            return Err(KnotError::ControlPoint);
        }
        Ok(Self {
            u_degree,
            v_degree,
            u_knots,
            v_knots,
            control_points,
            weights,
            u_closed: false,
            v_closed: false,
        })
    }

    /// A Bézier patch: one span in each direction on [0, 1]².
    pub fn bezier(
        control_points: Vec<Vec<Vec3>>,
        weights: Option<Vec<Vec<f64>>>,
    ) -> Result<Self, KnotError> {
        let nu = control_points.len();
        let nv = control_points.first().map_or(0, Vec::len);
        let clamp = |n: usize| {
            let mut k = vec![0.0; n];
            k.extend(std::iter::repeat_n(1.0, n));
            k
        };
        Self::try_new(
            nu.saturating_sub(1),
            nv.saturating_sub(1),
            clamp(nu),
            clamp(nv),
            control_points,
            weights,
        )
    }

    /// The parameter rectangle `((u0, u1), (v0, v1))` on which the surface is defined.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        let nu = self.control_points.len();
        let nv = self.control_points[0].len();
        (
            (self.u_knots[self.u_degree], self.u_knots[nu]),
            (self.v_knots[self.v_degree], self.v_knots[nv]),
        )
    }
}
