//! `shell_defects` names every solid whose mesh lost a face or is open (issue 12: nothing
//! dropped silently), and nothing for a watertight one.

use cadre_mesh::{FaceFailure, MeshParams, mesh_model, shell_defects};
use cadre_step::syntax::StepFile;

/// A unit cube solid #80 with its six planar faces, in millimetres.
const CUBE: &str = include_str!("data/unit_cube.step");

#[test]
fn a_solid_that_lost_a_face_is_reported_with_its_ids() {
    let file = StepFile::parse(CUBE.as_bytes().to_vec()).expect("parses");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let params = MeshParams {
        deflection: 0.01,
        ..MeshParams::default()
    };
    let mut mesh = mesh_model(&model, &params, None);
    // Control: the whole cube is watertight and reported as nothing.
    assert!(shell_defects(&model, &mesh).is_empty());
    // Lose one face, as a face that fails to mesh does.
    let lost = model.faces[0].step_id;
    mesh.faces[0] = None;
    mesh.failures.push(FaceFailure {
        face: cadre_brep::FaceId(0),
        step_id: lost,
        reason: "test".into(),
    });
    let d = shell_defects(&model, &mesh);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(d[0].solid, Some(model.solids[0].step_id));
    assert_eq!(d[0].failed_faces, vec![lost]);
    assert!(d[0].census.boundary > 0);
    // The four faces around the hole hold its open edges.
    assert_eq!(d[0].open_faces.len(), 4, "{:?}", d[0].open_faces);
    let text = d[0].describe();
    assert!(
        text.contains(&format!("#{lost}")) && text.contains("not meshed"),
        "{text}"
    );
}
