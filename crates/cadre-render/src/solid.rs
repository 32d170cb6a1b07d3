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
/// enclosed signed volume is negative). `None` for open or non-manifold meshes, meshes
/// without triangles, and meshes whose shells (their connected parts) wind different ways:
/// one flag per mesh cannot say which side of each is outside, and the side culled as seen
/// from inside would be the near half of the shell wound against the rest (PRO7071's
/// sphere of reversed faces, drawn as its far half).
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
    // Each triangle's first corner and its share of the enclosed volume, summed per shell
    // once the shells are known.
    let mut volumes: Vec<(u32, f64)> = Vec::new();
    let mut shells = Shells::new(ids.len());
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
            volumes.push((a, p(0).dot(p(1).cross(p(2)))));
            shells.join(a, b);
            shells.join(b, c);
        }
    }
    let closed = triangles > 0 && sides.values().all(|&(uses, net)| uses == 2 && net == 0);
    if !closed {
        return None;
    }
    let mut per_shell: FxHashMap<u32, f64> = FxHashMap::default();
    for (corner, volume) in volumes {
        *per_shell.entry(shells.root(corner)).or_default() += volume;
    }
    let inside_out = per_shell.values().filter(|&&v| v < 0.0).count();
    match inside_out {
        0 => Some(false),
        n if n == per_shell.len() => Some(true),
        _ => None,
    }
}

/// Disjoint sets of welded vertices (union by size, paths halved): the shells of a mesh.
struct Shells {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl Shells {
    fn new(count: usize) -> Shells {
        Shells {
            parent: (0..count as u32).collect(),
            size: vec![1; count],
        }
    }

    fn root(&mut self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            let grand = self.parent[self.parent[v as usize] as usize];
            self.parent[v as usize] = grand;
            v = grand;
        }
        v
    }

    fn join(&mut self, a: u32, b: u32) {
        let (mut a, mut b) = (self.root(a), self.root(b));
        if a == b {
            return;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
    }
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

    /// Two closed shells in one mesh: wound the same way, a solid of that orientation;
    /// one wound against the other, no orientation holds for both (not a solid).
    #[test]
    fn shells_wound_against_each_other_are_not_one_solid() {
        let one = tetrahedron();
        let mut two = tetrahedron();
        let offset = one.positions.len() as u32;
        for p in &one.positions {
            two.positions.push([p[0] + 10.0, p[1], p[2]]);
        }
        let first: Vec<u32> = two.primitives[0].indices.clone();
        two.primitives[0]
            .indices
            .extend(first.iter().map(|i| i + offset));
        assert_eq!(closed_orientation(&two), Some(false));
        // The second shell's triangles turned over.
        let n = first.len();
        for tri in two.primitives[0].indices[n..].chunks_exact_mut(3) {
            tri.swap(1, 2);
        }
        assert_eq!(closed_orientation(&two), None);
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
