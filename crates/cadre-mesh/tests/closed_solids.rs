//! End-to-end tessellation of small solids written by hand in STEP, one per way a face can
//! wrap around its surface: seamless cylinders, hemispheres with and without seam and pole,
//! a whole sphere and a whole torus bounded by one vertex, a cone closed at its apex. Each
//! must mesh closed, consistently oriented, with area and volume close to the exact values.

use std::f64::consts::PI;

use cadre_mesh::{MeshParams, mesh_model, mesh_stats};
use cadre_step::syntax::StepFile;

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
#7=DIRECTION('',(0.,0.,-1.));#8=AXIS2_PLACEMENT_3D('',#1,#7,#3);
#9=DIRECTION('',(0.,-1.,0.));#19=AXIS2_PLACEMENT_3D('',#1,#9,#3);
";

/// Reads a solid `#100` (a `MANIFOLD_SOLID_BREP`) written with the shared context.
fn model(data: &str) -> cadre_brep::Model {
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

/// Meshes a solid `#100` (a `MANIFOLD_SOLID_BREP`) and returns its figures.
fn mesh(data: &str, deflection: f64, angle: f64) -> cadre_mesh::MeshStats {
    let model = model(data);
    let params = MeshParams {
        deflection,
        angle,
        ..MeshParams::default()
    };
    let m = mesh_model(&model, &params, None);
    assert!(m.failures.is_empty(), "{:?}", m.failures);
    mesh_stats(&model, &m)
}

fn check(name: &str, data: &str, area: f64, volume: f64) {
    for (deflection, angle, tol) in [(0.05, 0.5, 0.02), (0.002, 0.1, 0.002)] {
        let s = mesh(data, deflection, angle);
        assert_eq!(s.solids, 1, "{name}");
        assert_eq!(s.boundary_edges, 0, "{name}: boundary edges");
        assert_eq!(s.nonmanifold_edges, 0, "{name}: non-manifold edges");
        assert_eq!(s.misoriented_edges, 0, "{name}: misoriented edges");
        let ea = (s.area - area).abs() / area;
        let ev = (s.volume - volume).abs() / volume;
        assert!(
            ea <= tol,
            "{name} @ {deflection}: area {} vs {area} ({ea:e})",
            s.area
        );
        assert!(
            ev <= tol,
            "{name} @ {deflection}: volume {} vs {volume} ({ev:e})",
            s.volume
        );
    }
}

/// Cylinder r 5, h 10 whose side face is bounded by its two circles, without a seam edge.
#[test]
fn seamless_cylinder_is_closed() {
    check(
        "cylinder",
        &cylinder_with_side("CYLINDRICAL_SURFACE('',#4,5.)"),
        150.0 * PI,
        250.0 * PI,
    );
}

/// The same cylinder with its side a surface of revolution of a line: u is the angle and v
/// the line's parameter (ISO 10303-42), so the face sense applies as written.
#[test]
fn cylinder_as_surface_of_revolution_is_closed() {
    let side = "SURFACE_OF_REVOLUTION('',#70,#73);#70=LINE('',#30,#72);#72=VECTOR('',#2,1.);\n#73=AXIS1_PLACEMENT('',#1,#2)";
    check(
        "revolution",
        &cylinder_with_side(side),
        150.0 * PI,
        250.0 * PI,
    );
}

/// Cylinder r 5, h 10 with side surface `side` (entity #10).
fn cylinder_with_side(side: &str) -> String {
    format!(
        "
#10={side};#11=PLANE('',#4);#12=PLANE('',#6);
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
"
    )
}

const HEMISPHERE_BASE: &str = "
#10=SPHERICAL_SURFACE('',#4,5.);#11=PLANE('',#4);
#20=CIRCLE('',#4,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#40=EDGE_CURVE('',#31,#31,#20,.T.);
#60=ORIENTED_EDGE('',*,*,#40,.F.);#61=EDGE_LOOP('',(#60));#62=FACE_OUTER_BOUND('',#61,.T.);
#63=ADVANCED_FACE('disk',(#62),#11,.F.);
#90=CLOSED_SHELL('',(#56,#63));#100=MANIFOLD_SOLID_BREP('',#90);
";

/// Hemisphere bounded by its equator only: closed at the pole by the trim.
#[test]
fn hemisphere_without_seam_is_closed_at_the_pole() {
    let data = format!(
        "{HEMISPHERE_BASE}
#50=ORIENTED_EDGE('',*,*,#40,.T.);#51=EDGE_LOOP('',(#50));#52=FACE_OUTER_BOUND('',#51,.T.);
#56=ADVANCED_FACE('dome',(#52),#10,.T.);"
    );
    check("hemisphere", &data, 75.0 * PI, 250.0 / 3.0 * PI);
}

/// Hemisphere with a seam meridian running up to a vertex at the pole, as most CAD systems
/// write spheres.
#[test]
fn hemisphere_with_seam_to_the_pole_is_closed() {
    let data = format!(
        "{HEMISPHERE_BASE}
#22=CIRCLE('',#19,5.);
#34=CARTESIAN_POINT('',(0.,0.,5.));#35=VERTEX_POINT('',#34);
#42=EDGE_CURVE('',#31,#35,#22,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.T.);#57=ORIENTED_EDGE('',*,*,#42,.T.);
#58=ORIENTED_EDGE('',*,*,#42,.F.);
#51=EDGE_LOOP('',(#50,#57,#58));#52=FACE_OUTER_BOUND('',#51,.T.);
#56=ADVANCED_FACE('dome',(#52),#10,.T.);"
    );
    check("hemisphere with seam", &data, 75.0 * PI, 250.0 / 3.0 * PI);
}

/// A sphere as two half-sphere lunes between the meridians at u = 0 and u = π, each bounded
/// by two edges from pole to pole. Across a pole the loop jumps by exactly half a period, so
/// the nearest copy of the next meridian is a tie: it must be the one that keeps the face on
/// the left (a B-spline sphere in pr1db.stp became a hole beyond its domain).
#[test]
fn sphere_of_two_lunes_is_closed() {
    let data = "
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
";
    check("two lunes", data, 100.0 * PI, 500.0 / 3.0 * PI);
}

/// A whole sphere: one face bounded by a single vertex.
#[test]
fn whole_sphere_from_a_vertex_loop() {
    let data = "
#10=SPHERICAL_SURFACE('',#4,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#50=VERTEX_LOOP('',#31);#52=FACE_OUTER_BOUND('',#50,.T.);
#56=ADVANCED_FACE('sphere',(#52),#10,.T.);
#90=CLOSED_SHELL('',(#56));#100=MANIFOLD_SOLID_BREP('',#90);
";
    check("sphere", data, 100.0 * PI, 500.0 / 3.0 * PI);
}

/// A whole torus (R 10, r 3): one face bounded by a single vertex, periodic both ways.
#[test]
fn whole_torus_from_a_vertex_loop() {
    let data = "
#10=TOROIDAL_SURFACE('',#4,10.,3.);
#30=CARTESIAN_POINT('',(13.,0.,0.));#31=VERTEX_POINT('',#30);
#50=VERTEX_LOOP('',#31);#52=FACE_OUTER_BOUND('',#50,.T.);
#56=ADVANCED_FACE('torus',(#52),#10,.T.);
#90=CLOSED_SHELL('',(#56));#100=MANIFOLD_SOLID_BREP('',#90);
";
    check("torus", data, 4.0 * PI * PI * 30.0, 2.0 * PI * PI * 90.0);
}

/// A cone (base radius 5 at z = 0, apex at z = 10): the side face is bounded by its base
/// circle and a vertex loop at the apex.
const CONE: &str = "
#10=CONICAL_SURFACE('',#8,5.,0.463647609000806);#11=PLANE('',#4);
#20=CIRCLE('',#8,5.);
#30=CARTESIAN_POINT('',(5.,0.,0.));#31=VERTEX_POINT('',#30);
#34=CARTESIAN_POINT('',(0.,0.,10.));#35=VERTEX_POINT('',#34);
#40=EDGE_CURVE('',#31,#31,#20,.T.);
#50=ORIENTED_EDGE('',*,*,#40,.F.);#51=EDGE_LOOP('',(#50));#52=FACE_OUTER_BOUND('',#51,.T.);
#53=VERTEX_LOOP('',#35);#54=FACE_BOUND('',#53,.T.);
#56=ADVANCED_FACE('side',(#52,#54),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#40,.T.);#61=EDGE_LOOP('',(#60));#62=FACE_OUTER_BOUND('',#61,.T.);
#63=ADVANCED_FACE('base',(#62),#11,.F.);
#90=CLOSED_SHELL('',(#56,#63));#100=MANIFOLD_SOLID_BREP('',#90);
";

/// The cone above meshes closed.
#[test]
fn cone_is_closed_at_its_apex() {
    let data = CONE;
    let slant = (125.0f64).sqrt();
    check("cone", data, PI * 5.0 * (5.0 + slant), 250.0 / 3.0 * PI);
}

/// Every trim segment of these faces (edges, seam lines, pole lines) keeps an exact (u, v)
/// curve, and the curve runs from the segment's first point to its last.
#[test]
fn trims_keep_exact_curves() {
    let two_lunes = "
#10=SPHERICAL_SURFACE('',#4,5.);
#22=CIRCLE('',#19,5.);
#34=CARTESIAN_POINT('',(0.,0.,5.));#35=VERTEX_POINT('',#34);
#36=CARTESIAN_POINT('',(0.,0.,-5.));#37=VERTEX_POINT('',#36);
#42=EDGE_CURVE('',#35,#37,#22,.T.);#43=EDGE_CURVE('',#35,#37,#22,.F.);
#50=ORIENTED_EDGE('',*,*,#42,.F.);#51=ORIENTED_EDGE('',*,*,#43,.T.);
#52=EDGE_LOOP('',(#50,#51));#53=FACE_OUTER_BOUND('',#52,.T.);
#54=ADVANCED_FACE('',(#53),#10,.T.);
#60=ORIENTED_EDGE('',*,*,#43,.F.);#61=ORIENTED_EDGE('',*,*,#42,.T.);
#62=EDGE_LOOP('',(#60,#61));#63=FACE_OUTER_BOUND('',#62,.T.);
#64=ADVANCED_FACE('',(#63),#10,.T.);
#90=CLOSED_SHELL('',(#54,#64));#100=MANIFOLD_SOLID_BREP('',#90);
";
    let cylinder = cylinder_with_side("CYLINDRICAL_SURFACE('',#4,5.)");
    for data in [cylinder.as_str(), two_lunes] {
        let model = model(data);
        let params = MeshParams {
            deflection: 0.01,
            angle: 0.2,
            ..MeshParams::default()
        };
        let acc = cadre_geom::Accuracy::default();
        let edges = cadre_mesh::edges::EdgeDiscretisation::new(&model, &params, acc);
        let tol = cadre_brep::trim::TrimTolerance {
            deflection: params.deflection,
            angle: params.angle,
            accuracy: acc,
            keep_exact: true,
        };
        for f in 0..model.faces.len() {
            let trim =
                cadre_brep::trim::face_trim(&model, cadre_brep::FaceId(f as u32), &edges, &tol)
                    .expect("trims");
            let surface = cadre_brep::trim::face_surface(&model, cadre_brep::FaceId(f as u32));
            let on = |uv: cadre_geom::Vec2| surface.eval(uv.x, uv.y);
            for s in trim.loops.iter().flat_map(|l| &l.segments) {
                let e = s
                    .exact
                    .as_ref()
                    .unwrap_or_else(|| panic!("{:?} has no exact curve", s.source));
                // Compared on the surface: at a pole the (u, v) of an end is a matter of
                // convention, the point is not.
                let (first, last) = (s.points[0].uv, s.points[s.points.len() - 1].uv);
                let start = e.curve.eval(e.t0) + e.offset;
                let end = e.curve.eval(e.t1) + e.offset;
                assert!(
                    (on(start) - on(first)).length() < 1e-6,
                    "{:?}: {start} vs {first}",
                    s.source
                );
                assert!(
                    (on(end) - on(last)).length() < 1e-6,
                    "{:?}: {end} vs {last}",
                    s.source
                );
                // The curve's middle lies on the segment's (u, v) polyline (every curve here is
                // a (u, v) line or circle sampled finely).
                let mid = e.curve.eval(0.5 * (e.t0 + e.t1)) + e.offset;
                let d = s
                    .points
                    .windows(2)
                    .map(|w| {
                        let (a, b) = (w[0].uv, w[1].uv);
                        let t = ((mid - a).dot(b - a) / (b - a).length_squared().max(1e-300))
                            .clamp(0.0, 1.0);
                        (a + (b - a) * t - mid).length()
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d < 1e-3,
                    "{:?}: the curve's middle is {d} from the segment",
                    s.source
                );
            }
        }
    }
}

/// The exported scene keeps every vertex's (u, v) on its surface, and a triangle touching the
/// apex of a cone gets its own apex copy whose u continues its other corners (the apex's own u
/// is a convention).
#[test]
fn scene_surface_uv_continue_across_an_apex() {
    let data = CONE;
    let model = model(data);
    let params = MeshParams {
        deflection: 0.05,
        angle: 0.5,
        ..MeshParams::default()
    };
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh_model(&model, &params, None));
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.surface_uv.len(), mesh.positions.len());
    let side = model.faces.iter().position(|f| f.step_id == 56).unwrap();
    let surface = &model.surfaces[model.faces[side].surface.index()];
    let mut apex_corners = 0;
    for prim in &mesh.primitives {
        for (t, tri) in prim.indices.chunks_exact(3).enumerate() {
            if scene.ids.face_step_id(prim.face_ids[t]) != 56 {
                continue;
            }
            let uv: Vec<[f32; 2]> = tri.iter().map(|&i| mesh.surface_uv[i as usize]).collect();
            for k in 0..3 {
                let p = mesh.positions[tri[k] as usize];
                if (p[2] - 10.0).abs() > 1e-6 {
                    continue;
                }
                apex_corners += 1;
                // The apex copy's u lies between its neighbours' (no wrap within a triangle).
                let (a, b) = (uv[(k + 1) % 3][0], uv[(k + 2) % 3][0]);
                assert!((uv[k][0] - 0.5 * (a + b)).abs() < 1e-5, "{uv:?}");
                // And (u, v) evaluates to the apex.
                let s = surface.eval(f64::from(uv[k][0]), f64::from(uv[k][1]));
                assert!(
                    (s - cadre_geom::Vec3::new(0.0, 0.0, 10.0)).length() < 1e-4,
                    "{s}"
                );
            }
        }
    }
    assert!(apex_corners > 8, "{apex_corners} triangles reach the apex");
}
