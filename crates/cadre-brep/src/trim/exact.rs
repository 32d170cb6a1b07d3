//! Exact (u, v) images of 3D edge curves, where the surface makes them simple: on a plane
//! every curve maps affinely (lines to lines, circles to circles, B-splines to B-splines with
//! the same knots and weights).

use cadre_geom::curve::CurveFrame;
use cadre_geom::{BSplineCurve, Curve, Curve2, Curve3, Frame, Surface, Vec2, Vec3};

/// The exact image in (u, v) of a 3D curve lying on `surface`, when it has a closed form.
pub(super) fn image(surface: &Surface, curve: &Curve3) -> Option<Curve2> {
    match surface {
        Surface::Plane { frame } => plane_image(frame, curve),
        _ => None,
    }
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
}
