//! Whether a mesh bounds a solid, for section caps: a view ray that meets the inside of a
//! closed surface through a cut sees the solid's material, so the renderer draws a cap there;
//! an open shell seen from behind is just its back side.

use rustc_hash::FxHashMap;

use crate::position_key::point_key;
use cadre_mesh::scene::SceneMesh;

/// `Some(inside_out)` when every triangle side of `mesh` (all primitives together, positions
/// welded by their bits: the mesher gives each face its own vertices) is shared by exactly
/// two triangles that run along it in opposite directions — a closed, consistently oriented
/// surface — with `inside_out` when the triangles wind clockwise seen from outside (the
/// enclosed signed volume is negative). `None` for open or non-manifold meshes and meshes
/// without triangles.
pub(crate) fn closed_orientation(mesh: &SceneMesh) -> Option<bool> {
    // One id per distinct position.
    let mut ids: FxHashMap<[u32; 3], u32> =
        FxHashMap::with_capacity_and_hasher(mesh.positions.len(), Default::default());
    let welded: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let next = ids.len() as u32;
            *ids.entry(point_key(*p)).or_insert(next)
        })
        .collect();
    // Per undirected side: (uses, uses from the lower id to the higher minus the reverse).
    let mut sides: FxHashMap<(u32, u32), (u32, i32)> = FxHashMap::default();
    let mut volume = 0.0f64;
    let mut triangles = 0usize;
    for prim in &mesh.primitives {
        for tri in prim.indices.chunks_exact(3) {
            let corner = |k: usize| welded.get(tri[k] as usize).copied();
            let (Some(a), Some(b), Some(c)) = (corner(0), corner(1), corner(2)) else {
                return None;
            };
            // Slivers with two corners at one point (poles, apexes) bound nothing; their
            // neighbours share the remaining side with each other.
            if a == b || b == c || c == a {
                continue;
            }
            triangles += 1;
            for (u, v) in [(a, b), (b, c), (c, a)] {
                let side = sides.entry((u.min(v), u.max(v))).or_default();
                side.0 += 1;
                side.1 += if u < v { 1 } else { -1 };
            }
            let p = |k: usize| glam::DVec3::from(mesh.positions[tri[k] as usize].map(f64::from));
            volume += p(0).dot(p(1).cross(p(2)));
        }
    }
    let closed = triangles > 0 && sides.values().all(|&(uses, net)| uses == 2 && net == 0);
    closed.then_some(volume < 0.0)
}

#[cfg(test)]
mod tests {
    use cadre_mesh::scene::Primitive;

    use super::*;

    /// A unit tetrahedron, each face with its own vertices (as the mesher makes them),
    /// counter-clockwise seen from outside.
    fn tetrahedron() -> SceneMesh {
        let corners = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for face in faces {
            for c in face {
                indices.push(positions.len() as u32);
                positions.push(corners[c]);
            }
        }
        SceneMesh {
            positions,
            primitives: vec![Primitive {
                indices,
                ..Primitive::default()
            }],
            ..SceneMesh::default()
        }
    }

    #[test]
    fn a_closed_mesh_is_a_solid_with_its_orientation() {
        let mut mesh = tetrahedron();
        assert_eq!(closed_orientation(&mesh), Some(false));
        // Reversed winding: inside out.
        for tri in mesh.primitives[0].indices.chunks_exact_mut(3) {
            tri.swap(1, 2);
        }
        assert_eq!(closed_orientation(&mesh), Some(true));
    }

    #[test]
    fn open_or_misoriented_meshes_are_not_solids() {
        let mut open = tetrahedron();
        open.primitives[0].indices.truncate(9);
        assert_eq!(closed_orientation(&open), None);
        // One face flipped: every side still used twice, but not in opposite directions.
        let mut flipped = tetrahedron();
        flipped.primitives[0].indices.swap(1, 2);
        assert_eq!(closed_orientation(&flipped), None);
        assert_eq!(closed_orientation(&SceneMesh::default()), None);
    }
}
