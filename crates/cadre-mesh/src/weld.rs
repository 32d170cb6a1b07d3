//! Welded meshes of bodies (one vertex per weld key) and their measures: area, enclosed
//! volume, and the edge census that says whether a mesh is closed and 2-manifold.

use std::collections::HashMap;

use cadre_brep::{FaceId, Model, ShellId};
use cadre_geom::Vec3;

use crate::ModelMesh;

/// A triangle mesh whose faces share their boundary vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WeldedMesh {
    /// Vertex positions (model units).
    pub positions: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from outside the body.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the STEP id of its B-Rep face.
    pub triangle_faces: Vec<u64>,
}

/// How the edges of a mesh are shared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeCensus {
    /// Edges used by one triangle only (holes, cracks).
    pub boundary: usize,
    /// Edges used by more than two triangles.
    pub nonmanifold: usize,
    /// Edges used by two triangles in the same direction (inconsistent orientation).
    pub misoriented: usize,
}

impl WeldedMesh {
    /// Appends faces, each used forward (`true`) or reversed, welding equal keys.
    pub fn add_faces(&mut self, model: &Model, mesh: &ModelMesh, faces: &[(FaceId, bool)]) {
        let mut index: HashMap<u64, u32> = HashMap::new();
        for &(face, forward) in faces {
            let Some(Some(fm)) = mesh.faces.get(face.index()) else {
                continue;
            };
            let step_id = model.faces[face.index()].step_id;
            let map: Vec<u32> = fm
                .points
                .iter()
                .map(|p| {
                    let mut new = || {
                        self.positions.push(p.xyz);
                        (self.positions.len() - 1) as u32
                    };
                    match p.key {
                        Some(k) => *index.entry(k).or_insert_with(new),
                        None => new(),
                    }
                })
                .collect();
            for t in &fm.triangles {
                let [a, b, c] = t.map(|i| map[i as usize]);
                if a == b || b == c || a == c {
                    continue;
                }
                self.triangles
                    .push(if forward { [a, b, c] } else { [a, c, b] });
                self.triangle_faces.push(step_id);
            }
        }
    }

    /// A mesh given as positions and triangles, with equal positions welded into one vertex:
    /// tessellated STEP faces repeat their shared vertices, one copy per face, taken from the
    /// same coordinate list (so the copies are bitwise equal).
    pub fn from_positions(positions: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        let mut w = Self::default();
        let mut index: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
        let map: Vec<u32> = positions
            .iter()
            .map(|p| {
                // +0.0 and -0.0 are the same point.
                let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
                *index.entry(key).or_insert_with(|| {
                    w.positions.push(*p);
                    (w.positions.len() - 1) as u32
                })
            })
            .collect();
        for t in triangles {
            let Some([a, b, c]) = t
                .iter()
                .map(|&i| map.get(i as usize).copied())
                .collect::<Option<Vec<u32>>>()
                .and_then(|v| <[u32; 3]>::try_from(v).ok())
            else {
                continue;
            };
            if a != b && b != c && a != c {
                w.triangles.push([a, b, c]);
            }
        }
        w
    }

    /// The mesh of a shell, faces oriented as the shell uses them.
    pub fn shell(model: &Model, mesh: &ModelMesh, shell: ShellId) -> Self {
        let mut w = Self::default();
        w.add_faces(model, mesh, &model.shells[shell.index()].faces);
        w
    }

    /// Total triangle area.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// Signed enclosed volume (divergence theorem): positive for a closed mesh oriented
    /// outwards.
    pub fn signed_volume(&self) -> f64 {
        // About the centroid of the vertices, to keep the sum well conditioned far from the
        // origin.
        let n = self.positions.len().max(1) as f64;
        let o = self.positions.iter().copied().sum::<Vec3>() / n;
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize] - o);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Counts boundary, non-manifold and misoriented edges.
    pub fn census(&self) -> EdgeCensus {
        // Per undirected edge: uses in each direction.
        let mut edges: HashMap<(u32, u32), [u32; 2]> =
            HashMap::with_capacity(self.triangles.len() * 2);
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let (key, dir) = if a < b { ((a, b), 0) } else { ((b, a), 1) };
                edges.entry(key).or_default()[dir] += 1;
            }
        }
        let mut c = EdgeCensus::default();
        for [f, r] in edges.into_values() {
            match f + r {
                1 => c.boundary += 1,
                2 if f != 1 => c.misoriented += 1,
                2 => {}
                _ => c.nonmanifold += 1,
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_positions_weld_across_faces() {
        // A tetrahedron written as four faces with their own copies of the corners.
        let c = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for f in faces {
            let base = positions.len() as u32;
            positions.extend(f.map(|i| c[i]));
            triangles.push([base, base + 1, base + 2]);
        }
        let w = WeldedMesh::from_positions(&positions, &triangles);
        assert_eq!(w.positions.len(), 4);
        assert_eq!(w.census(), EdgeCensus::default());
        assert!((w.signed_volume() - 1.0 / 6.0).abs() < 1e-12);
        // Unwelded, every edge is a boundary.
        let open = WeldedMesh {
            positions,
            triangles,
            triangle_faces: Vec::new(),
        };
        assert_eq!(open.census().boundary, 12);
    }
}
