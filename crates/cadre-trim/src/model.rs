//! The trim trees of a model's faces, built in parallel from the trim loops the model already
//! has (`cadre_brep::trim::face_trim` over one shared edge discretisation), each face's
//! (u, v) tolerances derived from an object-space tolerance and its surface's speeds.

use cadre_brep::trim::{TrimTolerance, face_surface, face_trim};
use cadre_brep::{FaceId, Model};
use cadre_geom::{Accuracy, Surface};
use cadre_mesh::MeshParams;
use cadre_mesh::edges::EdgeDiscretisation;
use rayon::prelude::*;

use crate::Uv;
use crate::fit::{UvTolerance, fit_points};
use crate::layout::{LayoutError, TrimBuffers};
use crate::quad::QuadPiece;
use crate::quadtree::TrimTree;

/// What building a model's trees gave.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrimStats {
    /// Faces of the model.
    pub faces: usize,
    /// Faces with a tree.
    pub built: usize,
    /// Trim curves (one edge's trace in one face's loops, seam and pole lines included).
    pub curves: usize,
    /// Monotone quadratic pieces.
    pub pieces: usize,
    /// Tree nodes.
    pub nodes: usize,
    /// Faces whose tree has a fallback leaf.
    pub fallback_faces: usize,
    /// Fallback leaves in all.
    pub fallback_leaves: usize,
    /// Those the depth cap made ([`TrimTree::capped_leaves`]).
    pub capped_leaves: usize,
    /// Faces whose tree is its root alone ([`crate::Leaf::All`]).
    pub root_only_faces: usize,
    /// Faces whose points are on their grid (a word a point, [`TrimTree::build_on_grid`]).
    pub grid_faces: usize,
    /// Bytes of the packed trees.
    pub bytes: usize,
}

/// A model's trees, packed, with where each face's lies.
#[derive(Clone, Debug, Default)]
pub struct ModelTrees {
    /// The packed trees.
    pub buffers: TrimBuffers,
    /// Per model face, its index in `buffers.faces`, or `None`.
    pub face_index: Vec<Option<u32>>,
    /// Per tree (as `buffers.faces`), the (u, v) tolerances it was fitted within.
    pub tolerances: Vec<UvTolerance>,
    /// The faces without a tree: STEP id and why (their meshes stand in for them).
    pub failures: Vec<(u64, String)>,
    /// Counts.
    pub stats: TrimStats,
}

/// Share of the tolerance the fitted pieces take (`fit_points` checks them against the
/// curve's samples and its estimated points between samples, not the polyline).
pub const FIT_SHARE: f64 = 0.75;
/// Share of the tolerance the grid's step may take (a point moves by at most a step onto
/// it; `TrimTree::build_on_grid`): with [`FIT_SHARE`], within 0.75 + 0.1·√2 ≈ 0.9 of the
/// tolerance at the checked points, the rest left for between them.
pub const GRID_SHARE: f64 = 0.1;

/// The trees of every face of `model`, within `eps` model units of the exact trims: the
/// edges are sampled to `eps / 2` (their points lie on the curves), the loops fitted within
/// [`FIT_SHARE`] of `eps` on the surface, and the pieces' points moved onto a 2¹⁶ grid of
/// the face's (u, v) box where its step is within [`GRID_SHARE`] of `eps` (one word a point).
pub fn model_trees(model: &Model, eps: f64) -> ModelTrees {
    let half = 0.5 * eps;
    let params = MeshParams {
        deflection: half,
        angle: 0.2,
        ..MeshParams::default()
    };
    let acc = Accuracy::default();
    let edges = EdgeDiscretisation::new(model, &params, acc);
    let tol = TrimTolerance {
        deflection: half,
        angle: 0.2,
        accuracy: acc,
        keep_exact: false,
    };
    let built: Vec<Result<(TrimTree, usize, UvTolerance), String>> = (0..model.faces.len())
        .into_par_iter()
        .map(|i| {
            let face = FaceId(i as u32);
            let trim = face_trim(model, face, &edges, &tol).map_err(|e| e.to_string())?;
            let surface = face_surface(model, face);
            let loops = loop_segments(&trim);
            let curves = loops.iter().map(Vec::len).sum();
            if curves == 0 {
                return Err("no trim loop".to_string());
            }
            let uv_tol = uv_tolerance(surface, loops.iter().flatten(), FIT_SHARE * eps);
            let grid_tol = UvTolerance {
                u: uv_tol.u * GRID_SHARE / FIT_SHARE,
                v: uv_tol.v * GRID_SHARE / FIT_SHARE,
            };
            let runs = closed_runs(loops, uv_tol);
            let pieces: Vec<QuadPiece> = runs.iter().flat_map(|r| fit_points(r, uv_tol)).collect();
            Ok((
                TrimTree::build_on_grid(&pieces, Some(grid_tol)),
                curves,
                uv_tol,
            ))
        })
        .collect();
    let mut out = ModelTrees {
        face_index: vec![None; model.faces.len()],
        ..ModelTrees::default()
    };
    out.stats.faces = model.faces.len();
    for (i, result) in built.into_iter().enumerate() {
        let step_id = model.faces[i].step_id;
        match result {
            Ok((tree, curves, uv_tol)) => match out.buffers.push(&tree) {
                Ok(index) => {
                    out.face_index[i] = Some(index as u32);
                    out.tolerances.push(uv_tol);
                    let s = &mut out.stats;
                    s.built += 1;
                    s.curves += curves;
                    s.pieces += tree.pieces.len();
                    s.nodes += tree.nodes.len();
                    let fallback = tree.fallback_leaves();
                    s.fallback_leaves += fallback;
                    s.fallback_faces += usize::from(fallback > 0);
                    s.capped_leaves += tree.capped_leaves();
                    s.grid_faces += usize::from(tree.on_grid);
                    s.root_only_faces += usize::from(matches!(
                        tree.nodes[0],
                        crate::Node::Leaf {
                            leaf: crate::Leaf::All,
                            ..
                        }
                    ));
                }
                Err(e @ LayoutError::TooLarge(_)) => out.failures.push((step_id, e.to_string())),
            },
            Err(why) => out.failures.push((step_id, why)),
        }
    }
    out.stats.bytes = out.buffers.bytes();
    out
}

/// A face's trim loops, each as its segments' (u, v) points (one edge's trace each, smooth:
/// the trim curves) with at least two points.
fn loop_segments(trim: &cadre_brep::trim::FaceTrim) -> Vec<Vec<Vec<Uv>>> {
    trim.loops
        .iter()
        .map(|l| {
            l.segments
                .iter()
                .map(|s| s.points.iter().map(|p| p.uv).collect::<Vec<Uv>>())
                .filter(|r| r.len() >= 2)
                .collect::<Vec<_>>()
        })
        .filter(|l| !l.is_empty())
        .collect()
}

/// The runs of (u, v) points to fit, loop by loop and in order, so that each loop's pieces
/// close exactly (the even-odd rule that [`crate::Leaf::All`] and fallback leaves count
/// leaves a row through a gap crossed once too few) and follow each other (the layout
/// shares their joints): between a segment's end and the next one's start, a straight run
/// where they are farther apart than a thousandth of `tol`, else the next start moved onto
/// the end (a narrower gap would only add a sliver piece meeting two others in every cell
/// down the tree).
fn closed_runs(loops: Vec<Vec<Vec<Uv>>>, tol: UvTolerance) -> Vec<Vec<Uv>> {
    let mut runs = Vec::new();
    for mut segments in loops {
        let n = segments.len();
        let mut bridges = vec![None; n];
        for k in 0..n {
            let end = segments[k][segments[k].len() - 1];
            let next = (k + 1) % n;
            let start = segments[next][0];
            if end == start {
                continue;
            }
            if tol.scaled(start - end) > 1e-3 {
                bridges[k] = Some(vec![end, start]);
            } else {
                segments[next][0] = end;
            }
        }
        for (segment, bridge) in segments.into_iter().zip(bridges) {
            runs.push(segment);
            runs.extend(bridge);
        }
    }
    runs
}

/// The (u, v) tolerances of a face: `eps` over the largest speeds `|∂S/∂u|`, `|∂S/∂v|` met at
/// its trim points and on a 5 × 5 grid over their box.
fn uv_tolerance<'a>(
    surface: &Surface,
    runs: impl Iterator<Item = &'a Vec<Uv>>,
    eps: f64,
) -> UvTolerance {
    let (mut lo, mut hi) = (Uv::splat(f64::INFINITY), Uv::splat(f64::NEG_INFINITY));
    let mut speed = (0.0f64, 0.0f64);
    let mut at = |p: Uv| {
        let d = surface.derivs(p.x, p.y);
        let (su, sv) = (d.du.length(), d.dv.length());
        if su.is_finite() && sv.is_finite() {
            speed = (speed.0.max(su), speed.1.max(sv));
        }
    };
    for p in runs.flatten() {
        lo = lo.min(*p);
        hi = hi.max(*p);
        at(*p);
    }
    for i in 0..5 {
        for j in 0..5 {
            let f = Uv::new(f64::from(i) / 4.0, f64::from(j) / 4.0);
            at(lo + f * (hi - lo));
        }
    }
    UvTolerance::from_speeds(eps, speed.0, speed.1)
}
