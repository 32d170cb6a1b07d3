//! Whole-model figures of a tessellation, counted per occurrence like a CAD kernel's
//! explorer (a part placed three times counts three times).

use cadre_brep::{Body, Model};

use crate::ModelMesh;
use crate::weld::{EdgeCensus, WeldedMesh};

/// Figures of a meshed model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshStats {
    /// Triangles over all occurrences.
    pub triangles: u64,
    /// Triangles stored (each part once).
    pub unique_triangles: u64,
    /// Mesh area over all occurrences, mm².
    pub area: f64,
    /// Enclosed volume of the solids over all occurrences, mm³.
    pub volume: f64,
    /// Solids over all occurrences.
    pub solids: u64,
    /// Boundary edges of solids and closed shells over all occurrences (0 when watertight).
    pub boundary_edges: u64,
    /// Edges of solids and closed shells used by more than two triangles.
    pub nonmanifold_edges: u64,
    /// Edges of solids and closed shells used twice in the same direction.
    pub misoriented_edges: u64,
    /// Boundary edges of open shells and loose faces (their natural border), over occurrences.
    pub open_boundary_edges: u64,
}

/// Per-part figures before multiplying by occurrences.
#[derive(Clone, Copy, Debug, Default)]
struct PartFigures {
    triangles: u64,
    area: f64,
    volume: f64,
    solids: u64,
    closed: EdgeCensus,
    open_boundary: u64,
}

fn add(c: &mut EdgeCensus, d: EdgeCensus) {
    c.boundary += d.boundary;
    c.nonmanifold += d.nonmanifold;
    c.misoriented += d.misoriented;
}

fn part_figures(model: &Model, mesh: &ModelMesh, bodies: &[Body]) -> PartFigures {
    let mut f = PartFigures::default();
    for body in bodies {
        match body {
            Body::Solid(id) => {
                let solid = &model.solids[id.index()];
                let mut volume = 0.0;
                for shell in solid.shells() {
                    let w = WeldedMesh::shell(model, mesh, shell);
                    f.triangles += w.triangles.len() as u64;
                    f.area += w.area();
                    // Voids subtract whatever their shells' stated orientation: files orient
                    // them either way (brep_wv1.stp's reversed void shells still face out of
                    // the void), and OCCT's reader reorients them too.
                    let v = w.signed_volume().abs();
                    volume += if shell == solid.outer { v } else { -v };
                    add(&mut f.closed, w.census());
                }
                f.volume += volume.abs();
                f.solids += 1;
            }
            Body::Shell(id) => {
                let w = WeldedMesh::shell(model, mesh, *id);
                f.triangles += w.triangles.len() as u64;
                f.area += w.area();
                let c = w.census();
                if model.shells[id.index()].closed {
                    add(&mut f.closed, c);
                } else {
                    f.open_boundary += c.boundary as u64;
                }
            }
            Body::Face(id) => {
                let mut w = WeldedMesh::default();
                w.add_faces(model, mesh, &[(*id, true)]);
                f.triangles += w.triangles.len() as u64;
                f.area += w.area();
                f.open_boundary += w.census().boundary as u64;
            }
            Body::Mesh(id) => {
                let m = &model.meshes[id.index()];
                let w = WeldedMesh::from_positions(&m.positions, &m.triangles);
                f.triangles += w.triangles.len() as u64;
                f.area += w.area();
                if m.solid_count > 0 {
                    f.volume += w.signed_volume().abs();
                    f.solids += u64::from(m.solid_count);
                    add(&mut f.closed, w.census());
                }
            }
            Body::Edge(_) | Body::Wire(_) | Body::Point(_) => {}
        }
    }
    f
}

/// Figures of `mesh` over every occurrence of `model`'s parts.
pub fn mesh_stats(model: &Model, mesh: &ModelMesh) -> MeshStats {
    let figures: Vec<PartFigures> = {
        use rayon::prelude::*;
        model
            .parts
            .par_iter()
            .map(|p| part_figures(model, mesh, &p.bodies))
            .collect()
    };
    let mut s = MeshStats {
        unique_triangles: figures.iter().map(|f| f.triangles).sum(),
        ..MeshStats::default()
    };
    model.visit_instances(|v| {
        let f = &figures[v.part.index()];
        // Scale factors of the placement (exact for similarities, which STEP placements are).
        let det = v.transform.matrix3.determinant().abs();
        let linear = det.cbrt();
        s.triangles += f.triangles;
        s.area += f.area * linear * linear;
        s.volume += f.volume * det;
        s.solids += f.solids;
        s.boundary_edges += f.closed.boundary as u64;
        s.nonmanifold_edges += f.closed.nonmanifold as u64;
        s.misoriented_edges += f.closed.misoriented as u64;
        s.open_boundary_edges += f.open_boundary;
    });
    s
}
