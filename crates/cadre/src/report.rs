//! What a tessellation lost or repaired, as warnings a user can act on: each names the STEP
//! instance and its line. `cadre mesh` prints them (and lists them in `--json`), `cadre
//! render` prints them too, so nothing is dropped, shrunk or left open silently.

use cadre_mesh::{ModelMesh, ShellDefect};
use cadre_step::syntax::StepFile;
use serde_json::{Value, json};

/// The losses and repairs of one meshed model.
pub struct MeshReport {
    /// Faces not meshed: (STEP id, reason).
    pub failed: Vec<(u64, String)>,
    /// Faces meshed after a repair of their trim or coarser than asked: (STEP id, what was
    /// done).
    pub repaired: Vec<(u64, String)>,
    /// Faces whose refinement stopped at the point budget.
    pub truncated: Vec<u64>,
    /// Solids and closed shells whose mesh is not watertight or lacks faces.
    pub open_shells: Vec<ShellDefect>,
}

impl MeshReport {
    /// Gathers the report of `mesh`, a tessellation of `model`.
    pub fn new(model: &cadre_brep::Model, mesh: &ModelMesh) -> MeshReport {
        MeshReport {
            failed: mesh
                .failures
                .iter()
                .map(|f| (f.step_id, f.reason.clone()))
                .collect(),
            repaired: mesh
                .repairs
                .iter()
                .map(|r| (r.step_id, r.note.clone()))
                .collect(),
            truncated: mesh
                .truncated
                .iter()
                .map(|f| model.faces[f.index()].step_id)
                .collect(),
            open_shells: cadre_mesh::shell_defects(model, mesh),
        }
    }

    /// One line per problem, `line N, #id: …`, worst first (lost faces, open solids, then
    /// repairs and truncations).
    pub fn warnings(&self, file: &StepFile) -> Vec<String> {
        let at = |id: u64| match file.line(id) {
            Some(line) => format!("line {line}, #{id}"),
            None => format!("#{id}"),
        };
        let mut out = Vec::new();
        for (id, reason) in &self.failed {
            out.push(format!("{}: face not meshed: {reason}", at(*id)));
        }
        for d in &self.open_shells {
            out.push(format!(
                "{}: {}",
                at(d.solid.unwrap_or(d.shell)),
                d.describe()
            ));
        }
        for (id, note) in &self.repaired {
            out.push(format!("{}: face meshed with a change: {note}", at(*id)));
        }
        for id in &self.truncated {
            out.push(format!(
                "{}: face refinement stopped at its point budget; the mesh may exceed the \
                 deflection there",
                at(*id)
            ));
        }
        out
    }

    /// The report's lists for `cadre mesh --json`.
    pub fn json(&self) -> [(&'static str, Value); 4] {
        [
            (
                "failed_faces",
                self.failed
                    .iter()
                    .map(|(id, reason)| json!({"face": id, "reason": reason}))
                    .collect(),
            ),
            (
                "repaired_faces",
                self.repaired
                    .iter()
                    .map(|(id, note)| json!({"face": id, "repair": note}))
                    .collect(),
            ),
            ("truncated_faces", json!(self.truncated)),
            (
                "open_shells",
                self.open_shells
                    .iter()
                    .map(|d| {
                        json!({
                            "solid": d.solid,
                            "shell": d.shell,
                            "boundary_edges": d.census.boundary,
                            "nonmanifold_edges": d.census.nonmanifold,
                            "misoriented_edges": d.census.misoriented,
                            "open_faces": d.open_faces.iter().map(|f| json!({"face": f.0, "edges": f.1})).collect::<Vec<_>>(),
                            "failed_faces": d.failed_faces,
                        })
                    })
                    .collect(),
            ),
        ]
    }
}
