//! The two faces along each edge segment of a closed solid's mesh, for the edges pass to drop
//! the segments hidden behind their own solid: where both faces along an edge turn away from
//! the eye, the edge lies on the solid's far side, so the solid itself hides it. Drawn, such a
//! segment would only be rasterized and then rejected by the depth test, fragment block by
//! block: on a CPU rasterizer (llvmpipe) most of the edges pass is that per-triangle work,
//! and about half the edges of a closed solid lie on its far side.

use crate::position_key::{SideKey, side_key};
use cadre_mesh::scene::SceneMesh;
use rustc_hash::FxHashMap;

/// The triangles met along one segment: their outward unit normals (the first two), and how
/// many there are.
#[derive(Clone, Copy, Default)]
struct Sides {
    normals: [[f32; 3]; 2],
    count: u32,
}

/// The faces along the segments asked for, of one closed mesh.
pub(crate) struct EdgeFaces {
    /// By exact bits (Fx hashing: std's SipHash made this 5.4 ms of a 12 k-triangle mesh's
    /// upload).
    sides: FxHashMap<SideKey, Sides>,
}

impl EdgeFaces {
    /// Finds the triangles of `mesh` along each of the segments `wanted`; `inside_out` when
    /// the mesh winds clockwise seen from outside (`solid::closed_orientation`), so that its
    /// normals by the right-hand rule point in.
    pub fn new(
        mesh: &SceneMesh,
        inside_out: bool,
        wanted: impl Iterator<Item = ([f32; 3], [f32; 3])>,
    ) -> EdgeFaces {
        let mut sides: FxHashMap<SideKey, Sides> = wanted
            .map(|(a, b)| (side_key(a, b), Sides::default()))
            .collect();
        let sign = if inside_out { -1.0 } else { 1.0 };
        for prim in &mesh.primitives {
            for tri in prim.indices.chunks_exact(3) {
                let corner = |k: usize| mesh.positions.get(tri[k] as usize).copied();
                let (Some(p0), Some(p1), Some(p2)) = (corner(0), corner(1), corner(2)) else {
                    continue;
                };
                let normal = unit(cross(sub(p1, p0), sub(p2, p0))).map(|c| sign * c);
                for (a, b) in [(p0, p1), (p1, p2), (p2, p0)] {
                    if let Some(s) = sides.get_mut(&side_key(a, b)) {
                        if let Some(slot) = s.normals.get_mut(s.count as usize) {
                            *slot = normal;
                        }
                        s.count += 1;
                    }
                }
            }
        }
        EdgeFaces { sides }
    }

    /// The packed normals ([`crate::layout::Segment::faces`]) of the two triangles along the
    /// segment `a`–`b`; 0 unless exactly two triangles meet there.
    pub fn packed(&self, a: [f32; 3], b: [f32; 3]) -> [u32; 2] {
        match self.sides.get(&side_key(a, b)) {
            Some(s) if s.count == 2 => s.normals.map(pack_snorm),
            _ => [0, 0],
        }
    }
}

/// `n` packed as WGSL's `pack4x8snorm(vec4(n, 0))`: each component rounded to 1/127.
pub(crate) fn pack_snorm(n: [f32; 3]) -> u32 {
    n.iter().enumerate().fold(0, |bits, (i, &c)| {
        let byte = (c.clamp(-1.0, 1.0) * 127.0).round() as i8 as u8;
        bits | (u32::from(byte) << (8 * i))
    })
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v` scaled to unit length; 0 for a degenerate triangle (never culled: its face counts as
/// turned towards the eye).
fn unit(v: [f32; 3]) -> [f32; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        v.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_mesh::scene::Primitive;

    /// A closed tetrahedron, counter-clockwise seen from outside.
    fn tetrahedron() -> SceneMesh {
        SceneMesh {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            primitives: vec![Primitive {
                indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
                ..Primitive::default()
            }],
            ..SceneMesh::default()
        }
    }

    fn unpack(bits: u32) -> [f32; 3] {
        [0, 1, 2].map(|i| f32::from((bits >> (8 * i)) as u8 as i8) / 127.0)
    }

    #[test]
    fn an_edge_gets_the_outward_normals_of_its_two_faces() {
        let mesh = tetrahedron();
        let edge = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let faces = EdgeFaces::new(&mesh, false, [edge].into_iter());
        let [n1, n2] = faces.packed(edge.0, edge.1).map(unpack);
        // The faces z = 0 (outward −z) and y = 0 (outward −y), in either order.
        let mut got = [n1, n2];
        got.sort_by(|a, b| a[1].total_cmp(&b[1]));
        assert_eq!(got, [[0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        // Reversed, the same edge; inside out, the normals turn.
        assert_eq!(faces.packed(edge.1, edge.0), faces.packed(edge.0, edge.1));
        let flipped = EdgeFaces::new(&mesh, true, [edge].into_iter());
        let [m1, _] = flipped.packed(edge.0, edge.1).map(unpack);
        assert!(m1 == n1.map(|c| -c) || m1 == n2.map(|c| -c), "{m1:?}");
    }

    #[test]
    fn a_segment_without_two_faces_gets_none() {
        let mut mesh = tetrahedron();
        // Not a side of any triangle.
        let lone = ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let faces = EdgeFaces::new(&mesh, false, [lone].into_iter());
        assert_eq!(faces.packed(lone.0, lone.1), [0, 0]);
        // An open mesh's border: one triangle along it.
        mesh.primitives[0].indices.truncate(3);
        let border = ([0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let faces = EdgeFaces::new(&mesh, false, [border].into_iter());
        assert_eq!(faces.packed(border.0, border.1), [0, 0]);
    }

    #[test]
    fn packing_matches_wgsl_pack4x8snorm() {
        assert_eq!(pack_snorm([1.0, -1.0, 0.0]), 0x0000_817f);
        assert_eq!(pack_snorm([0.5, 0.0, 2.0]), 0x007f_0040);
    }
}
