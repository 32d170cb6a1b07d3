//! Fuzzes the whole pipeline a `cadre mesh -o x.glb` run goes through: parse arbitrary
//! bytes, map whatever parses onto a model, tessellate every face, assemble the placed scene
//! and write it as GLB (to memory), then check the scene's own invariants.
//!
//! Beyond `step_map` this exercises the edge discretisation, face triangulation, healing
//! (sliver zips, crack fills), the welded shells and the assembly of instances: no panic,
//! no hang, no unbounded allocation, and never a scene that fails its own validation.

#![no_main]

use cadre_mesh::{MeshParams, mesh_model};
use cadre_step::syntax::StepFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(file) = StepFile::parse(data.to_vec()) else {
        return;
    };
    let model = cadre_step::map_file(&file);
    // The CLI's default tolerances (`cadre mesh`): relative deflection and 0.5 rad.
    let params = MeshParams::relative(&model, 0.001, 0.5);
    let mesh = mesh_model(&model, &params, None);
    let _ = cadre_mesh::mesh_stats(&model, &mesh);
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh);
    // What the exporter assembles must always be a valid scene (indices in range, finite
    // positions, materials that exist); a failure here is a bug in meshing or assembly.
    if let Err(e) = scene.validate() {
        panic!("assembled scene is invalid: {e}");
    }
    let _ = scene.instance_triangle_count();
    let mut glb = Vec::new();
    cadre_mesh::export::gltf::write_glb(&scene, &mut glb).expect("a valid scene writes as GLB");
});
