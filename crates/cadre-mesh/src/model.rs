//! Meshing a whole model: edges once, then every face in parallel from its trim.

use cadre_brep::trim::{FaceTrim, TrimTolerance, face_trim};
use cadre_brep::{FaceId, Model};
use cadre_geom::Accuracy;

use crate::periodic::{unwrapped_surface, uv_bounds};
use rayon::prelude::*;

use crate::MeshParams;
use crate::edges::EdgeDiscretisation;
use crate::face::{BoundaryPoint, FaceDomain, FaceMesh, triangulate_face};

/// A face that could not be tessellated, with the reason.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceFailure {
    /// The face.
    pub face: FaceId,
    /// Its STEP instance id.
    pub step_id: u64,
    /// Why.
    pub reason: String,
}

/// A face that was meshed after a repair of its trim (sense turned over, loops reversed,
/// crossing loops cut, …) or coarser than asked (see `FACE_RELATIVE_FLOOR`): meshed, but not
/// as the file wrote it or the caller asked.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceRepair {
    /// The face.
    pub face: FaceId,
    /// Its STEP instance id.
    pub step_id: u64,
    /// What was repaired.
    pub note: String,
}

/// The tessellation of every face of a model.
#[derive(Clone, Debug, Default)]
pub struct ModelMesh {
    /// Per face id: its triangles (`None` when it failed, see `failures`).
    pub faces: Vec<Option<FaceMesh>>,
    /// Faces that could not be tessellated.
    pub failures: Vec<FaceFailure>,
    /// Faces whose refinement stopped at the point budget.
    pub truncated: Vec<FaceId>,
    /// Faces meshed after a repair of their trim or coarser than asked, one entry each.
    pub repairs: Vec<FaceRepair>,
    /// The shared edge samples.
    pub edges: EdgeDiscretisation,
    /// The tolerances the model was meshed with (wire curves are sampled with them too).
    pub params: MeshParams,
}

/// The trim polygons of a face as the triangulator takes them.
pub fn face_domain(trim: &FaceTrim) -> FaceDomain {
    FaceDomain {
        loops: trim
            .loops
            .iter()
            .map(|l| {
                l.polygon()
                    .into_iter()
                    .map(|p| BoundaryPoint {
                        uv: p.uv,
                        xyz: p.xyz,
                        key: p.key,
                    })
                    .collect()
            })
            .collect(),
    }
}

/// Tessellates every face of `model`. `progress` is called with the number of faces done
/// so far (from worker threads).
pub fn mesh_model(
    model: &Model,
    params: &MeshParams,
    progress: Option<&(dyn Fn(usize) + Sync)>,
) -> ModelMesh {
    let acc = Accuracy::default();
    let edges = EdgeDiscretisation::new(model, params, acc);
    let tol = TrimTolerance {
        deflection: params.deflection,
        angle: params.angle,
        accuracy: acc,
        keep_exact: false,
    };
    let done = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<(Result<FaceMesh, String>, Vec<String>)> = (0..model.faces.len())
        .into_par_iter()
        .map(|i| {
            let id = FaceId(i as u32);
            tracing::debug!(face = model.faces[i].step_id, "meshing face");
            let started = std::time::Instant::now();
            let (r, notes) = mesh_face_noted(model, id, &edges, &tol, params);
            let seconds = started.elapsed().as_secs_f64();
            tracing::debug!(
                face = model.faces[i].step_id,
                seconds,
                triangles = r.as_ref().map_or(0, |m| m.triangles.len()),
                "face meshed"
            );
            if seconds > 0.5 {
                tracing::info!(
                    face = model.faces[i].step_id,
                    seconds,
                    triangles = r.as_ref().map_or(0, |m| m.triangles.len()),
                    "slow face"
                );
            }
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            if let Some(f) = progress {
                f(n);
            }
            (r, notes)
        })
        .collect();
    let mut out = ModelMesh {
        faces: Vec::with_capacity(results.len()),
        failures: Vec::new(),
        truncated: Vec::new(),
        repairs: Vec::new(),
        edges,
        params: *params,
    };
    for (i, (r, notes)) in results.into_iter().enumerate() {
        let id = FaceId(i as u32);
        let step_id = model.faces[i].step_id;
        out.repairs.extend(notes.into_iter().map(|note| FaceRepair {
            face: id,
            step_id,
            note,
        }));
        match r {
            Ok(m) => {
                if m.truncated {
                    out.truncated.push(id);
                }
                out.faces.push(Some(m));
            }
            Err(reason) => {
                out.failures.push(FaceFailure {
                    face: id,
                    step_id: model.faces[i].step_id,
                    reason,
                });
                out.faces.push(None);
            }
        }
    }
    let closed = crate::crack::close_cracks(model, &mut out);
    out.repairs.extend(closed);
    out
}

/// Trim and triangulation of one face.
pub fn mesh_face(
    model: &Model,
    id: FaceId,
    edges: &EdgeDiscretisation,
    tol: &TrimTolerance,
    params: &MeshParams,
) -> Result<FaceMesh, String> {
    mesh_face_noted(model, id, edges, tol, params).0
}

/// A face is never refined finer than this fraction of its own size (the box of its
/// surface over its trimmed (u, v) rectangle). A relative deflection is taken of the model's
/// edges; a face the trimmer reads as far larger than its edges (a torus whose only loop is a
/// tiny hole, fuzzed) was refined to its 500,000-point budget: 995,902 triangles in 2.6 s for
/// two faces, now 254,272 in 0.9 s. Real faces lie within the model, so this applies to them
/// only when their edges span under a tenth of the face at a relative deflection of 10⁻⁴ (at
/// 10⁻⁴ of the face, the corpus's torus-with-a-hole bug28414 was floored at fine settings; at
/// 10⁻⁵ no corpus face is).
const FACE_RELATIVE_FLOOR: f64 = 1e-5;

/// [`mesh_face`], with the repairs its trim and triangulation needed.
fn mesh_face_noted(
    model: &Model,
    id: FaceId,
    edges: &EdgeDiscretisation,
    tol: &TrimTolerance,
    params: &MeshParams,
) -> (Result<FaceMesh, String>, Vec<String>) {
    let face = &model.faces[id.index()];
    let surface = &model.surfaces[face.surface.index()];
    let mut trim = match face_trim(model, id, edges, tol) {
        Ok(t) => t,
        Err(e) => return (Err(format!("trim: {e}")), Vec::new()),
    };
    let mut notes = std::mem::take(&mut trim.notes);
    let domain = face_domain(&trim);
    let (lo, hi) = uv_bounds(domain.loops.iter().flatten().map(|p| p.uv));
    let extended = unwrapped_surface(surface, lo, hi);
    let surface = extended.as_ref().unwrap_or(surface);
    let own_size = surface.bbox_over(lo.x, hi.x, lo.y, hi.y).diagonal();
    let floored = MeshParams {
        deflection: FACE_RELATIVE_FLOOR * own_size,
        ..*params
    };
    let params = if own_size.is_finite() && params.deflection < floored.deflection {
        notes.push(format!(
            "meshed at a deflection of {:.3e} mm ({FACE_RELATIVE_FLOOR:e} of the face's own \
             size), not the {:.3e} mm asked: the face is far larger than the box the relative \
             deflection was taken of (its edges span less than the face)",
            floored.deflection, params.deflection
        ));
        &floored
    } else {
        params
    };
    let r = triangulate_face(surface, trim.reversed, &domain, params)
        .map_err(|e| format!("triangulation: {e}"));
    if r.as_ref().is_ok_and(|m| m.repaired) {
        notes.push(
            "conflicting trim loops (crossing or touching segments, repeated points) were \
             repaired; the face may not weld to its neighbours there"
                .into(),
        );
    }
    (r, notes)
}
