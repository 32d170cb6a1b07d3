//! Bad input: every problem becomes a warning naming the instance and its line, nothing
//! panics, and everything valid still loads.

mod common;

use cadre_geom::Accuracy;
use common::{CUBE, MM_CONTEXT, model};

fn warned(m: &cadre_brep::Model, id: u64, needle: &str) -> bool {
    m.warnings.iter().any(|w| {
        w.step_id == Some(id) && w.line.is_some() && w.message.to_lowercase().contains(needle)
    })
}

/// A cube plus a second representation holding `extra` items (as `#500…`).
fn cube_and(extra: &str, items: &str) -> cadre_brep::Model {
    model(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);
{extra}
#600=ADVANCED_BREP_SHAPE_REPRESENTATION('other',({items}),#900);"
    ))
}

fn cube_still_loads(m: &cadre_brep::Model) {
    let c = m.counts();
    assert!(
        c.solids >= 1 && c.faces >= 6,
        "the valid cube must still load: {c:?}"
    );
}

#[test]
fn dangling_reference_is_named() {
    let m = cube_and("#500=MANIFOLD_SOLID_BREP('',#9999);", "#500");
    // Reported where the reference is written, since the missing instance has no line.
    assert!(
        warned(
            &m,
            500,
            "#9999: reference to an instance that does not exist"
        ),
        "{:?}",
        m.warnings
    );
    cube_still_loads(&m);
}

/// A missing instance reached with no referrer in hand (a representation's context, read
/// apart from the items) used to be reported as `#9998: …` with no line; it is reported at
/// the first instance that references it.
#[test]
fn dangling_reference_outside_an_item_names_its_referrer() {
    let m = model(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);
#600=ADVANCED_BREP_SHAPE_REPRESENTATION('other',(#80),#9998);"
    ));
    assert!(
        m.warnings.iter().all(|w| w.line.is_some()),
        "{:?}",
        m.warnings
    );
    assert!(warned(&m, 600, "#9998: reference"), "{:?}", m.warnings);
}

/// An empty `CLOSED_SHELL` made a solid that bounded nothing, counted and unreported.
#[test]
fn solid_of_an_empty_shell_is_left_out_and_named() {
    let m = cube_and(
        "#500=MANIFOLD_SOLID_BREP('',#501);\n#501=CLOSED_SHELL('',());",
        "#500",
    );
    assert!(warned(&m, 500, "has no faces"), "{:?}", m.warnings);
    cube_still_loads(&m);
    assert_eq!(m.counts().solids, 1, "only the cube");
}

#[test]
fn unknown_entity_is_named() {
    let m = cube_and(
        "#500=MANIFOLD_SOLID_BREP('',#501);#501=CLOSED_SHELL('',(#502));\
         #502=ADVANCED_FACE('',(),#503,.T.);#503=FANCY_NEW_SURFACE('',1.);",
        "#500",
    );
    assert!(
        warned(&m, 503, "unsupported surface type fancy_new_surface"),
        "{:?}",
        m.warnings
    );
    cube_still_loads(&m);
}

#[test]
fn wrong_arity_is_named() {
    let m = cube_and(
        "#500=MANIFOLD_SOLID_BREP('',#501);#501=CLOSED_SHELL('',(#502));\
         #502=ADVANCED_FACE('',(),#503,.T.);#503=CYLINDRICAL_SURFACE('',#60);",
        "#500",
    );
    assert!(warned(&m, 503, "parameters"), "{:?}", m.warnings);
    cube_still_loads(&m);
}

#[test]
fn cyclic_references_are_cut() {
    let m = cube_and(
        "#500=GEOMETRIC_CURVE_SET('',(#501));#501=OFFSET_CURVE_3D('',#502,1.,.F.,#20);\
         #502=OFFSET_CURVE_3D('',#501,1.,.F.,#20);",
        "#500",
    );
    assert!(
        m.warnings.iter().any(|w| w.message.contains("nest deeper")),
        "{:?}",
        m.warnings
    );
    cube_still_loads(&m);
}

#[test]
fn cyclic_assembly_is_broken() {
    let m = cube_and(
        "#500=MAPPED_ITEM('',#501,#60);#501=REPRESENTATION_MAP(#60,#600);",
        "#500",
    );
    // The representation maps itself: the cycle is reported and walking the tree terminates.
    assert!(
        m.warnings
            .iter()
            .any(|w| w.message.contains("cycle") || w.message.contains("nest")),
        "{:?}",
        m.warnings
    );
    cube_still_loads(&m);
    let _ = m.bbox(Accuracy::default());
}

#[test]
fn absurd_numbers_are_refused() {
    let m = cube_and(
        "#500=GEOMETRIC_CURVE_SET('',(#501,#503));#501=CIRCLE('',#60,-5.);\
         #502=CARTESIAN_POINT('',(1.E400,0.,0.));#503=LINE('',#502,#23);",
        "#500",
    );
    assert!(warned(&m, 501, "radius"), "{:?}", m.warnings);
    assert!(
        m.warnings.iter().any(|w| w.step_id == Some(502)),
        "{:?}",
        m.warnings
    );
    cube_still_loads(&m);
}

#[test]
fn bad_bspline_knots_are_named() {
    let m = cube_and(
        "#500=GEOMETRIC_CURVE_SET('',(#501));\
         #501=B_SPLINE_CURVE_WITH_KNOTS('',3,(#1,#2),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);",
        "#500",
    );
    assert!(warned(&m, 501, "b-spline"), "{:?}", m.warnings);
    cube_still_loads(&m);
}

#[test]
fn huge_multiplicities_do_not_allocate() {
    let m = cube_and(
        "#500=GEOMETRIC_CURVE_SET('',(#501));\
         #501=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.UNSPECIFIED.,.F.,.F.,(4000000000000,2),(0.,1.),.UNSPECIFIED.);",
        "#500",
    );
    assert!(warned(&m, 501, "reason"), "{:?}", m.warnings);
    cube_still_loads(&m);
}

#[test]
fn wrong_entity_type_in_place_is_named() {
    let m = cube_and(
        "#500=MANIFOLD_SOLID_BREP('',#501);#501=CLOSED_SHELL('',(#1));",
        "#500",
    );
    assert!(warned(&m, 1, "not a face"), "{:?}", m.warnings);
    cube_still_loads(&m);
}

#[test]
fn truncated_file_keeps_what_is_complete() {
    let text = common::step(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    let cut = text.find("#200=").unwrap() + 30;
    let file = cadre_step::syntax::StepFile::parse(text.as_bytes()[..cut].to_vec()).unwrap();
    let m = cadre_step::map_file(&file);
    // The representation is cut off: the file's diagnostics name the cut, and the solid,
    // complete before the cut, still loads.
    assert!(
        m.warnings.iter().any(|w| w.line.is_some()),
        "{:?}",
        m.warnings
    );
    let c = m.counts();
    assert_eq!((c.solids, c.faces), (1, 6), "{:?}", m.warnings);
}

/// Geometry that the mapper can read but only by guessing is accepted with a warning naming
/// the instance: a 2-coordinate point used as a 3D point (z = 0 assumed) and a placement whose
/// reference direction is parallel to its axis (an arbitrary perpendicular is used).
#[test]
fn guessed_geometry_is_named() {
    let cube = CUBE
        .replace(
            "#1=CARTESIAN_POINT('',(0.,0.,0.));",
            "#1=CARTESIAN_POINT('',(0.,0.));",
        )
        .replace(
            "#60=AXIS2_PLACEMENT_3D('',#1,#22,#20);",
            "#60=AXIS2_PLACEMENT_3D('',#1,#22,#22);",
        );
    assert_ne!(cube, CUBE, "the cube text changed");
    let m = model(&format!(
        "{MM_CONTEXT}{cube}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    assert!(warned(&m, 1, "2 coordinate(s)"), "{:?}", m.warnings);
    assert!(warned(&m, 60, "parallel to the axis"), "{:?}", m.warnings);
    // Each instance is read several times (point #1 bounds three edges) but warned once.
    let about = |id| m.warnings.iter().filter(|w| w.step_id == Some(id)).count();
    assert_eq!((about(1), about(60)), (1, 1), "{:?}", m.warnings);
    cube_still_loads(&m);

    // Negative control: the well-formed cube raises neither warning.
    let clean = model(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    assert!(
        !warned(&clean, 1, "coordinate") && !warned(&clean, 60, "parallel"),
        "{:?}",
        clean.warnings
    );
}

/// A file cut before its shell (the shell, solid and representation were in the lost tail)
/// used to load nothing although every face was complete: faces that no shell uses, and
/// shells that no solid uses, are loaded as loose geometry, with a warning saying so.
#[test]
fn truncated_file_keeps_faces_whose_shell_was_cut_off() {
    let text = common::step(&format!(
        "{MM_CONTEXT}{CUBE}#200=ADVANCED_BREP_SHAPE_REPRESENTATION('cube',(#80),#900);"
    ));
    let load = |cut: usize| {
        let file = cadre_step::syntax::StepFile::parse(text.as_bytes()[..cut].to_vec()).unwrap();
        cadre_step::map_file(&file)
    };
    // Cut before the shell: six loose faces.
    let m = load(text.find("#160=CLOSED_SHELL").unwrap());
    assert_eq!(m.counts().faces, 6, "{:?}", m.warnings);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.line.is_some() && w.message.contains("6 faces in no shell")),
        "{:?}",
        m.warnings
    );
    // Cut before the solid: one loose shell holding the six faces (not six faces besides it).
    let m = load(text.find("#80=MANIFOLD_SOLID_BREP").unwrap());
    assert_eq!(m.counts().faces, 6, "{:?}", m.warnings);
    assert!(
        m.warnings.iter().any(|w| w
            .message
            .contains("1 shells in no solid, 0 faces in no shell")),
        "{:?}",
        m.warnings
    );
    // Negative control: the complete file has no loose geometry to report.
    let whole = load(text.len());
    assert!(
        !whole
            .warnings
            .iter()
            .any(|w| w.message.contains("in no shell")),
        "{:?}",
        whole.warnings
    );
    assert_eq!(whole.counts().faces, 6);
}
