//! Faces whose file states their sense wrong while their loops and neighbours agree with each
//! other (issue 12, class 1 and 2): as written they bound nothing finite, so the mesher reads
//! them with their sense turned over, meshes them, and says so. Each fixture is the face cut
//! out of the corpus file that showed it (with everything it references), and each test has
//! its control: the same face with the sense written right meshes the same without a repair.

use std::f64::consts::PI;

use cadre_mesh::{MeshParams, mesh_model, mesh_stats};
use cadre_step::syntax::StepFile;

fn data(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    std::fs::read_to_string(path).expect("fixture")
}

/// Area, failures and repair notes of a file's mesh at `deflection` mm.
fn mesh(text: &str, deflection: f64) -> (f64, usize, Vec<String>) {
    let file = StepFile::parse(text.as_bytes().to_vec()).expect("parses");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let params = MeshParams {
        deflection,
        angle: 0.1,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    let stats = mesh_stats(&model, &mesh);
    let notes = mesh.repairs.iter().map(|r| r.note.clone()).collect();
    (stats.area, mesh.failures.len(), notes)
}

#[test]
fn half_cones_through_their_apex_with_the_wrong_sense_mesh_reversed() {
    // PRO7071.stp faces #370 and #382: the two halves of a cone (radius 50, height 100, apex
    // at a vertex) bounded by a half circle and two rulings, written with sense .F. where the
    // loops say .T.: as written each goes around the cone into its open side.
    let text = data("half_cones_wrong_sense.step");
    let (area, failed, notes) = mesh(&text, 0.01);
    assert_eq!(failed, 0);
    let exact = PI * 50.0 * (50.0f64.powi(2) + 100.0f64.powi(2)).sqrt();
    assert!(
        (area - exact).abs() < 1e-3 * exact,
        "area {area} vs {exact}"
    );
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(
        notes
            .iter()
            .all(|n| n.contains("sense is taken as reversed"))
    );
    // Control: with the sense written right, the same area and no repair.
    let right = text
        .replace(
            "ADVANCED_FACE('*FAC14',(#381),#339,.F.)",
            "ADVANCED_FACE('*FAC14',(#381),#339,.T.)",
        )
        .replace(
            "ADVANCED_FACE('*FAC15',(#387),#339,.F.)",
            "ADVANCED_FACE('*FAC15',(#387),#339,.T.)",
        );
    assert_ne!(right, text, "the control must change the fixture");
    let (area_right, failed_right, notes_right) = mesh(&right, 0.01);
    assert_eq!((failed_right, notes_right.len()), (0, 0), "{notes_right:?}");
    assert!((area_right - area).abs() < 1e-9 * area);
}

#[test]
fn cone_patch_whose_loop_runs_clockwise_meshes_reversed() {
    // trj6_b1-ec-214.stp face #1157: a patch of a cone (radius 500, 2°) whose only bound runs
    // clockwise about the face normal, which would leave the face the unbounded rest of the
    // cone. Before: "the face has no boundary and its surface is unbounded".
    let text = data("cone_patch_clockwise.step");
    let (area, failed, notes) = mesh(&text, 0.005);
    assert_eq!(failed, 0);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("clockwise"), "{notes:?}");
    // Control: the face with its sense written right.
    let right = text.replace(
        "#1157=ADVANCED_FACE('',(#1158),#1185,.T.)",
        "#1157=ADVANCED_FACE('',(#1158),#1185,.F.)",
    );
    assert_ne!(right, text, "the control must change the fixture");
    let (area_right, failed_right, notes_right) = mesh(&right, 0.005);
    assert_eq!((failed_right, notes_right.len()), (0, 0), "{notes_right:?}");
    assert!(
        (area_right - area).abs() < 1e-9 * area,
        "{area} vs {area_right}"
    );
    // About 25 mm high and 0.25 rad around the 500 mm radius: the patch, not the cone.
    assert!(area > 1000.0 && area < 2000.0, "area {area}");
}

/// The unit cube with one edit, meshed: (volume, boundary and misoriented edges, notes).
fn cube_with(from: &str, to: &str) -> (f64, u64, u64, Vec<String>) {
    let text = data("unit_cube.step");
    let edited = text.replace(from, to);
    assert_ne!(edited, text, "the edit must change the cube");
    let file = StepFile::parse(edited.into_bytes()).expect("parses");
    let model = cadre_step::map_file(&file);
    let params = MeshParams {
        deflection: 0.01,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    assert!(mesh.failures.is_empty(), "{:?}", mesh.failures);
    let s = mesh_stats(&model, &mesh);
    let notes = mesh.repairs.iter().map(|r| r.note.clone()).collect();
    (s.volume, s.boundary_edges, s.misoriented_edges, notes)
}

#[test]
fn the_neighbours_tell_a_wrong_sense_from_a_wrong_bound() {
    // The cube's bottom face with its bound's orientation flipped: its loop runs clockwise and
    // its neighbours use its edges the same way it does, so the bound is wrong and the sense
    // right (trj9_ap209-mp.stp's planes).
    let (volume, open, misoriented, notes) = cube_with(
        "#106=FACE_OUTER_BOUND('',#105,.T.)",
        "#106=FACE_OUTER_BOUND('',#105,.F.)",
    );
    assert!((volume - 1.0).abs() < 1e-9, "volume {volume}");
    assert_eq!((open, misoriented), (0, 0));
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].contains("bounds are taken as reversed"),
        "{notes:?}"
    );
    // The same face with its sense flipped instead: the loop again runs clockwise, but now the
    // neighbours use its edges the other way round, so it is the sense that is wrong.
    let (volume, open, misoriented, notes) = cube_with(
        "#107=ADVANCED_FACE('bottom',(#106),#61,.F.)",
        "#107=ADVANCED_FACE('bottom',(#106),#61,.T.)",
    );
    assert!((volume - 1.0).abs() < 1e-9, "volume {volume}");
    assert_eq!((open, misoriented), (0, 0));
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("sense is taken as reversed"), "{notes:?}");
}
