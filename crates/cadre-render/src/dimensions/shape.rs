//! What a dimension is drawn with, from its kind and points: the lines (dimension line,
//! arc, legs, centre mark), the arrowheads and the point its label stands at. The points
//! each kind keeps ([`super::Dimension::points`], world coordinates):
//!
//! - `distance`: the two ends `[a, b]`: a dimension line between them;
//! - `length`: the measured edge's points in order: the edge drawn over, arrowheads at its
//!   ends;
//! - `radius`: `[centre, at]` or `[centre, at, centre + axis]`: a line from the centre to
//!   the point `at` on the circle or surface with an arrowhead there, and a centre mark (in
//!   the circle's plane when the axis is given);
//! - `angle`: `[vertex, a, b]`: an arc about the vertex from `a` to `b` (both at the same
//!   distance from it) with an arrowhead at each end, and the legs from the vertex to the
//!   arc's ends. An angle kept with two points (the picked points, as files written before
//!   had it) has no arc: its label stands at their middle.
//!
//! Anything else, or points that are not finite, draws no lines; a dimension without a
//! point to stand at draws nothing (the viewer lists it).

use glam::DVec3;

/// An arrowhead: its tip, the unit direction it points to, and the unit side its base
/// spreads along.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrow {
    /// The tip.
    pub tip: DVec3,
    /// Unit direction, from the base to the tip.
    pub pointing: DVec3,
    /// Unit direction across it (the plane it lies in: `pointing` and `side`).
    pub side: DVec3,
    /// Length, model units (its base is a third of it wide).
    pub length: f64,
}

/// The parts a dimension is drawn with.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shape {
    /// Polylines (world points).
    pub lines: Vec<Vec<DVec3>>,
    /// Arrowheads.
    pub arrows: Vec<Arrow>,
    /// Where its label stands, if anywhere.
    pub label_at: Option<DVec3>,
}

/// Arrowheads are this share of the line they end (a twelfth).
const ARROW_SHARE: f64 = 1.0 / 12.0;
/// Arcs are drawn with a segment per this angle at most (radians: 3°).
const ARC_STEP: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// The shape of a dimension of `kind` through `points`.
pub fn shape(kind: &str, points: &[[f64; 3]]) -> Shape {
    let points: Vec<DVec3> = points.iter().map(|&p| DVec3::from(p)).collect();
    if points.iter().any(|p| !p.is_finite()) {
        return Shape::default();
    }
    let shape = match (kind, &points[..]) {
        ("radius", [centre, at, rest @ ..]) => radius(*centre, *at, rest.first().copied()),
        ("angle", [vertex, a, b]) => angle(*vertex, *a, *b),
        ("length", path) if path.len() >= 2 => along(path),
        (_, [a, b]) if kind != "angle" => linear(*a, *b),
        (_, [a, b]) => Shape {
            label_at: Some(0.5 * (*a + *b)),
            ..Shape::default()
        },
        _ => Shape::default(),
    };
    // Finite points far apart (10²³⁶ mm, as a corrupt file may hold) still overflow a length
    // or a direction: such a dimension draws nothing rather than lines to infinity.
    let finite = shape.lines.iter().flatten().all(|p| p.is_finite())
        && shape.arrows.iter().all(|a| {
            a.tip.is_finite()
                && a.pointing.is_finite()
                && a.side.is_finite()
                && a.length.is_finite()
        })
        && shape.label_at.is_none_or(|p| p.is_finite());
    if finite { shape } else { Shape::default() }
}

/// A unit vector across `along` (unit): in the plane normal to `normal` when that is given
/// and not along it, else about the world axis least along it.
fn across(along: DVec3, normal: Option<DVec3>) -> DVec3 {
    if let Some(n) = normal {
        let side = n.cross(along);
        if side.length() > 1e-9 {
            return side.normalize();
        }
    }
    let axis = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .min_by(|p, q| along.dot(*p).abs().total_cmp(&along.dot(*q).abs()))
        .unwrap_or(DVec3::Z);
    along.cross(axis).normalize_or(DVec3::Z)
}

/// A dimension line from `a` to `b`, an arrowhead at each end pointing out to it.
fn linear(a: DVec3, b: DVec3) -> Shape {
    let length = a.distance(b);
    let mut shape = Shape {
        label_at: Some(0.5 * (a + b)),
        ..Shape::default()
    };
    if length > 0.0 {
        let along = (b - a) / length;
        let side = across(along, None);
        shape.lines.push(vec![a, b]);
        for (tip, pointing) in [(a, -along), (b, along)] {
            shape.arrows.push(Arrow {
                tip,
                pointing,
                side,
                length: length * ARROW_SHARE,
            });
        }
    }
    shape
}

/// The path itself, an arrowhead at each end pointing out along it, the label at the
/// middle of its length.
fn along(path: &[DVec3]) -> Shape {
    let total: f64 = path.windows(2).map(|w| w[0].distance(w[1])).sum();
    if total <= 0.0 {
        return Shape {
            label_at: path.first().copied(),
            ..Shape::default()
        };
    }
    // The middle by length.
    let mut left = 0.5 * total;
    let mut middle = path[0];
    for w in path.windows(2) {
        let step = w[0].distance(w[1]);
        if left <= step && step > 0.0 {
            middle = w[0].lerp(w[1], left / step);
            break;
        }
        left -= step;
    }
    // The end directions: the first and last segments that have a length.
    let first = path
        .windows(2)
        .find_map(|w| (w[1] - w[0]).try_normalize())
        .unwrap_or(DVec3::X);
    let last = path
        .windows(2)
        .rev()
        .find_map(|w| (w[1] - w[0]).try_normalize())
        .unwrap_or(DVec3::X);
    // Arrowheads in the plane the path bends in near each end, when it bends.
    let bend = first.cross(last).try_normalize();
    let length = total * ARROW_SHARE;
    Shape {
        lines: vec![path.to_vec()],
        arrows: vec![
            Arrow {
                tip: path[0],
                pointing: -first,
                side: across(-first, bend),
                length,
            },
            Arrow {
                tip: path[path.len() - 1],
                pointing: last,
                side: across(last, bend),
                length,
            },
        ],
        label_at: Some(middle),
    }
}

/// A radius: the line from the centre to `at` with an arrowhead at `at`, and a centre mark
/// (two short crossing lines, in the plane normal to `axis_point − centre` when given).
fn radius(centre: DVec3, at: DVec3, axis_point: Option<DVec3>) -> Shape {
    let r = centre.distance(at);
    let mut shape = Shape {
        label_at: Some(0.5 * (centre + at)),
        ..Shape::default()
    };
    if r <= 0.0 {
        return shape;
    }
    let out = (at - centre) / r;
    let normal = axis_point.and_then(|p| (p - centre).try_normalize());
    let side = across(out, normal);
    shape.lines.push(vec![centre, at]);
    shape.arrows.push(Arrow {
        tip: at,
        pointing: out,
        side,
        length: 0.2 * r,
    });
    // The centre mark: a cross a fifth of the radius across, along and across the line.
    let mark = 0.1 * r;
    shape
        .lines
        .push(vec![centre - out * mark, centre + out * mark]);
    shape
        .lines
        .push(vec![centre - side * mark, centre + side * mark]);
    shape
}

/// An angle: the arc about `vertex` from `a` to `b`, an arrowhead at each end pointing out
/// along it, and the legs from the vertex to its ends.
fn angle(vertex: DVec3, a: DVec3, b: DVec3) -> Shape {
    let (da, db) = (a - vertex, b - vertex);
    let r = da.length();
    let (Some(ua), Some(ub)) = (da.try_normalize(), db.try_normalize()) else {
        return Shape {
            label_at: Some(0.5 * (a + b)),
            ..Shape::default()
        };
    };
    let sweep = ua.dot(ub).clamp(-1.0, 1.0).acos();
    // The arc's plane: a straight angle (or none) has no plane of its own.
    let Some(normal) = ua.cross(ub).try_normalize() else {
        return linear(a, b);
    };
    let v = normal.cross(ua);
    let steps = ((sweep / ARC_STEP).ceil() as usize).clamp(2, 120);
    let arc: Vec<DVec3> = (0..=steps)
        .map(|k| {
            let t = sweep * k as f64 / steps as f64;
            vertex + (ua * t.cos() + v * t.sin()) * r
        })
        .collect();
    let tangent_a = -v;
    let tangent_b = (normal.cross(ub)).normalize();
    let length = (r * sweep / 6.0).min(0.3 * r);
    let middle = vertex + (ua * (0.5 * sweep).cos() + v * (0.5 * sweep).sin()) * r;
    Shape {
        lines: vec![arc, vec![a, vertex, b]],
        arrows: vec![
            Arrow {
                tip: a,
                pointing: tangent_a,
                side: ua,
                length,
            },
            Arrow {
                tip: b,
                pointing: tangent_b,
                side: ub,
                length,
            },
        ],
        label_at: Some(middle),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        a.distance(b) < 1e-9
    }

    #[test]
    fn a_distance_is_a_line_with_an_arrowhead_pointing_out_at_each_end() {
        let s = shape("distance", &[[0.0, 0.0, 0.0], [0.0, 0.0, 12.0]]);
        assert_eq!(s.lines, vec![vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 12.0)]]);
        assert_eq!(s.arrows.len(), 2);
        assert!(close(s.arrows[0].pointing, -DVec3::Z) && close(s.arrows[1].pointing, DVec3::Z));
        assert!((s.arrows[0].length - 1.0).abs() < 1e-12);
        assert!(
            s.arrows
                .iter()
                .all(|a| a.side.dot(a.pointing).abs() < 1e-12)
        );
        assert_eq!(s.label_at, Some(DVec3::new(0.0, 0.0, 6.0)));
    }

    #[test]
    fn a_radius_runs_from_its_centre_to_the_circle_with_a_centre_mark_in_its_plane() {
        // A circle of radius 5 about the z axis, measured at (3, 4, 0).
        let s = shape("radius", &[[0.0; 3], [3.0, 4.0, 0.0], [0.0, 0.0, 1.0]]);
        assert_eq!(s.lines[0], vec![DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0)]);
        assert_eq!(s.arrows.len(), 1, "one arrowhead, on the circle");
        let arrow = s.arrows[0];
        assert!(close(arrow.tip, DVec3::new(3.0, 4.0, 0.0)));
        assert!(close(arrow.pointing, DVec3::new(0.6, 0.8, 0.0)));
        assert!(arrow.side.z.abs() < 1e-12, "in the circle's plane");
        // The centre mark: two lines through the centre, both in the plane z = 0.
        assert_eq!(s.lines.len(), 3);
        for mark in &s.lines[1..] {
            assert!(close(0.5 * (mark[0] + mark[1]), DVec3::ZERO));
            assert!(mark.iter().all(|p| p.z.abs() < 1e-12));
        }
        assert!(close(s.label_at.unwrap(), DVec3::new(1.5, 2.0, 0.0)));
        // Without its axis it still draws; a zero radius only labels.
        assert_eq!(shape("radius", &[[0.0; 3], [3.0, 4.0, 0.0]]).lines.len(), 3);
        assert!(shape("radius", &[[1.0; 3], [1.0; 3]]).lines.is_empty());
    }

    #[test]
    fn an_angle_is_an_arc_between_its_legs_whose_middle_holds_the_label() {
        // 90° in the plane z = 0 about the origin, radius 2.
        let s = shape("angle", &[[0.0; 3], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let arc = &s.lines[0];
        assert!(close(arc[0], DVec3::new(2.0, 0.0, 0.0)));
        assert!(close(*arc.last().unwrap(), DVec3::new(0.0, 2.0, 0.0)));
        assert!(
            arc.iter()
                .all(|p| (p.length() - 2.0).abs() < 1e-12 && p.z.abs() < 1e-12)
        );
        assert!(arc.len() >= 30, "{} points for 90°", arc.len());
        // The legs from the vertex to the arc's ends.
        assert_eq!(
            s.lines[1],
            vec![
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::ZERO,
                DVec3::new(0.0, 2.0, 0.0)
            ]
        );
        // Arrowheads at the ends, pointing out of the arc along its tangent.
        assert!(close(s.arrows[0].pointing, -DVec3::Y));
        assert!(close(s.arrows[1].pointing, -DVec3::X));
        let h = std::f64::consts::SQRT_2;
        assert!(close(s.label_at.unwrap(), DVec3::new(h, h, 0.0)));
        // An angle of two points (files written before arcs) labels their middle only.
        let old = shape("angle", &[[0.0; 3], [2.0, 0.0, 0.0]]);
        assert!(old.lines.is_empty() && old.arrows.is_empty());
        assert_eq!(old.label_at, Some(DVec3::new(1.0, 0.0, 0.0)));
    }

    #[test]
    fn a_length_draws_its_edge_with_arrowheads_out_at_its_ends_and_the_label_halfway() {
        // A quarter circle of radius 10 in 90 points.
        let path: Vec<[f64; 3]> = (0..=90)
            .map(|k| {
                let t = (k as f64).to_radians();
                [10.0 * t.cos(), 10.0 * t.sin(), 0.0]
            })
            .collect();
        let s = shape("length", &path);
        assert_eq!(s.lines[0].len(), 91);
        let h = 10.0 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(s.label_at.unwrap().distance(DVec3::new(h, h, 0.0)) < 1e-3);
        assert!(s.arrows[0].pointing.dot(-DVec3::Y) > 0.99);
        assert!(s.arrows[1].pointing.dot(-DVec3::X) > 0.99);
        assert!(s.arrows.iter().all(|a| a.side.z.abs() < 1e-9));
    }

    #[test]
    fn bad_points_draw_nothing() {
        assert_eq!(
            shape("distance", &[[f64::NAN, 0.0, 0.0], [1.0; 3]]),
            Shape::default()
        );
        assert_eq!(shape("radius", &[]), Shape::default());
        assert_eq!(shape("distance", &[[1.0; 3]]), Shape::default());
        // Finite points whose lengths overflow (found by the `dimension_file` fuzz target: a
        // length along points 10²³⁶ apart got an infinite arrowhead).
        let far = [
            [1.0, 0.0, 0.0],
            [1.4e236, 0.0, 0.0],
            [-1.5e300, 0.0, 0.0],
            [0.0, 1e300, 1.0],
        ];
        for kind in ["length", "distance", "radius", "angle"] {
            let s = shape(kind, &far[..if kind == "angle" { 3 } else { 4 }]);
            assert!(s.lines.iter().flatten().all(|p| p.is_finite()), "{kind}");
            assert!(
                s.arrows
                    .iter()
                    .all(|a| a.length.is_finite() && a.tip.is_finite()),
                "{kind}"
            );
        }
        assert_eq!(shape("length", &far), Shape::default());
        // Negative control: the same kinds with good points draw.
        assert!(!shape("distance", &[[0.0; 3], [1.0; 3]]).lines.is_empty());
        assert!(
            !shape("length", &[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
                .lines
                .is_empty()
        );
    }
}
