//! Crease lines: parameters where a curve or surface may turn a corner (only C0), so that
//! normal-angle tests in tessellators do not try to smooth them away by refining.
//!
//! trj5_k1-al-214.stp has a degree-1 B-spline strip of 20 bilinear spans: every interior knot
//! is a crease, and refining for the angular deflection across them down to the minimum
//! triangle size gave one face 17,142 triangles (OCCT: a few hundred).

use crate::bspline::{BSplineCurve, BSplineSurface};
use crate::curve::Curve;
use crate::point::GeomPoint;
use crate::surface::Surface;

/// Distinct interior values of an expanded knot vector repeated at least `degree` times:
/// where a B-spline of that degree is only C0.
fn c0_knots(knots: &[f64], degree: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let (Some(&first), Some(&last)) = (knots.first(), knots.last()) else {
        return out;
    };
    let mut i = 0;
    while i < knots.len() {
        let k = knots[i];
        let mut j = i;
        while j < knots.len() && knots[j] == k {
            j += 1;
        }
        if j - i >= degree.max(1) && k > first && k < last {
            out.push(k);
        }
        i = j;
    }
    out
}

impl<P: GeomPoint> BSplineCurve<P> {
    /// Interior knots where the curve is only C0 (multiplicity ≥ degree).
    pub fn creases(&self) -> Vec<f64> {
        c0_knots(&self.knots, self.degree)
    }
}

impl BSplineSurface {
    /// Interior knot lines where the surface is only C0: u values, then v values.
    pub fn creases(&self) -> (Vec<f64>, Vec<f64>) {
        (
            c0_knots(&self.u_knots, self.u_degree),
            c0_knots(&self.v_knots, self.v_degree),
        )
    }
}

impl<P: GeomPoint> Curve<P> {
    /// Parameters, increasing, where the curve may turn a corner: C0 knots of B-splines,
    /// polyline vertices, composite joints. Empty for smooth curves.
    pub fn creases(&self) -> Vec<f64> {
        match self {
            Curve::BSpline(b) => b.creases(),
            Curve::Trimmed { basis, .. } | Curve::Offset { basis, .. } => basis.creases(),
            Curve::Polyline(points) => (1..points.len().saturating_sub(1))
                .map(|i| i as f64)
                .collect(),
            Curve::Composite(segs) => (1..segs.len()).map(|i| i as f64).collect(),
            _ => Vec::new(),
        }
    }
}

impl Surface {
    /// Lines of constant u, then of constant v, where the surface may turn a corner (only C0):
    /// B-spline knot lines of full multiplicity, and the corners of swept profiles. Empty for
    /// analytic surfaces.
    pub fn creases(&self) -> (Vec<f64>, Vec<f64>) {
        match self {
            Surface::BSpline(b) => b.creases(),
            Surface::Revolution { profile, .. } => (Vec::new(), profile.creases()),
            Surface::Extrusion { profile, .. } => (profile.creases(), Vec::new()),
            Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => basis.creases(),
            _ => (Vec::new(), Vec::new()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    #[test]
    fn full_multiplicity_interior_knots_are_creases() {
        assert_eq!(c0_knots(&[0.0, 0.0, 1.0, 2.0, 3.0, 3.0], 1), vec![1.0, 2.0]);
        assert_eq!(
            c0_knots(&[0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 3.0, 3.0, 3.0], 2),
            vec![2.0]
        );
        assert!(c0_knots(&[0.0; 4], 3).is_empty());
        assert!(c0_knots(&[], 3).is_empty());
    }

    #[test]
    fn a_bilinear_strip_creases_at_every_interior_knot_in_v_only() {
        let net = vec![
            (0..4)
                .map(|j| Vec3::new(0.0, j as f64, (j % 2) as f64))
                .collect(),
            (0..4)
                .map(|j| Vec3::new(1.0, j as f64, (j % 2) as f64))
                .collect(),
        ];
        let s = BSplineSurface::try_new(
            1,
            1,
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 2.0, 3.0, 3.0],
            net,
            None,
        )
        .unwrap();
        assert_eq!(
            Surface::BSpline(Box::new(s)).creases(),
            (vec![], vec![1.0, 2.0])
        );
        let smooth = Surface::Sphere {
            frame: crate::Frame::WORLD,
            radius: 1.0,
        };
        assert_eq!(smooth.creases(), (vec![], vec![]));
    }
}
