//! Circles, cylinders and spheres written as B-splines, recognised from points of the
//! curve or surface. Many exporters write every surface as a B-spline (I-DEAS, some CATIA
//! and Creo settings, mesh-to-B-Rep converters): a drilled hole is then a rational
//! B-spline whose radius a panel or a radius tool could not give. Here the shape is found
//! from a few points (a circle through three, a sphere through four, a cylinder's axis
//! from the normals) and every sample is checked against it: the answer holds within the
//! tolerance at all of them, or there is none.

use cadre_geom::Vec3;

use super::Axis;

/// A circle found through points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Its centre.
    pub centre: Vec3,
    /// Unit normal of its plane.
    pub normal: Vec3,
    /// Its radius.
    pub radius: f64,
    /// The farthest any point lies from it.
    pub deviation: f64,
}

/// A cylinder or a sphere found through points and their normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RoundSurface {
    /// A circular cylinder.
    Cylinder {
        /// Its axis (the origin: the axis point nearest the first sample).
        axis: Axis,
        /// Its radius.
        radius: f64,
        /// The farthest any point lies from it.
        deviation: f64,
    },
    /// A sphere.
    Sphere {
        /// Its centre.
        centre: Vec3,
        /// Its radius.
        radius: f64,
        /// The farthest any point lies from it.
        deviation: f64,
    },
}

/// Normals may stray from the shape's by this angle (radians) at the samples.
const NORMAL_TOLERANCE: f64 = 1e-6;

/// The circle through `a`, `b`, `c`; `None` when they are (nearly) on a line.
fn circumcircle(a: Vec3, b: Vec3, c: Vec3) -> Option<(Vec3, Vec3, f64)> {
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(ac);
    let n2 = n.length_squared();
    let scale = ab.length_squared().max(ac.length_squared());
    if n2 <= 1e-18 * scale * scale || !n2.is_finite() {
        return None;
    }
    let centre =
        a + (n.cross(ab) * ac.length_squared() + ac.cross(n) * ab.length_squared()) / (2.0 * n2);
    Some((centre, n / n2.sqrt(), centre.distance(a)))
}

/// Three of `points` spread along them: the first and those a third and two thirds along
/// (a closed curve's last point is its first).
fn spread3(points: &[Vec3]) -> Option<(Vec3, Vec3, Vec3)> {
    let n = points.len();
    (n >= 3).then(|| (points[0], points[n / 3], points[2 * n / 3]))
}

/// The circle all `points` lie on within `tolerance`, if there is one.
pub fn circle_through(points: &[Vec3], tolerance: f64) -> Option<Circle> {
    let (a, b, c) = spread3(points)?;
    let (centre, normal, radius) = circumcircle(a, b, c)?;
    let deviation = points
        .iter()
        .map(|p| {
            let d = *p - centre;
            let off_plane = d.dot(normal);
            let in_plane = (d - normal * off_plane).length();
            off_plane.abs().max((in_plane - radius).abs())
        })
        .fold(0.0, f64::max);
    (deviation <= tolerance).then_some(Circle {
        centre,
        normal,
        radius,
        deviation,
    })
}

/// The cylinder or sphere all `samples` (points and unit normals) lie on within
/// `tolerance`, their normals radial, if there is one; a cylinder is tried first (a sphere's
/// normals do not all lie in one plane).
pub fn round_surface_through(samples: &[(Vec3, Vec3)], tolerance: f64) -> Option<RoundSurface> {
    if samples.len() < 4 {
        return None;
    }
    cylinder_through(samples, tolerance).or_else(|| sphere_through(samples, tolerance))
}

fn cylinder_through(samples: &[(Vec3, Vec3)], tolerance: f64) -> Option<RoundSurface> {
    // The axis: normal to every normal; from the pair of normals farthest from parallel.
    let first = samples[0].1;
    let other = samples.iter().map(|s| s.1).max_by(|p, q| {
        first
            .cross(*p)
            .length()
            .total_cmp(&first.cross(*q).length())
    })?;
    let direction = first.cross(other).try_normalize()?;
    if samples
        .iter()
        .any(|(_, n)| n.dot(direction).abs() > NORMAL_TOLERANCE)
    {
        return None;
    }
    // The circle through the points taken along the axis into one plane.
    let flat: Vec<Vec3> = samples
        .iter()
        .map(|(p, _)| *p - direction * (*p - samples[0].0).dot(direction))
        .collect();
    let (a, b, c) = farthest_triple(&flat)?;
    let (centre, _, radius) = circumcircle(a, b, c)?;
    let deviation = radial_deviation(
        samples
            .iter()
            .zip(&flat)
            .map(|((_, n), q)| (*q - centre, *n)),
        radius,
    )?;
    (deviation <= tolerance).then_some(RoundSurface::Cylinder {
        axis: Axis {
            origin: centre,
            direction,
        },
        radius,
        deviation,
    })
}

fn sphere_through(samples: &[(Vec3, Vec3)], tolerance: f64) -> Option<RoundSurface> {
    // The centre: on every normal line; from the first sample's and the one whose normal
    // turns most from it, the nearest points of their two lines.
    let (p0, n0) = samples[0];
    let &(p1, n1) = samples
        .iter()
        .max_by(|a, b| n0.cross(a.1).length().total_cmp(&n0.cross(b.1).length()))?;
    let w = p0 - p1;
    let (b, d, e) = (n0.dot(n1), n0.dot(w), n1.dot(w));
    let denom = 1.0 - b * b;
    if denom <= 1e-12 {
        return None;
    }
    let s = (b * e - d) / denom;
    let t = (e - b * d) / denom;
    let centre = 0.5 * ((p0 + n0 * s) + (p1 + n1 * t));
    let radius = centre.distance(p0);
    if radius <= 0.0 || !radius.is_finite() {
        return None;
    }
    let deviation = radial_deviation(samples.iter().map(|(p, n)| (*p - centre, *n)), radius)?;
    (deviation <= tolerance).then_some(RoundSurface::Sphere {
        centre,
        radius,
        deviation,
    })
}

/// The farthest that points (given from the centre, or the axis) lie from the `radius`;
/// `None` when one's normal is not radial (within the square root of [`NORMAL_TOLERANCE`],
/// the angle the normals of a point a rounding off the shape may take) or one is at the
/// centre.
fn radial_deviation(from_centre: impl Iterator<Item = (Vec3, Vec3)>, radius: f64) -> Option<f64> {
    let mut deviation = 0.0f64;
    for (out, normal) in from_centre {
        deviation = deviation.max((out.length() - radius).abs());
        if out.try_normalize()?.cross(normal).length() > NORMAL_TOLERANCE.sqrt() {
            return None;
        }
    }
    Some(deviation)
}

/// Three of `points` far apart: the first, the farthest from it, and the farthest from the
/// line through those two (a cylinder's face seen along its axis may cover a small arc).
fn farthest_triple(points: &[Vec3]) -> Option<(Vec3, Vec3, Vec3)> {
    let a = *points.first()?;
    let b = *points
        .iter()
        .max_by(|p, q| a.distance(**p).total_cmp(&a.distance(**q)))?;
    let along = (b - a).try_normalize()?;
    let c = *points.iter().max_by(|p, q| {
        let off = |x: Vec3| {
            let d = x - a;
            (d - along * d.dot(along)).length()
        };
        off(**p).total_cmp(&off(**q))
    })?;
    Some((a, b, c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(centre: Vec3, r: f64, from: f64, to: f64, n: usize) -> Vec<Vec3> {
        (0..=n)
            .map(|k| {
                let t = from + (to - from) * k as f64 / n as f64;
                centre + Vec3::new(r * t.cos(), 0.0, r * t.sin())
            })
            .collect()
    }

    #[test]
    fn a_circle_is_found_through_its_points_and_a_wobble_is_refused() {
        let points = arc(Vec3::new(1.0, 2.0, 3.0), 4.0, 0.2, 2.0, 20);
        let c = circle_through(&points, 1e-9).expect("a circle");
        assert!(c.centre.distance(Vec3::new(1.0, 2.0, 3.0)) < 1e-9);
        assert!((c.radius - 4.0).abs() < 1e-9);
        assert!(c.normal.cross(Vec3::Y).length() < 1e-9);
        // Negative controls: one point 0.01 off the circle, or off its plane; a line.
        let mut off = points.clone();
        let out = (off[5] - Vec3::new(1.0, 2.0, 3.0)).normalize();
        off[5] += out * 0.01;
        assert!(circle_through(&off, 1e-6).is_none());
        assert!(
            circle_through(&off, 0.02).is_some(),
            "within a coarser tolerance"
        );
        let mut lifted = points.clone();
        lifted[12].y += 0.01;
        assert!(circle_through(&lifted, 1e-6).is_none());
        let line: Vec<Vec3> = (0..10).map(|k| Vec3::X * k as f64).collect();
        assert!(circle_through(&line, 1e-6).is_none());
    }

    #[test]
    fn a_cylinder_and_a_sphere_are_told_apart_and_found() {
        // A quarter of a cylinder of radius 2 about the axis through (5, 0, 0) along y.
        let mut cylinder = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                let t = 1.5 * i as f64 / 4.0;
                let n = Vec3::new(t.cos(), 0.0, t.sin());
                cylinder.push((Vec3::new(5.0, j as f64, 0.0) + n * 2.0, n));
            }
        }
        match round_surface_through(&cylinder, 1e-9) {
            Some(RoundSurface::Cylinder { axis, radius, .. }) => {
                assert!((radius - 2.0).abs() < 1e-9);
                assert!(axis.direction.cross(Vec3::Y).length() < 1e-9);
                let d = axis.origin - Vec3::new(5.0, 0.0, 0.0);
                assert!((d - axis.direction * d.dot(axis.direction)).length() < 1e-9);
            }
            other => panic!("{other:?}"),
        }
        // A patch of a sphere of radius 3 about (1, 1, 1).
        let mut sphere = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                let (a, b) = (0.3 * i as f64, 0.2 + 0.25 * j as f64);
                let n = Vec3::new(a.cos() * b.cos(), a.sin() * b.cos(), b.sin());
                sphere.push((Vec3::ONE + n * 3.0, n));
            }
        }
        match round_surface_through(&sphere, 1e-9) {
            Some(RoundSurface::Sphere { centre, radius, .. }) => {
                assert!(centre.distance(Vec3::ONE) < 1e-9);
                assert!((radius - 3.0).abs() < 1e-9);
            }
            other => panic!("{other:?}"),
        }
        // Negative controls: a plane's samples, an elliptic cylinder's.
        let plane: Vec<(Vec3, Vec3)> = (0..25)
            .map(|k| (Vec3::new((k % 5) as f64, (k / 5) as f64, 0.0), Vec3::Z))
            .collect();
        assert_eq!(round_surface_through(&plane, 1e-6), None);
        let ellipse: Vec<(Vec3, Vec3)> = (0..25)
            .map(|k| {
                let t = 1.5 * (k % 5) as f64 / 4.0;
                let n = Vec3::new(t.cos() / 2.0, 0.0, t.sin()).normalize();
                (Vec3::new(2.0 * t.cos(), (k / 5) as f64, t.sin()), n)
            })
            .collect();
        assert_eq!(round_surface_through(&ellipse, 1e-6), None);
    }
}
