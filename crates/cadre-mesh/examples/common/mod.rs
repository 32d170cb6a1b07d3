//! What the diagnostic examples share: reading a STEP file (exit with its message on error)
//! and the quality-bar mesh parameters.

use cadre_brep::Model;
use cadre_mesh::{MeshParams, deflection_diagonal};

/// Reads and maps `path`; prints the error and exits when the file cannot be read.
pub fn load(path: &str) -> Model {
    match cadre_step::syntax::StepFile::read(std::path::Path::new(path)) {
        Ok(f) => cadre_step::map_file(&f),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}

/// Deflection `rel` × the model's diagonal and the quality angle (0.1 rad).
#[allow(dead_code)] // Not every example uses it.
pub fn relative_params(model: &Model, rel: f64) -> MeshParams {
    MeshParams {
        deflection: rel * deflection_diagonal(model),
        angle: 0.1,
        ..MeshParams::default()
    }
}
