//! Faces with collapsed sides (poles, apexes).
//!
//! Runaway refinement (issue 12, class 6): t4mec.stp face #472 is a B-spline quarter sphere
//! (radius 100 mm) whose two pole sides are not quite collapsed (0.003 mm long, folded). The
//! grid took its steps from the curvature there and meshed the face into 203,898 triangles
//! at the default deflection, where OCCT needs about 2,900 for the whole file.
//!
//! Normals at an apex: a cone has one normal per ruling there, and every triangle about the
//! apex took the one of the parameter's convention (u = 0), which faces the other way from
//! the triangles across the apex: they were shaded as the cone's far side.

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

/// Corners of the scene's triangles whose normal faces away from their triangle (its
/// winding's normal), out of all corners; with `apex_normal`, every corner at `apex` takes
/// that normal instead (the control: one normal for the whole apex).
fn corners_facing_away(
    scene: &cadre_mesh::scene::Scene,
    apex: Option<([f32; 3], [f32; 3])>,
) -> (usize, usize) {
    let (mut away, mut all) = (0, 0);
    for mesh in &scene.meshes {
        let p = |i: u32| glam::Vec3::from(mesh.positions[i as usize]);
        for prim in &mesh.primitives {
            for t in prim.indices.chunks_exact(3) {
                let g = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
                for &i in t {
                    let mut n = glam::Vec3::from(mesh.normals[i as usize]);
                    if let Some((at, normal)) = apex
                        && p(i).distance(glam::Vec3::from(at)) < 1e-4
                    {
                        n = glam::Vec3::from(normal);
                    }
                    all += 1;
                    away += usize::from(n.dot(g) < 0.0);
                }
            }
        }
    }
    (away, all)
}

#[test]
fn triangles_about_an_apex_take_the_normal_of_their_own_ruling() {
    // A whole cone (radius 5 mm, apex at (12, 0, 10)) beside a dome.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cadre-render/tests/data/dome-and-cone.step");
    let file = StepFile::read(&path).expect("fixture");
    let model = cadre_step::map_file(&file);
    let params = MeshParams {
        deflection: 0.5,
        angle: 0.3,
        ..MeshParams::default()
    };
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh_model(&model, &params, None));
    let (away, all) = corners_facing_away(&scene, None);
    assert!(all > 50, "{all} corners");
    assert_eq!(
        away, 0,
        "{away} of {all} corners face away from their triangle"
    );
    // Control: the apex's corners all given one ruling's normal (the first one there).
    let mesh = &scene.meshes[0];
    let apex = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .min_by_key(|(p, _)| {
            let at = glam::Vec3::from(**p) - glam::Vec3::new(12.0, 0.0, 10.0);
            (at.length() * 1e6) as u64
        })
        .map(|(p, n)| (*p, *n))
        .expect("points");
    let (away_one, _) = corners_facing_away(&scene, Some(apex));
    assert!(
        away_one > 0,
        "apex {apex:?}: one normal fits every triangle"
    );
}
