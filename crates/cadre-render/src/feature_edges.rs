//! B-Rep edges recovered from a tessellated mesh: the mesher gives every face its own
//! vertices, so a triangle side used once within its face lies on the face's boundary, that
//! is on a B-Rep edge. Both faces of an edge share the edge's 3D samples, so the two copies
//! coincide exactly and are kept once.

use rustc_hash::FxHashMap;

use crate::position_key::{SideKey, point_key, side_key};
use cadre_mesh::scene::SceneMesh;

/// A segment's two ends, mesh-local.
type Segment = [[f32; 3]; 2];

/// Segments (pairs of mesh-local points) of the face boundaries of `mesh`.
pub fn feature_edges(mesh: &SceneMesh) -> Vec<Segment> {
    // Sides by position within each face: a seam (the face's own two copies of one line)
    // counts twice and is not drawn, as CAD viewers do not draw seams.
    let mut uses: FxHashMap<(u32, SideKey), (u32, Segment)> = FxHashMap::default();
    for prim in &mesh.primitives {
        for (t, tri) in prim.indices.chunks_exact(3).enumerate() {
            let face = prim.face_ids.get(t).copied().unwrap_or(0);
            for k in 0..3 {
                let (Some(&a), Some(&b)) = (
                    mesh.positions.get(tri[k] as usize),
                    mesh.positions.get(tri[(k + 1) % 3] as usize),
                ) else {
                    continue;
                };
                if point_key(a) == point_key(b) {
                    continue;
                }
                uses.entry((face, side_key(a, b))).or_insert((0, [a, b])).0 += 1;
            }
        }
    }
    let mut sides: Vec<(SideKey, Segment)> = uses
        .into_iter()
        .filter(|(_, (n, _))| *n == 1)
        .map(|((_, k), (_, seg))| (k, seg))
        .collect();
    // Both faces of an edge give it: keep one, in a stable order.
    sides.sort_unstable_by_key(|s| s.0);
    sides.dedup_by_key(|s| s.0);
    sides.into_iter().map(|(_, seg)| seg).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_mesh::scene::Primitive;

    #[test]
    fn two_faces_of_a_folded_square_give_their_outline_and_shared_edge_once() {
        // Face 1: triangles (0,1,2), (0,2,3); face 2 duplicates the shared side's points.
        let p = |x: f32, y: f32, z: f32| [x, y, z];
        let mesh = SceneMesh {
            name: String::new(),
            positions: vec![
                p(0.0, 0.0, 0.0),
                p(1.0, 0.0, 0.0),
                p(1.0, 1.0, 0.0),
                p(0.0, 1.0, 0.0),
                // face 2 (the fold up along x = 1)
                p(1.0, 0.0, 0.0),
                p(1.0, 0.0, 1.0),
                p(1.0, 1.0, 1.0),
                p(1.0, 1.0, 0.0),
            ],
            normals: Vec::new(),
            surface_uv: Vec::new(),
            lines: Vec::new(),
            primitives: vec![Primitive {
                indices: vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7],
                material: None,
                face_ids: vec![1, 1, 2, 2],
            }],
            ..SceneMesh::default()
        };
        let edges = feature_edges(&mesh);
        // 4 + 4 sides, the shared one once, the diagonals not at all.
        assert_eq!(edges.len(), 7, "{edges:?}");
        assert!(
            !edges
                .iter()
                .any(|e| e == &[p(0.0, 0.0, 0.0), p(1.0, 1.0, 0.0)])
        );
    }

    #[test]
    fn a_seam_inside_one_face_is_not_an_edge() {
        // A strip closed on itself: the face has two copies of the line x = 0 (a seam).
        let p = |x: f32, y: f32| [x, y, 0.0];
        let mesh = SceneMesh {
            name: String::new(),
            positions: vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
                p(0.0, 0.0),
                p(0.0, 1.0),
            ],
            normals: Vec::new(),
            surface_uv: Vec::new(),
            lines: Vec::new(),
            primitives: vec![Primitive {
                // (0,1,2),(0,2,3) one side; (1,4,5),(1,5,2) the other, back to the seam copies.
                indices: vec![0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2],
                material: None,
                face_ids: vec![7, 7, 7, 7],
            }],
            ..SceneMesh::default()
        };
        let edges = feature_edges(&mesh);
        assert!(
            !edges.iter().any(|e| e[0][0] == 0.0 && e[1][0] == 0.0),
            "seam drawn: {edges:?}"
        );
    }
}
