//! The spade constrained Delaunay triangulation in the scaled parameter plane: building it
//! from the boundary, even-odd classification of its triangles, and guarded insertion.

use std::collections::HashSet;

use spade::handles::{FixedFaceHandle, FixedVertexHandle, PossiblyOuterTag};
use spade::{
    ConstrainedDelaunayTriangulation, HasPosition, LastUsedVertexHintGenerator, Point2,
    PositionInTriangulation, Triangulation,
};

use super::FaceMeshError;
use super::domain::edge_key;

/// A triangulation vertex: its scaled position and the id of the point it stands for.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vert {
    /// Position in the scaled (u, v) plane.
    pub pos: Point2<f64>,
    /// Index into the mesh's point arrays.
    pub id: u32,
}

impl HasPosition for Vert {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

/// Sorted vertex ids of a triangle that already met the tolerances. Spade keeps face data
/// through edge flips, so the ids, not a flag, tell whether the face is still that triangle;
/// the default (all zero) never matches a real triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct FaceSig(pub [u32; 3]);

/// Sorted vertex ids of an edge whose midpoint already met the deflection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct EdgeSig(pub [u32; 2]);

/// The triangulation type used for faces.
pub(crate) type Cdt =
    ConstrainedDelaunayTriangulation<Vert, (), EdgeSig, FaceSig, LastUsedVertexHintGenerator>;

/// Bulk-loads `verts` with the constraint `edges` (indices into `verts`). Crossing
/// constraints are an error: the trim loops intersect each other or themselves.
///
/// Every segment must come out as one constraint edge: a loop vertex lying exactly on
/// another segment makes spade split that segment (and share the pieces between loops),
/// which breaks the boundary contract and the even-odd classification, so it is rejected
/// too, as are distinct points that coincide once scaled. Such loops are then triangulated
/// by [`super::repair`], which relaxes these rules.
pub(crate) fn build(verts: Vec<Vert>, edges: Vec<[usize; 2]>) -> Result<Cdt, FaceMeshError> {
    let n = verts.len();
    let mut conflicts = 0usize;
    let (cdt, handles) = match non_collinear_seed(&verts) {
        Some(seed) if bulk_load_starts_on_a_line(&verts) => {
            insert_one_by_one(verts, &edges, seed, &mut conflicts)?
        }
        _ => {
            let cdt = Cdt::try_bulk_load_cdt(verts, edges.clone(), |_| conflicts += 1)
                .map_err(|e| FaceMeshError::Triangulation(format!("{e:?}")))?;
            // The bulk loader keeps the vertices in their given order.
            (cdt, (0..n).map(FixedVertexHandle::from_index).collect())
        }
    };
    if conflicts > 0 {
        return Err(FaceMeshError::Triangulation(format!(
            "{conflicts} trim segment(s) cross other trim segments"
        )));
    }
    if cdt.num_vertices() != n {
        return Err(FaceMeshError::Triangulation(
            "distinct trim points coincide in the triangulation plane".into(),
        ));
    }
    for [a, b] in edges {
        if !cdt.exists_constraint(handles[a], handles[b]) {
            return Err(FaceMeshError::Triangulation(
                "a trim point lies on another trim segment".into(),
            ));
        }
    }
    if cdt.num_inner_faces() == 0 {
        return Err(FaceMeshError::EmptyDomain);
    }
    Ok(cdt)
}

/// How many of the points nearest their centroid may lie on one line before the bulk loader
/// is avoided. Spade's bulk loader inserts points nearest-first and, while all inserted
/// points are collinear, locates each new one by collecting and sorting every vertex: a face
/// bounded by a long straight polyline (its centroid on that line) costs O(n²) there —
/// 70 ms for a 4,764-point boundary, 4–7 ms one by one (issue 13's polyedge).
const MAX_COLLINEAR_START: usize = 32;

/// Whether the bulk loader's first [`MAX_COLLINEAR_START`] + 1 points (those nearest the
/// centroid of all, its insertion order) lie on one line.
fn bulk_load_starts_on_a_line(verts: &[Vert]) -> bool {
    if verts.len() <= MAX_COLLINEAR_START + 1 {
        return false;
    }
    let inv = 1.0 / verts.len() as f64;
    let (cx, cy) = verts.iter().fold((0.0, 0.0), |(x, y), v| {
        (x + v.pos.x * inv, y + v.pos.y * inv)
    });
    let d2 = |v: &Vert| (v.pos.x - cx).powi(2) + (v.pos.y - cy).powi(2);
    let mut nearest: Vec<&Vert> = verts.iter().collect();
    nearest.select_nth_unstable_by(MAX_COLLINEAR_START, |a, b| d2(a).total_cmp(&d2(b)));
    nearest.truncate(MAX_COLLINEAR_START + 1);
    let a = nearest[0].pos;
    let Some(b) = nearest.iter().map(|v| v.pos).find(|&p| p != a) else {
        return true;
    };
    nearest.iter().all(|v| cross(a, b, v.pos) == 0.0)
}

/// Twice the signed area of the triangle (a, b, p).
fn cross(a: Point2<f64>, b: Point2<f64>, p: Point2<f64>) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Indices of three points not on one line: the first, the farthest from it, and the
/// farthest from the line through those two. `None` when every point lies on one line.
fn non_collinear_seed(verts: &[Vert]) -> Option<[usize; 3]> {
    let a = verts.first()?.pos;
    let d2 = |p: Point2<f64>| (p.x - a.x).powi(2) + (p.y - a.y).powi(2);
    let (j, _) = verts
        .iter()
        .enumerate()
        .max_by(|x, y| d2(x.1.pos).total_cmp(&d2(y.1.pos)))?;
    let b = verts[j].pos;
    let (k, far) = verts
        .iter()
        .enumerate()
        .map(|(k, v)| (k, cross(a, b, v.pos).abs()))
        .max_by(|x, y| x.1.total_cmp(&y.1))?;
    (far > 0.0).then_some([0, j, k])
}

/// The triangulation built by inserting a non-collinear seed triangle first and then every
/// other point in the given (loop) order, so that no insertion meets the all-on-a-line
/// state; then the constraints. Returns the handle of every input point.
fn insert_one_by_one(
    verts: Vec<Vert>,
    edges: &[[usize; 2]],
    seed: [usize; 3],
    conflicts: &mut usize,
) -> Result<(Cdt, Vec<FixedVertexHandle>), FaceMeshError> {
    let mut cdt = Cdt::new();
    let mut handles = vec![FixedVertexHandle::from_index(0); verts.len()];
    let seeded = seed.iter().copied();
    let rest = (0..verts.len()).filter(|i| !seed.contains(i));
    for i in seeded.chain(rest) {
        handles[i] = cdt
            .insert(verts[i])
            .map_err(|e| FaceMeshError::Triangulation(format!("{e:?}")))?;
    }
    if cdt.num_vertices() != verts.len() {
        // Coincident points share a handle; `build` names the failure.
        return Ok((cdt, handles));
    }
    for &[a, b] in edges {
        if cdt.try_add_constraint(handles[a], handles[b]).is_empty() {
            *conflicts += 1;
        }
    }
    Ok((cdt, handles))
}

/// Even-odd classification of every face (indexed by face index; the outer face is
/// outside): flood fill from the outer face, toggling at each constraint crossed, except
/// constraints used an even number of times by the loops.
pub(crate) fn classify(cdt: &Cdt, even: &HashSet<(u32, u32)>, inside: &mut Vec<bool>) {
    let n = cdt.num_all_faces();
    inside.clear();
    inside.resize(n, false);
    let mut seen = vec![false; n];
    let outer = cdt.outer_face().fix();
    seen[outer.index()] = true;
    let mut stack: Vec<FixedFaceHandle<PossiblyOuterTag>> = vec![outer];
    while let Some(f) = stack.pop() {
        let here = inside[f.index()];
        let Some(start) = cdt.face(f).adjacent_edge() else {
            continue;
        };
        let mut e = start;
        loop {
            let nb = e.rev().face().fix();
            if !seen[nb.index()] {
                seen[nb.index()] = true;
                let toggles = e.is_constraint_edge() && {
                    let [a, b] = e.vertices().map(|v| v.data().id);
                    even.is_empty() || !even.contains(&edge_key(a, b))
                };
                inside[nb.index()] = here ^ toggles;
                stack.push(nb);
            }
            e = e.next();
            if e == start {
                break;
            }
        }
    }
}

/// Inserts a refinement point unless it would land on an existing vertex, on a constraint
/// (which would split a shared boundary segment) or outside the face. `inside` holds the
/// classification of every face; the faces the insertion creates are inside too (they
/// subdivide the inside face hit, and edge flips never cross a constraint, so no face changes
/// region). Returns the new vertex's handle.
pub(crate) fn insert_interior(
    cdt: &mut Cdt,
    vert: Vert,
    hint: Option<FixedVertexHandle>,
    inside: &mut Vec<bool>,
) -> Option<FixedVertexHandle> {
    let loc = match hint {
        Some(h) => cdt.locate_with_hint(vert.pos, h),
        None => cdt.locate(vert.pos),
    };
    let face = match loc {
        PositionInTriangulation::OnFace(f) => f.index(),
        PositionInTriangulation::OnEdge(e) => {
            let e = cdt.directed_edge(e);
            if e.is_constraint_edge() {
                return None;
            }
            e.face().fix().index()
        }
        _ => return None,
    };
    if !inside.get(face).copied().unwrap_or(false) {
        return None;
    }
    let before = cdt.num_vertices();
    let h = match hint {
        Some(h) => cdt.insert_with_hint(vert, h),
        None => cdt.insert(vert),
    }
    .ok()?;
    inside.resize(cdt.num_all_faces(), true);
    (cdt.num_vertices() > before).then_some(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, id: u32) -> Vert {
        Vert {
            pos: Point2::new(x, y),
            id,
        }
    }

    #[test]
    fn square_with_hole_classifies() {
        let verts = vec![
            v(0.0, 0.0, 0),
            v(3.0, 0.0, 1),
            v(3.0, 3.0, 2),
            v(0.0, 3.0, 3),
            v(1.0, 1.0, 4),
            v(1.0, 2.0, 5),
            v(2.0, 2.0, 6),
            v(2.0, 1.0, 7),
        ];
        let edges = vec![
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
        ];
        let cdt = build(verts, edges).unwrap();
        let mut inside = Vec::new();
        classify(&cdt, &HashSet::new(), &mut inside);
        let mut area = 0.0;
        for f in cdt.inner_faces() {
            if inside[f.fix().index()] {
                area += f.area();
                let c = f.center();
                assert!(!(c.x > 1.0 && c.x < 2.0 && c.y > 1.0 && c.y < 2.0));
            }
        }
        assert!((area - 8.0).abs() < 1e-12, "{area}");
    }

    #[test]
    fn crossing_constraints_are_an_error() {
        let verts = vec![
            v(0.0, 0.0, 0),
            v(1.0, 1.0, 1),
            v(1.0, 0.0, 2),
            v(0.0, 1.0, 3),
        ];
        let edges = vec![[0, 1], [1, 2], [2, 3], [3, 0]];
        assert!(matches!(
            build(verts, edges),
            Err(FaceMeshError::Triangulation(_))
        ));
    }

    #[test]
    fn insertion_never_splits_constraints() {
        let verts = vec![v(0.0, 0.0, 0), v(2.0, 0.0, 1), v(1.0, 1.0, 2)];
        let mut cdt = build(verts, vec![[0, 1], [1, 2], [2, 0]]).unwrap();
        let mut inside = Vec::new();
        classify(&cdt, &HashSet::new(), &mut inside);
        let mut ins = |cdt: &mut Cdt, x, y| insert_interior(cdt, v(x, y, 3), None, &mut inside);
        assert!(ins(&mut cdt, 1.0, 0.0).is_none());
        assert!(ins(&mut cdt, 0.0, 0.0).is_none());
        assert!(ins(&mut cdt, 5.0, 5.0).is_none());
        assert!(ins(&mut cdt, 1.0, 0.5).is_some());
        assert!(ins(&mut cdt, 1.0, 0.25).is_some());
        assert_eq!(cdt.num_constraints(), 3);
    }

    /// A square whose left side is an `n`-point straight polyline, as a loop: the shape of
    /// issue 13's polyedge face, whose centroid lies near that side.
    fn square_with_long_side(n: usize) -> (Vec<Vert>, Vec<[usize; 2]>) {
        let mut verts: Vec<Vert> = (0..n)
            .map(|i| v(0.0, 100.0 * i as f64 / (n - 1) as f64, i as u32))
            .collect();
        verts.push(v(100.0, 100.0, n as u32));
        verts.push(v(100.0, 0.0, n as u32 + 1));
        let m = verts.len();
        let edges = (0..m).map(|i| [i, (i + 1) % m]).collect();
        (verts, edges)
    }

    fn inside_area(cdt: &Cdt) -> f64 {
        let mut inside = Vec::new();
        classify(cdt, &HashSet::new(), &mut inside);
        cdt.inner_faces()
            .filter(|f| inside[f.fix().index()])
            .map(|f| f.area())
            .sum()
    }

    #[test]
    fn a_long_straight_side_is_triangulated_one_by_one() {
        let (verts, edges) = square_with_long_side(2_000);
        assert!(bulk_load_starts_on_a_line(&verts));
        let seed = non_collinear_seed(&verts).unwrap();
        let mut conflicts = 0;
        let (one_by_one, handles) =
            insert_one_by_one(verts.clone(), &edges, seed, &mut conflicts).unwrap();
        assert_eq!(conflicts, 0);
        // The same triangulation as the bulk loader's: same triangles, every loop segment a
        // constraint, the same area inside.
        let bulk = Cdt::bulk_load_cdt(verts.clone(), edges.clone()).unwrap();
        assert_eq!(one_by_one.num_inner_faces(), bulk.num_inner_faces());
        assert_eq!(one_by_one.num_constraints(), edges.len());
        for &[a, b] in &edges {
            assert!(one_by_one.exists_constraint(handles[a], handles[b]));
        }
        assert!((inside_area(&one_by_one) - 10_000.0).abs() < 1e-6);
        // And `build` takes this path and gives the same.
        let built = build(verts, edges).unwrap();
        assert!((inside_area(&built) - 10_000.0).abs() < 1e-6);
    }

    #[test]
    fn ordinary_loops_keep_the_bulk_loader() {
        // Negative control: a 200-gon (no three nearest points on a line) and a short side.
        let ring: Vec<Vert> = (0..200)
            .map(|i| {
                let t = i as f64 * std::f64::consts::TAU / 200.0;
                v(t.cos(), t.sin(), i)
            })
            .collect();
        assert!(!bulk_load_starts_on_a_line(&ring));
        let (short, _) = square_with_long_side(MAX_COLLINEAR_START - 2);
        assert!(!bulk_load_starts_on_a_line(&short));
        // All on one line: no seed triangle, the bulk loader names the empty domain.
        let line: Vec<Vert> = (0..100).map(|i| v(f64::from(i), 0.0, i)).collect();
        assert!(non_collinear_seed(&line).is_none());
        let edges = (0..99).map(|i| [i, i + 1]).collect();
        assert!(matches!(
            build(line, edges),
            Err(FaceMeshError::EmptyDomain)
        ));
    }

    #[test]
    fn one_by_one_still_rejects_coincident_and_crossing_points() {
        let (mut verts, edges) = square_with_long_side(500);
        verts[250].pos = verts[251].pos;
        assert!(bulk_load_starts_on_a_line(&verts));
        assert!(matches!(
            build(verts, edges),
            Err(FaceMeshError::Triangulation(m)) if m.contains("coincide")
        ));
        // A bow-tie: the far corners swapped, so two sides cross.
        let (mut verts, edges) = square_with_long_side(500);
        let n = verts.len();
        verts.swap(n - 1, n - 2);
        for (i, v) in verts.iter_mut().enumerate() {
            v.id = i as u32;
        }
        assert!(matches!(
            build(verts, edges),
            Err(FaceMeshError::Triangulation(m)) if m.contains("cross")
        ));
    }
}
