//! A hole across a cylinder's seam (trj4_pm2-ec-214.stp face #21376): the face's one loop runs
//! down the seam, around a cut-out bounded by two B-splines that meet the seam at two points,
//! and on to the far circle. With the seam edges taken out, the cut-out falls into two open
//! pieces, which were each "closed with a straight segment" (a chord across the hole, and a
//! repair note). They are now joined into the hole they are.

use cadre_mesh::{MeshParams, mesh_model, mesh_stats};
use cadre_step::syntax::StepFile;

#[test]
fn a_hole_across_the_seam_is_one_closed_chain() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/cylinder_hole_across_seam.step");
    let file = StepFile::read(&path).expect("fixture");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let params = MeshParams {
        deflection: 0.01,
        angle: 0.2,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    assert!(mesh.failures.is_empty(), "{:?}", mesh.failures);
    assert!(mesh.repairs.is_empty(), "{:?}", mesh.repairs);
    // The band between the two circles (radius 16.81, 33.02 apart) less the cut-out: under
    // the band's 2 pi r h = 3487 mm2, and more than half of it.
    let area = mesh_stats(&model, &mesh).area;
    assert!(area > 1750.0 && area < 3487.0, "area {area}");
}
