//! Where the seam line of a band around a cylinder goes (trj3_s1-md-214.stp face #1710): the
//! band's lower chain starts at the foot of a slot, and a seam line drawn from there runs up
//! across the slot's end, so the loop crossed itself and the face was meshed after a repair
//! that left the solid open. The line now starts where it crosses no chain.

use cadre_mesh::{MeshParams, mesh_model, mesh_stats};
use cadre_step::syntax::StepFile;

#[test]
fn a_band_with_a_slot_at_its_chain_start_meshes_without_repair() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/cylinder_band_slot_at_chain_start.step");
    let file = StepFile::read(&path).expect("fixture");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let params = MeshParams {
        deflection: 0.05,
        angle: 0.2,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    assert!(mesh.failures.is_empty(), "{:?}", mesh.failures);
    assert!(mesh.repairs.is_empty(), "{:?}", mesh.repairs);
    let area = mesh_stats(&model, &mesh).area;
    // OCCT's exact area of the face in the whole file (BRepGProp): 19,359.5 mm2.
    let exact = 19_359.5;
    assert!(
        (area - exact).abs() <= 2e-3 * exact,
        "area {area} vs OCCT's {exact}"
    );
}
