//! Loading a model file with the context a user needs when it fails.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use cadre_brep::Model;
use cadre_step::syntax::StepFile;

/// A model with the parsed file it came from and how long each stage took.
pub struct Loaded {
    /// The parsed exchange structure.
    pub file: StepFile,
    /// The mapped model.
    pub model: Model,
    /// Seconds spent reading and parsing.
    pub parse_seconds: f64,
    /// Seconds spent mapping to the B-Rep model.
    pub map_seconds: f64,
}

/// Reads and maps a STEP file.
pub fn load_step(path: &Path) -> Result<Loaded> {
    let t0 = Instant::now();
    let file = StepFile::read(path).with_context(|| format!("reading {}", path.display()))?;
    let parse_seconds = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let model = cadre_step::map_file(&file);
    Ok(Loaded {
        file,
        model,
        parse_seconds,
        map_seconds: t1.elapsed().as_secs_f64(),
    })
}

/// Refuses, before any meshing, a model whose assembly expands to more part instances than
/// one scene holds ([`cadre_mesh::assemble::MAX_NODES`], one node each): the scene builder
/// would cut the tree there. `holder` names what holds the nodes ("export", "scene") and
/// `nothing` says what was not done, for the message.
pub fn check_scene_nodes(model: &Model, input: &Path, holder: &str, nothing: &str) -> Result<()> {
    let nodes = model.placed_instances();
    let cap = cadre_mesh::assemble::MAX_NODES;
    if nodes > cap as u64 {
        bail!(
            "{}: the assembly expands to {nodes} part instances, over the {cap} one {holder}; {nothing}",
            input.display()
        );
    }
    Ok(())
}
