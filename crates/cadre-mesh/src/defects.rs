//! What a tessellation lost, per body: the solids and closed shells whose mesh is not
//! watertight (boundary, non-manifold or misoriented edges), with the faces along their open
//! edges and the faces that could not be meshed at all. A CAD viewer must never lose a face,
//! a shell or a solid silently: `cadre mesh --json` and `cadre render` print these.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use cadre_brep::{Body, Model, ShellId};

use crate::ModelMesh;
use crate::weld::{EdgeCensus, WeldedMesh};

/// A solid's or closed shell's mesh that is not closed, or that lacks faces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShellDefect {
    /// STEP id of the solid, when the shell bounds one.
    pub solid: Option<u64>,
    /// STEP id of the shell.
    pub shell: u64,
    /// Its edge census (boundary edges: holes or cracks; 0 when watertight).
    pub census: EdgeCensus,
    /// STEP ids of the faces holding boundary edges, with how many each holds (most first).
    pub open_faces: Vec<(u64, usize)>,
    /// STEP ids of the shell's faces that could not be meshed (see `ModelMesh::failures`).
    pub failed_faces: Vec<u64>,
}

impl ShellDefect {
    /// One line for a warning: what is wrong and where.
    pub fn describe(&self) -> String {
        let what = match self.solid {
            Some(s) => format!("solid #{s} (shell #{})", self.shell),
            None => format!("closed shell #{}", self.shell),
        };
        let mut parts = Vec::new();
        if !self.failed_faces.is_empty() {
            parts.push(format!(
                "{} face(s) not meshed ({})",
                self.failed_faces.len(),
                ids(self.failed_faces.iter().copied())
            ));
        }
        if self.census.boundary > 0 {
            parts.push(format!(
                "{} open edge(s) along face(s) {}",
                self.census.boundary,
                ids(self.open_faces.iter().map(|f| f.0))
            ));
        }
        if self.census.nonmanifold > 0 {
            parts.push(format!("{} non-manifold edge(s)", self.census.nonmanifold));
        }
        if self.census.misoriented > 0 {
            parts.push(format!("{} misoriented edge(s)", self.census.misoriented));
        }
        format!("{what} is not watertight: {}", parts.join("; "))
    }
}

/// `#a, #b, …` for at most eight ids.
fn ids(ids: impl Iterator<Item = u64>) -> String {
    let all: Vec<u64> = ids.collect();
    let mut s: Vec<String> = all.iter().take(8).map(|i| format!("#{i}")).collect();
    if all.len() > 8 {
        s.push(format!("… {} more", all.len() - 8));
    }
    s.join(", ")
}

/// Every solid shell and closed shell of `model` (each once, however often it is placed)
/// whose mesh is not watertight or lacks faces, in STEP id order.
pub fn shell_defects(model: &Model, mesh: &ModelMesh) -> Vec<ShellDefect> {
    let failed: HashSet<u64> = mesh.failures.iter().map(|f| f.step_id).collect();
    // Closed shells to check: the shells of solids, and closed shells standing alone.
    let mut shells: BTreeMap<u32, Option<u64>> = BTreeMap::new();
    for part in &model.parts {
        for body in &part.bodies {
            match body {
                Body::Solid(id) => {
                    let solid = &model.solids[id.index()];
                    for shell in solid.shells() {
                        shells.insert(shell.0, Some(solid.step_id));
                    }
                }
                Body::Shell(id) if model.shells[id.index()].closed => {
                    shells.entry(id.0).or_insert(None);
                }
                _ => {}
            }
        }
    }
    use rayon::prelude::*;
    let shells: Vec<(u32, Option<u64>)> = shells.into_iter().collect();
    let mut out: Vec<ShellDefect> = shells
        .par_iter()
        .filter_map(|&(shell, solid)| shell_defect(model, mesh, ShellId(shell), solid, &failed))
        .collect();
    out.sort_by_key(|d| (d.solid, d.shell));
    out
}

fn shell_defect(
    model: &Model,
    mesh: &ModelMesh,
    shell: ShellId,
    solid: Option<u64>,
    failed: &HashSet<u64>,
) -> Option<ShellDefect> {
    let sh = &model.shells[shell.index()];
    let failed_faces: Vec<u64> = sh
        .faces
        .iter()
        .map(|(f, _)| model.faces[f.index()].step_id)
        .filter(|id| failed.contains(id))
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let w = WeldedMesh::shell(model, mesh, shell);
    let census = w.census();
    if census == EdgeCensus::default() && failed_faces.is_empty() {
        return None;
    }
    let mut uses: HashMap<(u32, u32), (u32, usize)> = HashMap::new();
    for (i, t) in w.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            uses.entry((a.min(b), a.max(b))).or_insert((0, i)).0 += 1;
        }
    }
    let mut open: BTreeMap<u64, usize> = BTreeMap::new();
    for &(n, tri) in uses.values() {
        if n == 1 {
            *open.entry(w.triangle_faces[tri]).or_default() += 1;
        }
    }
    let mut open_faces: Vec<(u64, usize)> = open.into_iter().collect();
    open_faces.sort_by_key(|&(id, n)| (std::cmp::Reverse(n), id));
    Some(ShellDefect {
        solid,
        shell: sh.step_id,
        census,
        open_faces,
        failed_faces,
    })
}
