//! Assemblies built at test time from the corpus cube (`tr8_ha1_tc.stp`), as
//! `../shared/tools/bad_inputs.py` builds them: a chain of `levels` products each placing the
//! one below `uses` times, the cube's product at the bottom. Skipped when `../shared` is
//! absent.

use cadre_step::syntax::StepFile;

#[path = "common/hostile.rs"]
mod hostile;
use hostile::chain;

/// How many part instances with a body the model places.
fn placed_bodies(model: &cadre_brep::Model) -> usize {
    let mut n = 0;
    model.visit_instances(|v| {
        if !model.part(v.part).bodies.is_empty() {
            n += 1;
        }
    });
    n
}

/// 300 nested levels (`deep300.step` of the robustness issue) loaded as nothing, silently,
/// when the tree walks stopped at 256: now the cube is placed, with no warning.
#[test]
fn a_300_level_chain_loads_whole() {
    let Some(bytes) = chain(300, 1) else { return };
    let model = cadre_step::map_file(&StepFile::parse(bytes).unwrap());
    assert!(placed_bodies(&model) > 0);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    // The 200-level chain, which always loaded, places as many.
    let Some(bytes) = chain(200, 1) else { return };
    let shallow = cadre_step::map_file(&StepFile::parse(bytes).unwrap());
    assert_eq!(placed_bodies(&shallow), placed_bodies(&model));
}

/// Past the cap the tree is cut, and said to be, naming the part and its line.
#[test]
fn a_chain_past_the_cap_is_cut_with_a_warning() {
    let levels = cadre_brep::assembly::MAX_ASSEMBLY_DEPTH + 20;
    let Some(bytes) = chain(levels, 1) else {
        return;
    };
    let model = cadre_step::map_file(&StepFile::parse(bytes).unwrap());
    let w: Vec<String> = model.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.starts_with("line ") && w.contains("nests deeper than")),
        "{w:?}"
    );
}
