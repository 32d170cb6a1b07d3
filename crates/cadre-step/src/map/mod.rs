//! Mapping of the B-Rep, assembly and presentation content of AP203, AP214 and AP242 onto a
//! [`cadre_brep::Model`].
//!
//! The mapper starts from the product structure (product definitions, their shape
//! representations, assembly usages) and maps only what the model needs, on demand, caching
//! every mapped instance so shared geometry is shared in the model too. Each instance that
//! cannot be mapped becomes a warning naming its `#id` and line; what depends on it is skipped
//! and everything else still loads.

mod access;
mod context;
mod error;
mod geometry;
mod pmi;
mod product;
mod style;
mod tessellated;
mod topology;
mod units;

pub use error::{MapError, MapResult};

use crate::syntax::StepFile;
use cadre_brep::Model;

/// Maps everything the file holds into a model. Never fails: problems become
/// [`Model::warnings`], starting with the syntax diagnostics of the file.
pub fn map_file(file: &StepFile) -> Model {
    let mut mapper = context::Mapper::new(file);
    for d in file.diagnostics() {
        mapper.model.warn(d.id, Some(d.line), d.message.clone());
    }
    mapper.model.schemas = file.header().schemas.clone();
    product::map_products(&mut mapper);
    style::map_styles(&mut mapper);
    pmi::map_pmi(&mut mapper);
    let mut model = mapper.finish();
    report_vertex_repairs(&mut model, file);
    model
}

/// Moves vertices written off their edges' curves onto the curves' meeting point
/// ([`Model::snap_vertices_to_curves`]) and warns about each, naming the vertex.
fn report_vertex_repairs(model: &mut Model, file: &StepFile) {
    for m in model.snap_vertices_to_curves(cadre_geom::Accuracy::default()) {
        let id = model.vertices[m.vertex.index()].step_id;
        let (id, line) = if id == 0 {
            (None, None)
        } else {
            (Some(id), file.line(id))
        };
        model.warn(
            id,
            line,
            format!(
                "vertex lies {:.3e} mm off its edges' curves; moved {:.3e} mm to where they meet",
                m.off_curve,
                (m.to - m.from).length()
            ),
        );
    }
}
