//! Exact face areas from tessellations of small solids written in STEP by hand (spheres with
//! and without seams and poles, a cylinder, a torus), against the flat triangle areas; and a
//! property test of exact arc lengths.

use std::f64::consts::{PI, TAU};

use cadre_brep::measure::edge_properties;
use cadre_brep::{Edge, EdgeId, FaceId, Model, StepIndex, Vertex, VertexId};
use cadre_geom::curve::Curve;
use cadre_geom::{Accuracy, Frame, Vec3};
use cadre_mesh::face_area::{face_area, mesh_area};
use cadre_mesh::{MeshParams, mesh_model};
use cadre_step::syntax::StepFile;
use proptest::prelude::*;

const CONTEXT: &str = "
#900=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904))
 GLOBAL_UNIT_ASSIGNED_CONTEXT((#901,#902,#903)) REPRESENTATION_CONTEXT('',''));
#901=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#902=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#903=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#901,'distance_accuracy_value','');
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5=CARTESIAN_POINT('',(0.,0.,10.));#6=AXIS2_PLACEMENT_3D('',#5,#2,#3);
#9=DIRECTION('',(0.,-1.,0.));#19=AXIS2_PLACEMENT_3D('',#1,#9,#3);
";

/// Reads a solid `#100` (a `MANIFOLD_SOLID_BREP`) written with the shared context.
fn model(data: &str) -> Model {
    let text = format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('t','',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{CONTEXT}{data}\n\
         #999=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#100),#900);\nENDSEC;\nEND-ISO-10303-21;\n"
    );
    let file = StepFile::parse(text.into_bytes()).expect("parses");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    model
}

/// Exact and flat areas of the faces with STEP ids `faces`, summed, meshed with `deflection`.
fn areas(m: &Model, faces: &[u64], deflection: f64) -> (f64, f64) {
    let params = MeshParams {
        deflection,
        angle: 0.5,
        ..MeshParams::default()
    };
    let mesh = mesh_model(m, &params, None);
    assert!(mesh.failures.is_empty(), "{:?}", mesh.failures);
    let idx = StepIndex::new(m);
    let mut exact = 0.0;
    let mut flat = 0.0;
    for &step in faces {
        let f = idx.face(step).expect("face");
        let fm = mesh.faces[f.index()].as_ref().expect("meshed");
        exact += face_area(m, f, fm);
        flat += mesh_area(fm);
    }
    (exact, flat)
}

/// Checks the exact area to 1e-4 relative and that the flat one is measurably smaller, at a
/// coarse and a fine deflection.
fn check(name: &str, m: &Model, faces: &[u64], want: f64) {
    for deflection in [0.05, 0.01] {
        let (exact, flat) = areas(m, faces, deflection);
        let e_exact = (exact - want).abs() / want;
        let e_flat = (want - flat) / want;
        assert!(
            e_exact <= 1e-4,
            "{name} @ {deflection}: exact {exact} vs {want} ({e_exact:e})"
        );
        assert!(
            e_flat > 1e-4 && e_flat > 10.0 * e_exact,
            "{name} @ {deflection}: flat {flat} vs {want} ({e_flat:e}), exact {e_exact:e}"
        );
    }
}

#[test]
fn whole_sphere_area_is_exact() {
    let m = model(
        "
#10=SPHERICAL_SURFACE('',#4,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#50=VERTEX_LOOP('',#31);#52=FACE_OUTER_BOUND('',#50,.T.);
#56=ADVANCED_FACE('sphere',(#52),#10,.T.);
#90=CLOSED_SHELL('',(#56));#100=MANIFOLD_SOLID_BREP('',#90);
",
    );
    check("sphere", &m, &[56], 100.0 * PI);
}

#[test]
fn sphere_of_two_lunes_area_is_exact() {
    let m = model(
        "
#10=SPHERICAL_SURFACE('',#4,5.);
#22=CIRCLE('',#19,5.);
#34=CARTESIAN_POINT('',(0.,0.,5.));#35=VERTEX_POINT('',#34);
#36=CARTESIAN_POINT('',(0.,0.,-5.));#37=VERTEX_POINT('',#36);
#42=EDGE_CURVE('via -x',#35,#37,#22,.T.);#43=EDGE_CURVE('via +x',#35,#37,#22,.F.);
#50=ORIENTED_EDGE('',*,*,#42,.F.);#51=ORIENTED_EDGE('',*,*,#43,.T.);
#52=EDGE_LOOP('',(#50,#51));#53=FACE_OUTER_BOUND('',#52,.T.);
#54=ADVANCED_FACE('y > 0',(#53),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#43,.F.);#61=ORIENTED_EDGE('',*,*,#42,.T.);
#62=EDGE_LOOP('',(#60,#61));#63=FACE_OUTER_BOUND('',#62,.T.);
#64=ADVANCED_FACE('y < 0',(#63),#10,.T.);
#90=CLOSED_SHELL('',(#54,#64));#100=MANIFOLD_SOLID_BREP('',#90);
",
    );
    check("lune y > 0", &m, &[54], 50.0 * PI);
    check("two lunes", &m, &[54, 64], 100.0 * PI);
}

#[test]
fn hemisphere_with_a_seam_to_the_pole_area_is_exact() {
    let m = model(
        "
#10=SPHERICAL_SURFACE('',#4,5.);#11=PLANE('',#4);
#20=CIRCLE('',#4,5.);#22=CIRCLE('',#19,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#34=CARTESIAN_POINT('',(0.,0.,5.));#35=VERTEX_POINT('',#34);
#40=EDGE_CURVE('',#31,#31,#20,.T.);#42=EDGE_CURVE('',#31,#35,#22,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.T.);#57=ORIENTED_EDGE('',*,*,#42,.T.);
#58=ORIENTED_EDGE('',*,*,#42,.F.);
#51=EDGE_LOOP('',(#50,#57,#58));#52=FACE_OUTER_BOUND('',#51,.T.);
#56=ADVANCED_FACE('dome',(#52),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#40,.F.);#61=EDGE_LOOP('',(#60));#62=FACE_OUTER_BOUND('',#61,.T.);
#63=ADVANCED_FACE('disk',(#62),#11,.F.);
#90=CLOSED_SHELL('',(#56,#63));#100=MANIFOLD_SOLID_BREP('',#90);
",
    );
    check("dome", &m, &[56], 50.0 * PI);
}

#[test]
fn cylinder_and_torus_areas_are_exact() {
    let cylinder = model(
        "
#10=CYLINDRICAL_SURFACE('',#4,5.);#11=PLANE('',#4);#12=PLANE('',#6);
#20=CIRCLE('',#4,5.);#21=CIRCLE('',#6,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#32=CARTESIAN_POINT('',(5.,0.,10.));#33=VERTEX_POINT('',#32);
#40=EDGE_CURVE('',#31,#31,#20,.T.);#41=EDGE_CURVE('',#33,#33,#21,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.T.);#51=EDGE_LOOP('',(#50));#52=FACE_BOUND('',#51,.T.);
#53=ORIENTED_EDGE('',*,*,#41,.F.);#54=EDGE_LOOP('',(#53));#55=FACE_BOUND('',#54,.T.);
#56=ADVANCED_FACE('side',(#52,#55),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#40,.F.);#61=EDGE_LOOP('',(#60));#62=FACE_OUTER_BOUND('',#61,.T.);
#63=ADVANCED_FACE('bottom',(#62),#11,.F.);
#64=ORIENTED_EDGE('',*,*,#41,.T.);#65=EDGE_LOOP('',(#64));#66=FACE_OUTER_BOUND('',#65,.T.);
#67=ADVANCED_FACE('top',(#66),#12,.T.);
#90=CLOSED_SHELL('',(#56,#63,#67));#100=MANIFOLD_SOLID_BREP('',#90);
",
    );
    check("cylinder side", &cylinder, &[56], 100.0 * PI);
    let torus = model(
        "
#10=TOROIDAL_SURFACE('',#4,10.,3.);
#30=CARTESIAN_POINT('',(13.,0.,0.));#31=VERTEX_POINT('',#30);
#50=VERTEX_LOOP('',#31);#52=FACE_OUTER_BOUND('',#50,.T.);
#56=ADVANCED_FACE('torus',(#52),#10,.T.);
#90=CLOSED_SHELL('',(#56));#100=MANIFOLD_SOLID_BREP('',#90);
",
    );
    check("torus", &torus, &[56], 4.0 * PI * PI * 10.0 * 3.0);
}

/// A model holding one circle of radius `r` with an edge between the points at angles `a`
/// and `b` (running forward from `a`).
fn arc_model(r: f64, a: f64, b: f64) -> Model {
    let frame =
        Frame::from_axis(Vec3::new(1.0, -2.0, 3.0), Vec3::new(1.0, 1.0, 1.0), None).expect("frame");
    let circle = Curve::Circle {
        frame: frame.into(),
        radius: r,
    };
    let mut m = Model::default();
    for t in [a, b] {
        m.vertices.push(Vertex {
            point: circle.eval(t),
            step_id: 0,
        });
    }
    m.curves.push(circle);
    m.edges.push(Edge {
        curve: Some(cadre_brep::CurveId(0)),
        start: VertexId(0),
        end: VertexId(1),
        same_sense: true,
        pcurves: Vec::new(),
        step_id: 7,
    });
    m
}

proptest! {
    /// A circular arc's length is r·Δt, both from the edge (vertices projected onto the
    /// circle) and from the integrator over any parameter range.
    #[test]
    fn arc_length_is_radius_times_angle(
        r in 1e-3f64..1e4,
        a in -10.0f64..10.0,
        sweep in 0.01f64..(TAU - 0.01),
        t0 in -20.0f64..20.0,
        dt in 0.0f64..50.0,
    ) {
        let m = arc_model(r, a, a + sweep);
        let p = edge_properties(&m, EdgeId(0)).expect("edge");
        let len = p.length.expect("length");
        prop_assert!((len - r * sweep).abs() <= 1e-9 * r * sweep, "{len} vs {}", r * sweep);
        prop_assert!((p.arc_angle.expect("arc") - sweep).abs() <= 1e-9 * sweep);
        let circle = &m.curves[0];
        let len = circle
            .arc_length(t0 + dt, t0, Accuracy::default())
            .expect("length");
        prop_assert!((len - r * dt).abs() <= 1e-12 * r * dt.max(1.0));
    }
}

#[test]
fn bad_face_ids_fall_back_to_the_flat_area() {
    let m = arc_model(1.0, 0.0, 1.0);
    let mesh = cadre_mesh::face::FaceMesh::default();
    assert_eq!(face_area(&m, FaceId(3), &mesh), 0.0);
}
