//! Tessellation of one face in its (u, v) parameter domain: constrained Delaunay
//! triangulation (spade) of the closed trim polygons, refined until the chordal deviation and
//! the normal deviation are within [`MeshParams`].
//!
//! The boundary points come from the shared edge discretisation and are never moved or split,
//! so two faces meeting at an edge use exactly the same vertices there.

mod arrange;
mod cdt;
mod domain;
mod grid;
mod metric;
mod output;
mod refine;
mod repair;
#[cfg(test)]
mod repair_tests;
mod sliver;
#[cfg(test)]
mod tests;

use cadre_geom::{Surface, Vec2, Vec3};

use crate::MeshParams;
use metric::{Metric, StepTol};

/// A point of a trim polygon: its (u, v), its exact 3D position (taken from the shared edge
/// discretisation, not re-evaluated from `uv`), and the key that welds it to the same point in
/// other faces (edge samples, vertices) or elsewhere in this face (seams, poles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// Parameters on the face's surface (unwrapped: may lie outside the surface's first period).
    pub uv: Vec2,
    /// Exact position, model units.
    pub xyz: Vec3,
    /// Weld key: equal keys become one vertex of the body mesh.
    pub key: u64,
}

/// The region of a face in (u, v): closed polygons (the last point connects back to the
/// first, it is not repeated), the face on the left of each (outer boundaries
/// counter-clockwise, holes clockwise in (u, v)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceDomain {
    /// Closed polygons.
    pub loops: Vec<Vec<BoundaryPoint>>,
}

/// One vertex of a face mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPoint {
    /// Parameters on the surface.
    pub uv: Vec2,
    /// Position, model units.
    pub xyz: Vec3,
    /// Unit normal of the face (already flipped for a reversed face).
    pub normal: Vec3,
    /// Weld key of a boundary point; `None` for points inside the face.
    pub key: Option<u64>,
}

/// The triangles of one face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceMesh {
    /// Vertices.
    pub points: Vec<MeshPoint>,
    /// Triangles, counter-clockwise seen from the side the face normal points to.
    pub triangles: Vec<[u32; 3]>,
    /// Whether refinement stopped at [`MeshParams::max_face_points`] before meeting the
    /// tolerances.
    pub truncated: bool,
    /// Whether the trim loops conflicted (crossing segments, a point on another segment,
    /// coincident points) and were repaired: then some boundary points may be merged away and
    /// some boundary segments split at new unkeyed points, so the face may not weld exactly
    /// to its neighbours there (see [`triangulate_face`]).
    pub repaired: bool,
}

/// Why a face could not be triangulated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FaceMeshError {
    /// The domain has fewer than three distinct points or no area.
    #[error("the trim loops enclose no area")]
    EmptyDomain,
    /// A coordinate is NaN or infinite.
    #[error("a trim point is not finite")]
    NonFinite,
    /// The triangulator failed, even on the repaired trim loops.
    #[error("constrained triangulation failed: {0}")]
    Triangulation(String),
}

/// Triangulates `domain` on `surface`. `reversed` is true when the face normal is opposite to
/// the surface normal (face `same_sense` false, or the face used reversed by its shell); then
/// triangles and normals are flipped.
///
/// The boundary points are kept exactly (same `uv`, `xyz`, `key`) and every loop segment is
/// an edge of the mesh; interior points are added where the surface is curved, until every
/// triangle is within `params.deflection` of the surface and the normals at its corners are
/// within `params.angle` of each other, or the point budget `params.max_face_points` is spent
/// (then [`FaceMesh::truncated`] is set). Triangles with two corners of the same key (at a
/// pole or a collapsed seam) are left out.
///
/// Loops that conflict (segments crossing, a point on another segment, distinct points that
/// coincide in the triangulation plane) do not fail the face: it is triangulated again with
/// the conflicts repaired, and [`FaceMesh::repaired`] is set. Then the contract above holds
/// only approximately: coincident points are merged (the later ones' keys are missing from
/// the mesh), crossing segments are split at new points with no key, and the face is the
/// region of positive winding number of the loops (overlapping outer loops are united, a
/// hole sticking out of the outer loop cuts only what it overlaps).
///
/// # Errors
///
/// [`FaceMeshError::NonFinite`] for a NaN or infinite coordinate,
/// [`FaceMeshError::EmptyDomain`] when the loops enclose no area (fewer than three distinct
/// points, all collinear), [`FaceMeshError::Triangulation`] only if the triangulator fails
/// even on the repaired loops.
pub fn triangulate_face(
    surface: &Surface,
    reversed: bool,
    domain: &FaceDomain,
    params: &MeshParams,
) -> Result<FaceMesh, FaceMeshError> {
    let prep = domain::prepare(domain)?;
    guarded(|| mesh_prepared(surface, reversed, &prep, params))
}

/// Runs `f`, turning a panic into an error. Spade has had internal assertion failures on
/// near-degenerate constraint sets; one bad face must cost at most that attempt, not the
/// whole model.
fn guarded(f: impl FnOnce() -> Result<FaceMesh, FaceMeshError>) -> Result<FaceMesh, FaceMeshError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|_| {
        Err(FaceMeshError::Triangulation(
            "the triangulator failed on this domain".into(),
        ))
    })
}

/// [`triangulate_face`] after validation: first in the metric plane stretched as much as the
/// curvature asks ([`metric::WIDE_STRETCH`]) on a short point budget, and if refinement does
/// not converge within it, in the plane of bounded stretch ([`metric::MAX_STRETCH`]).
fn mesh_prepared(
    surface: &Surface,
    reversed: bool,
    prep: &domain::Prepared,
    params: &MeshParams,
) -> Result<FaceMesh, FaceMeshError> {
    let tol = StepTol::new(params);
    let planar = metric::is_planar(surface);
    let metric_with = |stretch| Metric::new(surface, prep.lo, prep.hi, &tol, planar, stretch);
    let (wide, capped) = (
        metric_with(metric::WIDE_STRETCH),
        metric_with(metric::MAX_STRETCH),
    );
    if !planar && wide.su != capped.su {
        let first = mesh_in_plane(surface, reversed, prep, params, wide, Some(WIDE_GROWTH));
        if first.as_ref().is_ok_and(|m| !m.truncated) {
            return first;
        }
        tracing::debug!("refinement ran away in the wide metric; bounded stretch instead");
    }
    mesh_in_plane(surface, reversed, prep, params, capped, None)
}

/// How many times its grid and boundary points a face may grow in the wide metric before it
/// falls back to the bounded stretch. Runaway refinement doubles the points every round
/// (bug30053.stp #944: 74, 128, 213, 417, 679, ...) while a converging face rarely needs more
/// than a few times its start.
const WIDE_GROWTH: usize = 4;

/// One triangulation in the plane of `metric`: the strict triangulation, and when the loops
/// conflict, the repaired ones (see [`repair`]) from the most faithful to the most robust.
/// `growth`: a tighter refinement budget, in multiples of the start points (see [`Job::run`]).
fn mesh_in_plane(
    surface: &Surface,
    reversed: bool,
    prep: &domain::Prepared,
    params: &MeshParams,
    metric: Metric,
    growth: Option<usize>,
) -> Result<FaceMesh, FaceMeshError> {
    let tol = StepTol::new(params);
    let planar = metric::is_planar(surface);
    // The boundary is never thinned, so it may exceed the budget on its own.
    let max_points = params.max_face_points.max(prep.points.len());
    let budget = max_points - prep.points.len();

    let grid = if planar {
        grid::Grid::default()
    } else {
        grid::interior_points(surface, prep, &tol, &metric, budget)
    };

    let mut pts = Points::with_capacity(prep.points.len() + grid.points.len());
    // A plane has one normal; computing it once keeps plane faces at the cost of the CDT.
    let plane_normal = planar.then(|| {
        let c = 0.5 * (prep.lo + prep.hi);
        surface.normal(c.x, c.y)
    });
    for p in &prep.points {
        let (on_surface, n) = match plane_normal {
            Some(n) => (surface.eval(p.uv.x, p.uv.y), n),
            None => refine::sample(surface, p.uv),
        };
        pts.push(p.uv, p.xyz, n, Some(p.key));
        pts.off_surface.push(p.xyz - on_surface);
    }
    // Boundary segments whose ends weld together lie on a line the surface collapses to one
    // point (a pole, an apex). The (u, v) → 3D map folds there, so refinement leaves the
    // triangles touching it alone; the ring of points `grid` put along it makes them right.
    pts.collapsed = vec![false; prep.points.len()];
    for &[a, b] in &prep.edges {
        if prep.points[a as usize].key == prep.points[b as usize].key {
            pts.collapsed[a as usize] = true;
            pts.collapsed[b as usize] = true;
        }
    }
    for &uv in &grid.points {
        let (x, n) = refine::sample(surface, uv);
        pts.push(uv, x, n, None);
    }

    let job = Job {
        surface,
        reversed,
        prep,
        metric,
        tol,
        planar,
        max_points,
        growth,
        truncated: grid.truncated,
        pts,
    };
    let reason = match guarded(|| job.run(None, true)) {
        Err(FaceMeshError::Triangulation(reason)) => reason,
        done => return done,
    };
    // A thin face whose chords cross needs no split point: its boundary alone, clipped
    // into ears, welds to the neighbours (see `sliver`).
    if let Ok(Some(m)) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        sliver::triangulate(surface, reversed, prep, &job.pts, &job.metric, &tol)
    })) {
        tracing::debug!(%reason, triangles = m.triangles.len(), "crossing trim loop clipped from its boundary alone");
        return Ok(m);
    }
    // Splitting keeps the whole boundary in the mesh; skipping cannot fail on crossings; no
    // refinement is the last resort should refinement trip over the repaired triangulation.
    let mut last = Err(FaceMeshError::Triangulation(reason.clone()));
    for (mode, refine) in [
        (repair::Mode::Split, true),
        (repair::Mode::Skip, true),
        (repair::Mode::Skip, false),
    ] {
        last = guarded(|| job.run(Some(mode), refine));
        if let Ok(m) = &last {
            tracing::debug!(%reason, ?mode, refine, triangles = m.triangles.len(), "trim loops repaired");
            break;
        }
    }
    last
}

/// Smallest point budget of a repaired face (see [`Job::run`]).
const REPAIRED_MIN_BUDGET: usize = 50_000;

/// How many times its grid and boundary points a sound face may grow by refinement.
const SOUND_GROWTH: usize = 24;

/// Smallest point budget of a sound face.
const SOUND_MIN_BUDGET: usize = 20_000;

/// Everything one triangulation attempt needs; the grid is computed once for all attempts.
struct Job<'a> {
    surface: &'a Surface,
    reversed: bool,
    prep: &'a domain::Prepared,
    metric: Metric,
    tol: StepTol,
    planar: bool,
    max_points: usize,
    /// A tighter refinement budget, in multiples of the start points.
    growth: Option<usize>,
    truncated: bool,
    /// Boundary points, then the interior grid points.
    pts: Points,
}

impl Job<'_> {
    /// Triangulates strictly (`repair` `None`: every segment one constraint edge, or an
    /// error) or with the conflicts repaired, refines unless told not to, and assembles.
    fn run(&self, repair: Option<repair::Mode>, refine: bool) -> Result<FaceMesh, FaceMeshError> {
        let mut pts = self.pts.clone();
        let (mut tri, mut inside) = match repair {
            None => {
                let verts = (0..pts.len())
                    .map(|i| cdt::Vert {
                        pos: self.metric.to_plane(pts.uv[i]),
                        id: i as u32,
                    })
                    .collect();
                let edges = self
                    .prep
                    .edges
                    .iter()
                    .map(|e| [e[0] as usize, e[1] as usize])
                    .collect();
                let tri = cdt::build(verts, edges)?;
                let mut inside = Vec::new();
                cdt::classify(&tri, &self.prep.even_edges, &mut inside);
                (tri, inside)
            }
            Some(mode) => {
                let r = repair::build(self.surface, self.prep, &self.metric, &mut pts, mode)?;
                tracing::debug!(
                    merged = r.merged,
                    skipped = r.skipped,
                    split_points = r.split_points,
                    "repaired trim loops"
                );
                (r.cdt, r.inside)
            }
        };
        let mut truncated = self.truncated;
        // Conflicting loops often come from a wrong trim (a loop retracing a pole line, a
        // misplaced edge) whose region refinement can never satisfy: on trj2_f1-db-214.stp
        // such faces refined to the full point budget, 17 s each. A repaired face gets a
        // budget proportional to what the grid needed, generous for a sound face with one
        // bad crossing.
        //
        // Sound faces get a wider but still proportional budget: refinement normally adds a
        // few times the grid's points, while a face it cannot satisfy (slivers standing on
        // the surface on narrow B-spline bands, trj9_io1-sy-214.stp face #439, root cause
        // not found yet) would otherwise grow to the whole point budget, ~10 s a face. Such a
        // face is reported as truncated.
        let max_points = match (self.growth, repair) {
            (Some(g), _) => self.max_points.min(g * pts.len()),
            (None, None) => self
                .max_points
                .min((SOUND_GROWTH * pts.len()).max(SOUND_MIN_BUDGET)),
            (None, Some(_)) => self
                .max_points
                .min((8 * pts.len()).max(REPAIRED_MIN_BUDGET)),
        };
        if refine && !self.planar {
            truncated |= refine::refine(
                self.surface,
                &self.metric,
                &self.tol,
                &mut tri,
                &mut pts,
                &mut inside,
                max_points,
            );
        }
        Ok(output::assemble(
            self.surface,
            self.reversed,
            &tri,
            &pts,
            &inside,
            truncated,
            repair.is_some(),
        ))
    }
}

/// The mesh points under construction, by id (boundary points first, then interior ones),
/// as parallel arrays.
#[derive(Clone, Debug, Default)]
pub(crate) struct Points {
    /// Parameters.
    pub uv: Vec<Vec2>,
    /// Positions.
    pub xyz: Vec<Vec3>,
    /// Unit surface normals (not flipped for reversed faces); `None` at singular points.
    pub normal: Vec<Option<Vec3>>,
    /// Weld keys of boundary points.
    pub key: Vec<Option<u64>>,
    /// Whether a boundary point lies on a collapsed segment (pole line); shorter than the
    /// other arrays (interior points are never collapsed).
    pub collapsed: Vec<bool>,
    /// How far each boundary point (the shared edge sample) lies from the surface at its
    /// (u, v): files whose edges stray from their faces' surfaces (bug29478.stp: 16× the
    /// deflection) give boundary corners refinement cannot move. Shorter than the other
    /// arrays: interior points lie on the surface.
    pub off_surface: Vec<Vec3>,
}

impl Points {
    fn with_capacity(n: usize) -> Points {
        Points {
            uv: Vec::with_capacity(n),
            xyz: Vec::with_capacity(n),
            normal: Vec::with_capacity(n),
            key: Vec::with_capacity(n),
            collapsed: Vec::new(),
            off_surface: Vec::new(),
        }
    }

    /// Appends a point; its id is the previous length.
    pub fn push(&mut self, uv: Vec2, xyz: Vec3, normal: Option<Vec3>, key: Option<u64>) {
        self.uv.push(uv);
        self.xyz.push(xyz);
        self.normal.push(normal);
        self.key.push(key);
    }

    /// The surface point at point `id`'s (u, v): its position less its distance from the
    /// surface. Refinement measures triangles built on these, so it chases only the error it
    /// can fix (the flat triangles' distance from the surface), not the file's own gaps.
    pub fn on_surface(&self, id: u32) -> Vec3 {
        let i = id as usize;
        self.xyz[i] - self.off_surface.get(i).copied().unwrap_or(Vec3::ZERO)
    }

    /// How far point `id` lies from the surface at its (u, v) (zero inside the face).
    pub fn gap(&self, id: u32) -> f64 {
        self.off_surface
            .get(id as usize)
            .map_or(0.0, |g| g.length())
    }

    /// Whether point `id` lies on a collapsed boundary line (a pole, an apex).
    pub fn is_collapsed(&self, id: u32) -> bool {
        self.collapsed.get(id as usize).is_some_and(|&c| c)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.uv.len()
    }
}
