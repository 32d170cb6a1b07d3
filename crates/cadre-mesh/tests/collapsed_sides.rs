//! Runaway refinement (issue 12, class 6): t4mec.stp face #472 is a B-spline quarter sphere
//! (radius 100 mm) whose two pole sides are not quite collapsed (0.003 mm long, folded). The
//! grid took its steps from the curvature there and meshed the face into 203,898 triangles
//! at the default deflection, where OCCT needs about 2,900 for the whole file.

use cadre_mesh::{MeshParams, mesh_model, mesh_stats};
use cadre_step::syntax::StepFile;

fn mesh(deflection: f64, angle: f64) -> (u64, f64) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/quarter_sphere_collapsed_sides.step");
    let file = StepFile::read(&path).expect("fixture");
    let model = cadre_step::map_file(&file);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let params = MeshParams {
        deflection,
        angle,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    assert!(mesh.failures.is_empty() && mesh.truncated.is_empty());
    let s = mesh_stats(&model, &mesh);
    (s.triangles, s.area)
}

#[test]
fn a_quarter_sphere_with_nearly_collapsed_sides_meshes_in_proportion() {
    // OCCT's exact area of the face (pi R^2 = 31415.93).
    const EXACT: f64 = 31415.92;
    for (deflection, angle, most) in [(2.29, 0.5, 5_000), (0.5, 0.1, 10_000), (0.1, 0.1, 40_000)] {
        let (triangles, area) = mesh(deflection, angle);
        assert!(
            triangles <= most,
            "{triangles} triangles at {deflection} mm / {angle} rad"
        );
        // A mesh of a sphere of radius R lies inside it by up to the deflection: its area is
        // short by about 2 × deflection / R at most.
        let short = (EXACT - area) / EXACT;
        assert!(
            (-1e-4..=2.0 * deflection / 100.0).contains(&short),
            "area {area} at {deflection} mm ({short:e} short)"
        );
    }
}
