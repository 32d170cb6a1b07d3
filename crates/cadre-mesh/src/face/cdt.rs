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
    let cdt = Cdt::try_bulk_load_cdt(verts, edges.clone(), |_| conflicts += 1)
        .map_err(|e| FaceMeshError::Triangulation(format!("{e:?}")))?;
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
    let h = FixedVertexHandle::from_index;
    for [a, b] in edges {
        if !cdt.exists_constraint(h(a), h(b)) {
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
}
