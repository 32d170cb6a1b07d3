//! Mapping of B-Rep, units, assemblies, styles and tessellated geometry from small STEP texts.

mod common;

use cadre_brep::{Body, LoopKind, model::StyleTarget};
use cadre_geom::{Accuracy, Surface, Vec3};
use common::{CUBE, INCH_DEGREE_CONTEXT, MM_CONTEXT, model};

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

#[test]
fn cube_solid_maps_with_counts_orientations_and_bbox() {
    let m = model(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let c = m.counts();
    assert_eq!((c.solids, c.shells, c.faces), (1, 1, 6));
    assert_eq!(c.surface_types.get("Plane"), Some(&6));
    assert_eq!(m.edges.len(), 12);
    assert_eq!(m.vertices.len(), 8);
    // Orientation flags are kept as written.
    let bottom = m.faces.iter().find(|f| f.step_id == 107).unwrap();
    assert!(!bottom.same_sense);
    let LoopKind::Edges(es) = &bottom.loops[0].kind else {
        panic!("edge loop")
    };
    assert_eq!(
        es.iter().map(|e| e.forward).collect::<Vec<_>>(),
        [true, true, false, false]
    );
    let b = m.bbox(Accuracy::default());
    assert!(close(b.min.x, 0.0) && close(b.max.z, 1.0), "{b:?}");
    assert_eq!(m.units.length_name, "mm");
    assert_eq!(m.units.uncertainty_mm, Some(1e-7));
}

#[test]
fn inch_units_scale_geometry_to_millimetres() {
    let m = model(&format!(
        "{INCH_DEGREE_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let b = m.bbox(Accuracy::default());
    assert!(close(b.max.x, 25.4) && close(b.max.y, 25.4), "{b:?}");
    assert_eq!(m.units.length_name, "inch");
    assert!(close(m.units.length_to_mm, 25.4));
    assert!(close(m.units.uncertainty_mm.unwrap(), 25.4e-5));
}

#[test]
fn cone_semi_angle_in_degrees_becomes_radians() {
    let m = model(&format!(
        "{INCH_DEGREE_CONTEXT}
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=CONICAL_SURFACE('',#4,2.,30.);
#6=CIRCLE('',#4,2.);#7=CARTESIAN_POINT('',(2.,0.,0.));#8=VERTEX_POINT('',#7);
#9=EDGE_CURVE('',#8,#8,#6,.T.);#10=ORIENTED_EDGE('',*,*,#9,.T.);#11=EDGE_LOOP('',(#10));
#12=FACE_OUTER_BOUND('',#11,.T.);#13=ADVANCED_FACE('',(#12),#5,.T.);
#14=OPEN_SHELL('',(#13));#15=SHELL_BASED_SURFACE_MODEL('',(#14));
#16=MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#15),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let Surface::Cone {
        radius, semi_angle, ..
    } = &m.surfaces[0]
    else {
        panic!("cone expected, got {:?}", m.surfaces[0]);
    };
    assert!(close(*semi_angle, 30f64.to_radians()), "{semi_angle}");
    assert!(close(*radius, 2.0 * 25.4));
    let c = m.counts();
    assert_eq!((c.solids, c.shells, c.faces), (0, 1, 1));
}

#[test]
fn bundled_assembly_places_shared_instances() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/pin-assembly.step"
    );
    let file = cadre_step::syntax::StepFile::read(std::path::Path::new(path)).unwrap();
    let m = cadre_step::map_file(&file);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let c = m.counts();
    assert_eq!(
        (c.solids, c.shells, c.faces, c.products, c.instances),
        (2, 2, 6, 2, 2)
    );
    // Geometry is stored once and shared by both instances.
    assert_eq!(m.solids.len(), 1);
    assert_eq!(m.roots.len(), 1);
    assert_eq!(m.part(m.roots[0]).name, "pin assembly");
    let b = m.bbox(Accuracy::default());
    let want = [-5.0, -5.0, -5.0, 25.0, 40.0, 10.0];
    for (got, want) in b.to_array().iter().zip(want) {
        assert!((got - want).abs() < 1e-6, "bbox {:?}", b.to_array());
    }
    // The colour on the solid is kept.
    let style = m
        .styles
        .get(&StyleTarget::Solid(cadre_brep::SolidId(0)))
        .unwrap();
    let rgb = style.color.unwrap();
    assert!((rgb.r - 0.8).abs() < 1e-6 && (rgb.g - 0.2).abs() < 1e-6);
    // The seam edge is used twice by the side face.
    let side = m.faces.iter().find(|f| f.step_id == 74).unwrap();
    let LoopKind::Edges(es) = &side.loops[0].kind else {
        panic!()
    };
    assert_eq!(es[1].edge, es[3].edge);
    assert_ne!(es[1].forward, es[3].forward);
}

#[test]
fn rational_bspline_complex_instance_and_pcurves() {
    // A quarter circle as a rational quadratic B-spline (complex instance), with a pcurve.
    let m = model(&format!(
        "{MM_CONTEXT}
#1=CARTESIAN_POINT('',(1.,0.,0.));#2=CARTESIAN_POINT('',(1.,1.,0.));#3=CARTESIAN_POINT('',(0.,1.,0.));
#4=(BOUNDED_CURVE() B_SPLINE_CURVE(2,(#1,#2,#3),.CIRCULAR_ARC.,.F.,.F.)
 B_SPLINE_CURVE_WITH_KNOTS((3,3),(0.,1.),.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM()
 RATIONAL_B_SPLINE_CURVE((1.,0.707106781186548,1.)) REPRESENTATION_ITEM(''));
#5=GEOMETRIC_CURVE_SET('',(#4));
#6=GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('',(#5),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let cadre_geom::Curve3::BSpline(b) = &m.curves[0] else {
        panic!("{:?}", m.curves[0])
    };
    assert_eq!(b.degree, 2);
    assert_eq!(b.knots, vec![0., 0., 0., 1., 1., 1.]);
    assert!(b.weights.is_some());
    let mid = m.curves[0].eval(0.5);
    assert!(
        (mid.length() - 1.0).abs() < 1e-9,
        "rational evaluation stays on the circle: {mid}"
    );
    let parts_with_wire = m
        .parts
        .iter()
        .filter(|p| p.bodies.iter().any(|b| matches!(b, Body::Wire(_))))
        .count();
    assert_eq!(parts_with_wire, 1);
}

#[test]
fn tessellated_solid_counts_faces_shells_solids() {
    let m = model(&format!(
        "{MM_CONTEXT}
#1=COORDINATES_LIST('',4,((0.,0.,0.),(1.,0.,0.),(1.,1.,0.),(0.,1.,0.)));
#2=COMPLEX_TRIANGULATED_FACE('',#1,4,((0.,0.,1.)),$,(1,2,3,4),((1,2,4,3)),());
#3=TRIANGULATED_FACE('',#1,4,((0.,0.,-1.)),$,(),((1,3,2),(1,4,3)));
#4=TESSELLATED_SOLID('',(#2,#3),$);
#5=TESSELLATED_SHAPE_REPRESENTATION('',(#4),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let c = m.counts();
    assert_eq!((c.solids, c.shells, c.faces), (1, 1, 2));
    let mesh = &m.meshes[0];
    assert_eq!(mesh.triangles.len(), 4);
    assert_eq!(mesh.face_starts, vec![0, 2]);
    // The strip (1,2,4,3) gives (1,2,4), then (4,2,3): odd triangles swap their first two
    // indices so every triangle keeps the strip's winding.
    assert_eq!(mesh.triangles[0], [0, 1, 3]);
    assert_eq!(mesh.triangles[1], [3, 1, 2]);
}

#[test]
fn brep_with_voids_counts_the_void_shell() {
    let m = model(&format!(
        "{MM_CONTEXT}{CUBE}
#300=ORIENTED_CLOSED_SHELL('',*,#160,.F.);
#301=BREP_WITH_VOIDS('',#160,(#300));
#302=ADVANCED_BREP_SHAPE_REPRESENTATION('',(#301),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let c = m.counts();
    assert_eq!((c.solids, c.shells, c.faces), (1, 2, 12));
    let void = &m.shells[m.solids[0].voids[0].index()];
    assert!(void.faces.iter().all(|&(_, forward)| !forward));
    let _ = Vec3::ZERO;
}

#[test]
fn solid_with_open_shell_is_read_as_shells_with_a_warning() {
    // The cube's shell without its top face has four free edges: no volume is bounded.
    let data = CUBE.replace(
        "#160=CLOSED_SHELL('',(#107,#117,#127,#137,#147,#157));",
        "#160=CLOSED_SHELL('',(#107,#127,#137,#147,#157));",
    );
    let m = model(&format!(
        "{MM_CONTEXT}{data}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    let c = m.counts();
    assert_eq!((c.solids, c.shells, c.faces), (0, 1, 5));
    assert!(
        m.warnings
            .iter()
            .any(|w| w.step_id == Some(80) && w.message.contains("4 free edges")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn surfaces_in_a_geometric_set_are_faces() {
    // A plane bounded by a square of polylines, and a bare cylinder, in a geometric set.
    let m = model(&format!(
        "{MM_CONTEXT}
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=DIRECTION('',(0.,0.,1.));#3=DIRECTION('',(1.,0.,0.));
#4=AXIS2_PLACEMENT_3D('',#1,#2,#3);#5=PLANE('',#4);
#10=CARTESIAN_POINT('',(0.,0.,0.));#11=CARTESIAN_POINT('',(4.,0.,0.));
#12=CARTESIAN_POINT('',(4.,3.,0.));#13=CARTESIAN_POINT('',(0.,3.,0.));
#14=POLYLINE('',(#10,#11,#12,#13,#10));
#15=COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,#14);
#16=BOUNDARY_CURVE('',(#15),.F.);
#17=CURVE_BOUNDED_SURFACE('',#5,(#16),.F.);
#18=CYLINDRICAL_SURFACE('',#4,1.);
#19=RECTANGULAR_TRIMMED_SURFACE('',#18,0.,3.14159265358979,0.,2.,.T.,.T.);
#20=GEOMETRIC_SET('',(#17,#19));
#21=GEOMETRICALLY_BOUNDED_SURFACE_SHAPE_REPRESENTATION('',(#20),#900);"
    ));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let c = m.counts();
    assert_eq!((c.faces, c.shells, c.solids), (2, 0, 0));
    let b = m.bbox(Accuracy::default());
    // Square 4 × 3 at z = 0 and a half cylinder of radius 1 up to z = 2 (y ≥ 0 side).
    let want = [-1.0, 0.0, 0.0, 4.0, 3.0, 2.0];
    for (got, want) in b.to_array().iter().zip(want) {
        assert!((got - want).abs() < 1e-6, "bbox {:?}", b.to_array());
    }
}

#[test]
fn straight_edge_missing_its_vertices_is_healed() {
    // Edge #30's line is moved 2 mm off its vertices.
    let data = CUBE.replace(
        "#30=EDGE_CURVE('',#11,#12,#31,.T.);#31=LINE('',#1,#23);",
        "#30=EDGE_CURVE('',#11,#12,#31,.T.);#31=LINE('',#999,#23);#999=CARTESIAN_POINT('',(0.,-2.,0.));",
    );
    let m = model(&format!(
        "{MM_CONTEXT}{data}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    assert!(
        m.warnings
            .iter()
            .any(|w| w.step_id == Some(30) && w.message.contains("misses its vertices")),
        "{:?}",
        m.warnings
    );
    let b = m.bbox(Accuracy::default());
    assert!(
        b.min.y.abs() < 1e-9,
        "the healed edge stays on the cube: {b:?}"
    );
}

#[test]
fn an_unbounded_surface_alone_in_a_set_is_construction_geometry() {
    // tr8_ha1_db.stp: a bare plane in a geometric curve set beside a solid. It has no extent
    // to draw: no face is made, and a warning says so (before: a face that failed to mesh).
    let m = model(&format!(
        "{MM_CONTEXT}{CUBE}
#301=CARTESIAN_POINT('',(0.,0.,0.));#302=DIRECTION('',(0.,0.,1.));#303=DIRECTION('',(1.,0.,0.));
#304=AXIS2_PLACEMENT_3D('',#301,#302,#303);#305=PLANE('',#304);
#306=GEOMETRIC_CURVE_SET('',(#305));
#200=SHAPE_REPRESENTATION('cube and plane',(#80,#306),#900);"
    ));
    assert_eq!(m.counts().faces, 6, "only the cube's faces");
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    let w = m.warnings[0].to_string();
    assert!(
        w.contains("#305") && w.contains("construction geometry"),
        "{w}"
    );
}

/// A cube product placed 5 mm along x in an assembly product; `relating` is what the usage
/// names as its parent: the assembly's product definition `#312` or its shape `#313`.
fn cube_assembly(relating: &str) -> String {
    format!(
        "{MM_CONTEXT}{CUBE}
#300=PRODUCT_DEFINITION_CONTEXT('',#301,'design');#301=APPLICATION_CONTEXT('');
#310=PRODUCT('asm','asm','',());#311=PRODUCT_DEFINITION_FORMATION('','',#310);
#312=PRODUCT_DEFINITION('','',#311,#300);#313=PRODUCT_DEFINITION_SHAPE('','',#312);
#320=PRODUCT('cube','cube','',());#321=PRODUCT_DEFINITION_FORMATION('','',#320);
#322=PRODUCT_DEFINITION('','',#321,#300);#323=PRODUCT_DEFINITION_SHAPE('','',#322);
#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80,#60),#900);
#324=SHAPE_DEFINITION_REPRESENTATION(#323,#200);
#341=CARTESIAN_POINT('',(5.,0.,0.));#340=AXIS2_PLACEMENT_3D('',#341,#22,#20);
#330=SHAPE_REPRESENTATION('asm',(#60,#340),#900);
#331=SHAPE_DEFINITION_REPRESENTATION(#313,#330);
#350=NEXT_ASSEMBLY_USAGE_OCCURRENCE('1','','',{relating},#322,$);
#351=PRODUCT_DEFINITION_SHAPE('','',#350);
#352=(REPRESENTATION_RELATIONSHIP('','',#200,#330) REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#353) SHAPE_REPRESENTATION_RELATIONSHIP());
#353=ITEM_DEFINED_TRANSFORMATION('','',#60,#340);
#354=CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#352,#351);"
    )
}

#[test]
fn assembly_usage_naming_a_product_definition_shape_is_followed_to_its_definition() {
    // bug25167.stp: 4 of 9 usages name the parent's PRODUCT_DEFINITION_SHAPE; they were
    // skipped, and their parts lost (30 % of the area, with a warning only).
    let m = model(&cube_assembly("#313"));
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    let w = m.warnings[0].to_string();
    assert!(
        w.contains("#350") && w.contains("#313") && w.contains("#312"),
        "{w}"
    );
    let b = m.bbox(Accuracy::default());
    assert!(close(b.min.x, 5.0) && close(b.max.x, 6.0), "placed: {b:?}");
    assert_eq!(m.counts().solids, 1);
    // Control: the same assembly written right places the cube the same, without a warning.
    let right = model(&cube_assembly("#312"));
    assert!(right.warnings.is_empty(), "{:?}", right.warnings);
    let rb = right.bbox(Accuracy::default());
    assert!(
        close(rb.min.x, 5.0) && close(rb.max.x, 6.0),
        "placed: {rb:?}"
    );
}

#[test]
fn a_complex_definitional_representation_gives_its_pcurve() {
    // Edge #30 (0,0,0)–(1,0,0) as a surface curve on the bottom plane #61, its pcurve's
    // representation written as a complex instance whose REPRESENTATION record holds the
    // items (its DEFINITIONAL_REPRESENTATION record is empty).
    let complex = "
#30=EDGE_CURVE('',#11,#12,#2000,.T.);
#2000=SURFACE_CURVE('',#31,(#2001),.PCURVE_S1.);
#2001=PCURVE('',#61,#2002);
#2002=(DEFINITIONAL_REPRESENTATION()REPRESENTATION('',(#2003),#2010)SHAPE_REPRESENTATION());
#2003=LINE('',#2004,#2005);
#2004=CARTESIAN_POINT('',(0.,0.));
#2005=VECTOR('',#2006,1.);
#2006=DIRECTION('',(1.,0.));
#2010=(GEOMETRIC_REPRESENTATION_CONTEXT(2)PARAMETRIC_REPRESENTATION_CONTEXT()\
REPRESENTATION_CONTEXT('2D','Parametric Space'));
";
    let cube = CUBE.replace("#30=EDGE_CURVE('',#11,#12,#31,.T.);", "");
    let m = model(&format!("{MM_CONTEXT}{cube}{complex}"));
    let about_pcurve = |m: &cadre_brep::Model| {
        m.warnings
            .iter()
            .map(|w| w.to_string())
            .filter(|w| w.contains("#200") || w.contains("DEFINITIONAL"))
            .collect::<Vec<_>>()
    };
    assert!(about_pcurve(&m).is_empty(), "{:?}", about_pcurve(&m));
    assert_eq!(m.pcurves.len(), 1);
    // Negative control: the simple form reads the same.
    let simple = complex.replace(
        "#2002=(DEFINITIONAL_REPRESENTATION()REPRESENTATION('',(#2003),#2010)SHAPE_REPRESENTATION());",
        "#2002=DEFINITIONAL_REPRESENTATION('',(#2003),#2010);",
    );
    let m = model(&format!("{MM_CONTEXT}{cube}{simple}"));
    assert!(about_pcurve(&m).is_empty(), "{:?}", about_pcurve(&m));
    assert_eq!(m.pcurves.len(), 1);
}
