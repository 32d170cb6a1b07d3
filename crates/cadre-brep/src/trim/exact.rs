//! Exact (u, v) images of 3D edge curves, where the surface makes them simple: on a plane
//! every curve maps affinely (lines to lines, circles to circles, B-splines to B-splines with
//! the same knots and weights); on other surfaces, curves whose (u, v) moves linearly with
//! their parameter (iso-curves: a cylinder's rulings and coaxial circles, a sphere's parallels
//! and meridians, a torus's circles) map to (u, v) lines, found and verified by
//! [`linear_image`].

use cadre_geom::curve::CurveFrame;
use cadre_geom::{BSplineCurve, Curve, Curve2, Curve3, Frame, Surface, Vec2, Vec3};

/// The exact image in (u, v) of a 3D curve lying on `surface`, when it has a closed form.
pub(super) fn image(surface: &Surface, curve: &Curve3) -> Option<Curve2> {
    match surface {
        Surface::Plane { frame } => plane_image(frame, curve),
        _ => None,
    }
}

/// The (u, v) line through `uv0` at `t0` and `uv1` at `t1` (two points of the edge, unwrapped
/// so the line runs the way the edge does; inner ones, since an end at a pole has no u), when
/// `surface` along it is `curve` over the edge's range `range`: checked at nine inner
/// parameters to `tol`. `None` where the image is not linear (an ellipse on a cylinder, a
/// meridian across a pole).
pub(super) fn linear_image(
    surface: &Surface,
    curve: &Curve3,
    (t0, uv0): (f64, Vec2),
    (t1, uv1): (f64, Vec2),
    range: (f64, f64),
    tol: f64,
) -> Option<Curve2> {
    if matches!(surface, Surface::Plane { .. }) || !(t1 - t0).is_normal() {
        return None;
    }
    let direction = (uv1 - uv0) / (t1 - t0);
    let origin = uv0 - direction * t0;
    let (t0, t1) = range;
    if !(direction.is_finite() && origin.is_finite()) {
        return None;
    }
    let on_surface = (1..10).all(|k| {
        let t = t0 + (t1 - t0) * k as f64 / 10.0;
        let uv = origin + direction * t;
        (surface.eval(uv.x, uv.y) - curve.eval(t)).length() <= tol
    });
    on_surface.then_some(Curve::Line { origin, direction })
}

fn local(frame: &Frame, p: Vec3) -> Vec2 {
    let q = frame.to_local(p);
    Vec2::new(q.x, q.y)
}

fn dir(frame: &Frame, d: Vec3) -> Vec2 {
    Vec2::new(d.dot(frame.x), d.dot(frame.y))
}

fn plane_frame(frame: &Frame, f: &CurveFrame<Vec3>) -> CurveFrame<Vec2> {
    CurveFrame {
        origin: local(frame, f.origin),
        x: dir(frame, f.x),
        y: dir(frame, f.y),
    }
}

/// Affine image on a plane (`frame` gives the plane's u and v axes).
fn plane_image(frame: &Frame, curve: &Curve3) -> Option<Curve2> {
    Some(match curve {
        Curve::Line { origin, direction } => Curve::Line {
            origin: local(frame, *origin),
            direction: dir(frame, *direction),
        },
        Curve::Circle { frame: f, radius } => Curve::Circle {
            frame: plane_frame(frame, f),
            radius: *radius,
        },
        Curve::Ellipse { frame: f, a, b } => Curve::Ellipse {
            frame: plane_frame(frame, f),
            a: *a,
            b: *b,
        },
        Curve::Parabola { frame: f, focal } => Curve::Parabola {
            frame: plane_frame(frame, f),
            focal: *focal,
        },
        Curve::Hyperbola { frame: f, a, b } => Curve::Hyperbola {
            frame: plane_frame(frame, f),
            a: *a,
            b: *b,
        },
        Curve::Polyline(points) => {
            Curve::Polyline(points.iter().map(|p| local(frame, *p)).collect())
        }
        Curve::BSpline(b) => Curve::BSpline(BSplineCurve {
            degree: b.degree,
            knots: b.knots.clone(),
            control_points: b.control_points.iter().map(|p| local(frame, *p)).collect(),
            weights: b.weights.clone(),
            closed: b.closed,
        }),
        Curve::Trimmed {
            basis,
            t0,
            t1,
            sense,
        } => Curve::Trimmed {
            basis: Box::new(plane_image(frame, basis)?),
            t0: *t0,
            t1: *t1,
            sense: *sense,
        },
        // Composite and offset curves keep their sampled polyline.
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_on_a_tilted_plane_maps_to_a_circle_through_the_same_points() {
        let frame = Frame::from_axis(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, 1.0),
            Some(Vec3::new(1.0, 1.0, 0.0)),
        )
        .unwrap();
        let plane = Surface::Plane { frame };
        let circle = Curve::Circle {
            frame: CurveFrame {
                origin: Vec3::new(4.0, 2.0, 3.0),
                x: frame.y,
                y: -frame.x,
            },
            radius: 2.5,
        };
        let img = image(&plane, &circle).unwrap();
        for i in 0..12 {
            let t = i as f64 * 0.5;
            let uv = img.eval(t);
            let p = plane.eval(uv.x, uv.y);
            assert!((p - circle.eval(t)).length() < 1e-12, "t={t}");
        }
    }

    #[test]
    fn iso_curves_of_curved_surfaces_map_to_lines() {
        let cylinder = Surface::Cylinder {
            frame: Frame::WORLD,
            radius: 2.0,
        };
        // A coaxial circle at height 3, run clockwise seen from +z.
        let circle = Curve::Circle {
            frame: CurveFrame {
                origin: Vec3::new(0.0, 0.0, 3.0),
                x: Vec3::X,
                y: -Vec3::Y,
            },
            radius: 2.0,
        };
        let uv = |t: f64| Vec2::new(-t, 3.0);
        let img = linear_image(
            &cylinder,
            &circle,
            (0.5, uv(0.5)),
            (2.0, uv(2.0)),
            (0.5, 2.0),
            1e-9,
        )
        .unwrap();
        for t in [0.5, 1.0, 1.7, 2.0] {
            let q = img.eval(t);
            assert!((cylinder.eval(q.x, q.y) - circle.eval(t)).length() < 1e-12);
        }
        // An ellipse on the cylinder (an oblique section) is not linear in (u, v).
        let ellipse = Curve::Ellipse {
            frame: CurveFrame {
                origin: Vec3::ZERO,
                x: Vec3::new(1.0, 0.0, 1.0).normalize(),
                y: Vec3::Y,
            },
            a: 2.0 * std::f64::consts::SQRT_2,
            b: 2.0,
        };
        let end = |t: f64| {
            let (u, v) = cylinder
                .project(ellipse.eval(t), None, Default::default())
                .unwrap();
            Vec2::new(u, v)
        };
        let fit = linear_image(
            &cylinder,
            &ellipse,
            (0.2, end(0.2)),
            (1.2, end(1.2)),
            (0.2, 1.2),
            1e-6,
        );
        assert!(fit.is_none());
        // A sphere's meridian is linear in v up to the pole, not across it.
        let sphere = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 1.0,
        };
        let meridian = Curve::Circle {
            frame: CurveFrame {
                origin: Vec3::ZERO,
                x: Vec3::X,
                y: Vec3::Z,
            },
            radius: 1.0,
        };
        let below = linear_image(
            &sphere,
            &meridian,
            (0.0, Vec2::new(0.0, 0.0)),
            (1.0, Vec2::new(0.0, 1.0)),
            (0.0, 1.0),
            1e-9,
        );
        assert!(below.is_some());
        let across = linear_image(
            &sphere,
            &meridian,
            (1.0, Vec2::new(0.0, 1.0)),
            (
                2.5,
                Vec2::new(std::f64::consts::PI, std::f64::consts::PI - 2.5),
            ),
            (1.0, 2.5),
            1e-9,
        );
        assert!(across.is_none());
    }
}
