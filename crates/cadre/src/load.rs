//! Loading a model file with the context a user needs when it fails.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
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
