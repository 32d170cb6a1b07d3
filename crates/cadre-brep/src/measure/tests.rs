//! Unit tests of the measurements and properties on small hand-built models.

use super::*;
use crate::{Body, StepIndex};
use crate::{CurveId, Loop, OrientedEdge, Part, Shell, ShellId, SurfaceId, Vertex};
use cadre_geom::Frame;
use cadre_geom::curve::CurveFrame;
use std::f64::consts::{FRAC_PI_2, TAU};

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

fn vertex(model: &mut Model, p: Vec3, step_id: u64) -> VertexId {
    model.vertices.push(Vertex { point: p, step_id });
    VertexId(model.vertices.len() as u32 - 1)
}

fn edge(model: &mut Model, curve: Curve3, a: VertexId, b: VertexId, step: u64) -> EdgeId {
    model.curves.push(curve);
    model.edges.push(Edge {
        curve: Some(CurveId(model.curves.len() as u32 - 1)),
        start: a,
        end: b,
        same_sense: true,
        pcurves: Vec::new(),
        step_id: step,
    });
    EdgeId(model.edges.len() as u32 - 1)
}

fn line(a: Vec3, b: Vec3) -> Curve3 {
    Curve::Line {
        origin: a,
        direction: b - a,
    }
}

/// A unit cube [0, 1]³ with its +x and +y faces (and the edge between them), written with
/// the +y face reversed by `same_sense` and the +x face's plane normal pointing inward
/// but the face reversed by its shell, to exercise both flips.
fn two_faces_of_a_box() -> (Model, FaceId, FaceId, EdgeId) {
    let mut m = Model::default();
    let p = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    let v0 = vertex(&mut m, p(1.0, 1.0, 0.0), 10);
    let v1 = vertex(&mut m, p(1.0, 1.0, 1.0), 11);
    let v2 = vertex(&mut m, p(1.0, 0.0, 1.0), 12);
    let v3 = vertex(&mut m, p(1.0, 0.0, 0.0), 13);
    let v4 = vertex(&mut m, p(0.0, 1.0, 1.0), 14);
    let v5 = vertex(&mut m, p(0.0, 1.0, 0.0), 15);
    let shared = edge(&mut m, line(p(1.0, 1.0, 0.0), p(1.0, 1.0, 1.0)), v0, v1, 20);
    let ex1 = edge(&mut m, line(p(1.0, 1.0, 1.0), p(1.0, 0.0, 1.0)), v1, v2, 21);
    let ex2 = edge(&mut m, line(p(1.0, 0.0, 1.0), p(1.0, 0.0, 0.0)), v2, v3, 22);
    let ex3 = edge(&mut m, line(p(1.0, 0.0, 0.0), p(1.0, 1.0, 0.0)), v3, v0, 23);
    let ey1 = edge(&mut m, line(p(1.0, 1.0, 1.0), p(0.0, 1.0, 1.0)), v1, v4, 24);
    let ey2 = edge(&mut m, line(p(0.0, 1.0, 1.0), p(0.0, 1.0, 0.0)), v4, v5, 25);
    let ey3 = edge(&mut m, line(p(0.0, 1.0, 0.0), p(1.0, 1.0, 0.0)), v5, v0, 26);
    // +x face: plane normal −x (inward), face same_sense true, used reversed by the shell.
    // Its loop runs counter-clockwise about −x: v0 → v3 → v2 → v1 → v0.
    let fwd = |edge, forward| OrientedEdge { edge, forward };
    m.surfaces.push(Surface::Plane {
        frame: Frame::from_axis(p(1.0, 0.0, 0.0), -Vec3::X, Some(Vec3::Y)).unwrap(),
    });
    m.faces.push(Face {
        surface: SurfaceId(0),
        same_sense: true,
        loops: vec![Loop {
            kind: LoopKind::Edges(vec![
                fwd(ex3, false),
                fwd(ex2, false),
                fwd(ex1, false),
                fwd(shared, false),
            ]),
            orientation: true,
            outer: true,
        }],
        step_id: 30,
    });
    // +y face: plane normal −y, same_sense false; loop counter-clockwise about +y:
    // v0 → v5 → v4 → v1 → v0.
    m.surfaces.push(Surface::Plane {
        frame: Frame::from_axis(p(0.0, 1.0, 0.0), -Vec3::Y, Some(Vec3::X)).unwrap(),
    });
    m.faces.push(Face {
        surface: SurfaceId(1),
        same_sense: false,
        loops: vec![Loop {
            kind: LoopKind::Edges(vec![
                fwd(ey3, false),
                fwd(ey2, false),
                fwd(ey1, false),
                fwd(shared, false),
            ]),
            orientation: true,
            outer: true,
        }],
        step_id: 31,
    });
    m.shells.push(Shell {
        faces: vec![(FaceId(0), false), (FaceId(1), true)],
        closed: false,
        step_id: 40,
    });
    m.parts.push(Part {
        name: "box".into(),
        bodies: vec![Body::Shell(ShellId(0))],
        ..Part::default()
    });
    (m, FaceId(0), FaceId(1), shared)
}

#[test]
fn box_faces_meet_at_a_right_angle_with_outward_normals() {
    let (m, fx, fy, shared) = two_faces_of_a_box();
    let px = face_properties(&m, fx).unwrap();
    assert_eq!(px.kind, SurfaceKind::Plane);
    assert!(px.reversed);
    assert!((px.plane.unwrap().normal - Vec3::X).length() < 1e-15);
    assert_eq!(
        face_plane(&m, fx),
        px.plane,
        "the plane alone, as the properties give it"
    );
    let py = face_properties(&m, fy).unwrap();
    assert!(py.reversed);
    assert!((py.plane.unwrap().normal - Vec3::Y).length() < 1e-15);
    let a = angle_between_faces(&m, fx, fy).unwrap();
    assert!(close(a.between_normals, FRAC_PI_2, 1e-15));
    assert!(close(a.between_planes, FRAC_PI_2, 1e-15));
    assert!(close(a.interior.unwrap(), FRAC_PI_2, 1e-15));
    assert_eq!(a.shared_edge, Some(shared));
    assert_eq!(a.distance, None);
    let same = angle_between_faces(&m, fx, fx).unwrap();
    assert_eq!(same.between_normals, 0.0);
    assert_eq!(same.distance, Some(0.0));
    assert_eq!((same.interior, same.shared_edge), (None, None));
    // Edge rows.
    let e = edge_properties(&m, shared).unwrap();
    assert_eq!(e.kind, CurveKind::Line);
    assert!(close(e.length.unwrap(), 1.0, 1e-14));
    assert_eq!(e.direction, Some(Vec3::Z));
}

#[test]
fn concave_edge_reports_the_reflex_interior_angle() {
    let (mut m, fx, fy, _) = two_faces_of_a_box();
    // Flip both faces: the same planes bound the complement, so the edge is concave.
    m.shells[0].faces = vec![(FaceId(0), true), (FaceId(1), false)];
    let a = angle_between_faces(&m, fx, fy).unwrap();
    assert!(close(a.between_normals, FRAC_PI_2, 1e-15));
    assert!(close(a.interior.unwrap(), 1.5 * PI, 1e-15));
}

#[test]
fn step_index_and_parts() {
    let (m, fx, fy, shared) = two_faces_of_a_box();
    let idx = StepIndex::new(&m);
    assert_eq!(idx.face(30), Some(fx));
    assert_eq!(idx.face(31), Some(fy));
    assert_eq!(idx.edge(20), Some(shared));
    assert_eq!(idx.vertex(12), Some(VertexId(2)));
    assert_eq!(idx.entity(20), Some(Entity::Edge(shared)));
    assert_eq!(idx.face(20), None);
    assert_eq!(idx.entity(9999), None);
    assert_eq!(idx.part_name(&m, fy), Some("box"));
    assert_eq!(idx.part_name(&m, shared), Some("box"));
    assert_eq!(idx.part_name(&m, VertexId(4)), Some("box"));
    assert_eq!(idx.part_of(FaceId(77)), None);
}

#[test]
fn bad_ids_give_none() {
    let (mut m, fx, _, _) = two_faces_of_a_box();
    assert_eq!(face_properties(&m, FaceId(99)), None);
    assert_eq!(edge_properties(&m, EdgeId(99)), None);
    assert_eq!(radius_of(&m, FaceId(99)), None);
    assert_eq!(radius_of(&m, EdgeId(99)), None);
    assert_eq!(angle_between_faces(&m, fx, FaceId(99)), None);
    assert_eq!(vertex_distance(&m, VertexId(0), VertexId(99)), None);
    m.edges[0].curve = Some(CurveId(1000));
    assert_eq!(edge_properties(&m, EdgeId(0)), None);
    m.edges[1].end = VertexId(1000);
    assert_eq!(edge_properties(&m, EdgeId(1)), None);
    m.faces[0].surface = SurfaceId(1000);
    assert_eq!(face_properties(&m, fx), None);
    // StepIndex survives dangling ids too.
    m.parts[0].bodies.push(Body::Solid(crate::SolidId(5)));
    m.parts[0].bodies.push(Body::Face(FaceId(500)));
    let _ = StepIndex::new(&m);
}

#[test]
fn analytic_face_properties() {
    let mut m = Model::default();
    let frame = Frame::from_axis(Vec3::new(1.0, 2.0, 3.0), Vec3::Z, None).unwrap();
    m.surfaces.push(Surface::Cylinder { frame, radius: 4.0 });
    m.surfaces.push(Surface::Cone {
        frame,
        radius: 2.0,
        semi_angle: PI / 4.0,
    });
    m.surfaces.push(Surface::Torus {
        frame,
        major_radius: 10.0,
        minor_radius: 3.0,
    });
    m.surfaces.push(Surface::Offset {
        basis: Box::new(Surface::Trimmed {
            basis: Box::new(Surface::Sphere { frame, radius: 5.0 }),
            u0: 0.0,
            u1: 1.0,
            v0: 0.0,
            v1: 1.0,
        }),
        distance: 1.5,
    });
    for i in 0..4 {
        m.faces.push(Face {
            surface: SurfaceId(i),
            same_sense: true,
            loops: Vec::new(),
            step_id: 100 + i as u64,
        });
    }
    let cyl = face_properties(&m, FaceId(0)).unwrap();
    assert_eq!((cyl.kind, cyl.radius), (SurfaceKind::Cylinder, Some(4.0)));
    assert_eq!(cyl.axis.unwrap().direction, Vec3::Z);
    assert_eq!(radius_of(&m, FaceId(0)), Some(4.0));
    let cone = face_properties(&m, FaceId(1)).unwrap();
    assert!((cone.apex.unwrap() - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-12);
    assert!(close(
        cone.semi_angle.unwrap(),
        std::f64::consts::FRAC_PI_4,
        1e-15
    ));
    assert_eq!(radius_of(&m, FaceId(1)), None);
    let torus = face_properties(&m, FaceId(2)).unwrap();
    assert_eq!(
        (torus.major_radius, torus.minor_radius),
        (Some(10.0), Some(3.0))
    );
    let off = face_properties(&m, FaceId(3)).unwrap();
    assert_eq!((off.kind, off.radius), (SurfaceKind::Offset, Some(6.5)));
}

#[test]
fn circle_edges() {
    let mut m = Model::default();
    let frame = Frame::from_axis(Vec3::new(0.0, 0.0, 2.0), Vec3::Z, Some(Vec3::X)).unwrap();
    let c = Curve::Circle {
        frame: CurveFrame::from(frame),
        radius: 2.5,
    };
    let a = vertex(&mut m, Vec3::new(2.5, 0.0, 2.0), 1);
    let b = vertex(&mut m, Vec3::new(0.0, 2.5, 2.0), 2);
    let full = edge(&mut m, c.clone(), a, a, 3);
    let quarter = edge(&mut m, c, a, b, 4);
    let p = edge_properties(&m, full).unwrap();
    assert!(p.closed);
    assert!(close(p.length.unwrap(), 5.0 * PI, 1e-12));
    assert_eq!(p.radius, Some(2.5));
    assert_eq!(p.axis.unwrap().direction, Vec3::Z);
    assert!(close(p.arc_angle.unwrap(), TAU, 1e-15));
    let q = edge_properties(&m, quarter).unwrap();
    assert!(close(q.length.unwrap(), 1.25 * PI, 1e-12));
    assert!(close(q.arc_angle.unwrap(), FRAC_PI_2, 1e-15));
    assert_eq!(radius_of(&m, quarter), Some(2.5));
    assert_eq!(radius_of(&m, a), None);
    // A degenerate edge.
    m.edges.push(Edge {
        curve: None,
        start: a,
        end: a,
        same_sense: true,
        pcurves: Vec::new(),
        step_id: 5,
    });
    let d = edge_properties(&m, EdgeId(2)).unwrap();
    assert_eq!((d.kind, d.length), (CurveKind::Degenerate, Some(0.0)));
}

#[test]
fn distance_is_euclidean() {
    assert_eq!(distance(Vec3::ZERO, Vec3::new(3.0, 4.0, 12.0)), 13.0);
    let mut m = Model::default();
    let a = vertex(&mut m, Vec3::ZERO, 1);
    let b = vertex(&mut m, Vec3::new(0.0, 3.0, 4.0), 2);
    assert_eq!(vertex_distance(&m, a, b), Some(5.0));
    assert_eq!(vertex_distance(&m, a, VertexId(7)), None);
}

/// A quarter of a cylinder of radius 2 about z, 3 high, written as a rational B-spline
/// surface bounded by its two arcs (rational B-spline curves, or polynomial ones when not
/// `rational`: then parabolas, no circle) and two rulings.
fn bspline_quarter_cylinder(rational: bool) -> (Model, FaceId, EdgeId) {
    use cadre_geom::bspline::{BSplineCurve, BSplineSurface};
    let mut m = Model::default();
    let p = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let weights = rational.then(|| vec![1.0, h, 1.0]);
    let arc = |z: f64| {
        Curve::BSpline(
            BSplineCurve::try_new(
                2,
                vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
                vec![p(2.0, 0.0, z), p(2.0, 2.0, z), p(0.0, 2.0, z)],
                weights.clone(),
            )
            .unwrap(),
        )
    };
    let v0 = vertex(&mut m, p(2.0, 0.0, 0.0), 1);
    let v1 = vertex(&mut m, p(0.0, 2.0, 0.0), 2);
    let v2 = vertex(&mut m, p(0.0, 2.0, 3.0), 3);
    let v3 = vertex(&mut m, p(2.0, 0.0, 3.0), 4);
    let bottom = edge(&mut m, arc(0.0), v0, v1, 10);
    let left = edge(&mut m, line(p(0.0, 2.0, 0.0), p(0.0, 2.0, 3.0)), v1, v2, 11);
    let top = edge(&mut m, arc(3.0), v3, v2, 12);
    let right = edge(&mut m, line(p(2.0, 0.0, 3.0), p(2.0, 0.0, 0.0)), v3, v0, 13);
    let net = |z0: f64, z1: f64| {
        vec![
            vec![p(2.0, 0.0, z0), p(2.0, 0.0, z1)],
            vec![p(2.0, 2.0, z0), p(2.0, 2.0, z1)],
            vec![p(0.0, 2.0, z0), p(0.0, 2.0, z1)],
        ]
    };
    m.surfaces.push(Surface::BSpline(Box::new(
        BSplineSurface::try_new(
            2,
            1,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![0.0, 0.0, 1.0, 1.0],
            net(0.0, 3.0),
            rational.then(|| vec![vec![1.0, 1.0], vec![h, h], vec![1.0, 1.0]]),
        )
        .unwrap(),
    )));
    let fwd = |edge, forward| OrientedEdge { edge, forward };
    m.faces.push(Face {
        surface: SurfaceId(0),
        same_sense: true,
        loops: vec![Loop {
            kind: LoopKind::Edges(vec![
                fwd(bottom, true),
                fwd(left, true),
                fwd(top, false),
                fwd(right, true),
            ]),
            orientation: true,
            outer: true,
        }],
        step_id: 20,
    });
    (m, FaceId(0), bottom)
}

#[test]
fn a_bspline_cylinder_and_its_bspline_arcs_are_measured_as_such() {
    let (m, face, arc) = bspline_quarter_cylinder(true);
    let f = face_properties(&m, face).unwrap();
    assert_eq!(f.kind, SurfaceKind::BSpline);
    assert_eq!(face_plane(&m, face), None, "a cylinder has no plane");
    let (shape, deviation) = f.recognised.expect("recognised");
    assert_eq!(shape, "cylinder");
    assert!(deviation < 1e-9, "{deviation}");
    assert!(close(f.radius.unwrap(), 2.0, 1e-9));
    let axis = f.axis.unwrap();
    assert!(axis.direction.cross(Vec3::Z).length() < 1e-9);
    assert!(axis.origin.truncate().length() < 1e-9, "{axis:?}");
    assert!(close(radius_of(&m, face).unwrap(), 2.0, 1e-9));
    let e = edge_properties(&m, arc).unwrap();
    assert_eq!(e.kind, CurveKind::BSpline);
    assert_eq!(e.recognised.map(|r| r.0), Some("circle"));
    assert!(close(e.radius.unwrap(), 2.0, 1e-9));
    assert!(e.centre.unwrap().length() < 1e-9);
    assert!(close(e.arc_angle.unwrap(), FRAC_PI_2, 1e-6));
    // Negative control: the same written polynomial is a parabolic cylinder — no radius.
    let (m, face, arc) = bspline_quarter_cylinder(false);
    let f = face_properties(&m, face).unwrap();
    assert_eq!((f.recognised, f.radius), (None, None));
    let e = edge_properties(&m, arc).unwrap();
    assert_eq!((e.recognised, e.radius), (None, None));
}
