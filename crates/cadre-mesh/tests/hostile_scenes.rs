//! Hostile assemblies (`../shared/tools/bad_inputs.py`'s deep and wide chains, built at test
//! time from the corpus cube) carried through meshing to the assembled scene: every instance
//! the model keeps is in the scene the writers and the renderer walk. A 300-level chain once
//! loaded whole and then exported nothing, because the scene walk stopped at 256 levels.
//! Skipped when `../shared` is absent.

#[path = "../../cadre-step/tests/common/hostile.rs"]
mod hostile;

use cadre_mesh::{MeshParams, mesh_model};
use cadre_step::syntax::StepFile;

/// Instances in the assembled scene, and placed body instances in the model.
fn scene_and_model_instances(bytes: Vec<u8>) -> (u64, u64) {
    let model = cadre_step::map_file(&StepFile::parse(bytes).expect("parses"));
    let params = MeshParams::relative(&model, 0.001, MeshParams::default().angle);
    let mesh = mesh_model(&model, &params, None);
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh);
    (
        scene.instances().count() as u64,
        model.placed_body_instances(),
    )
}

#[test]
fn a_300_level_chain_reaches_the_scene() {
    let Some(deep) = hostile::chain(300, 1) else {
        return;
    };
    let (scene, model) = scene_and_model_instances(deep);
    assert!(model >= 1, "the model places the cube");
    assert!(scene >= model, "scene {scene}, model {model}");
}

#[test]
fn a_wide_assembly_reaches_the_scene_whole() {
    let Some(wide) = hostile::chain(3, 10) else {
        return;
    };
    let (scene, model) = scene_and_model_instances(wide);
    // Negative control of the count itself: three levels of ten uses place 10³ cubes.
    assert!(model >= 1000, "{model}");
    assert!(scene >= model, "scene {scene}, model {model}");
}

#[test]
fn a_huge_assembly_shares_its_nodes_and_keeps_every_instance() {
    let Some(wide) = hostile::chain(6, 9) else {
        return;
    };
    let model = cadre_step::map_file(&StepFile::parse(wide).expect("parses"));
    let params = MeshParams::relative(&model, 0.001, MeshParams::default().angle);
    let mesh = mesh_model(&model, &params, None);
    let scene = cadre_mesh::assemble::build_scene(&model, &mesh);
    // 9⁶ = 531,441 uses, past SHARE_NODES_ABOVE: one node per occurrence in the file, not
    // one per instance, and the walk still reaches every instance.
    assert!(model.placed_instances() > cadre_mesh::assemble::SHARE_NODES_ABOVE);
    assert!(scene.nodes.len() < 100, "{} nodes", scene.nodes.len());
    let placed = model.placed_body_instances();
    assert!(placed >= 531_441, "{placed}");
    assert_eq!(scene.instances().count() as u64, placed);
}
