//! Closing cracks thinner than the deflection in the meshes of closed shells.
//!
//! Faces mesh their trims independently, and where a trim had to be repaired (crossing
//! chords split at points the neighbour lacks, a tiny edge merged away on a domain corner)
//! the faces no longer share every boundary point: the shell is left with small holes, each
//! a thin loop of boundary edges (bug32596_abc_0_13.step: lobes between two tangentially
//! touching edges; trj7_b1-ec-214.stp: a 0.07 × 0.01 mm gap where an edge runs past its
//! face's surface). A closed shell has no boundary, so any loop of boundary edges is such a
//! hole; one no wider than the deflection is filled with a strip of triangles, given to the
//! face that borders it most, and reported. Wider holes are left open (and reported as open
//! edges, as before).

use std::collections::{HashMap, HashSet};

use cadre_brep::{FaceId, Model};
use cadre_geom::{Accuracy, Vec3};

use crate::face::{FaceMesh, MeshPoint};
use crate::model::{FaceRepair, ModelMesh};
use crate::strip::{height, zip_strip};

/// Largest hole filled, in boundary edges: a crack between two faces, not a missing face.
const MAX_CRACK_EDGES: usize = 64;

/// Weld keys given to unkeyed points (split points) a crack joins to another face: the top
/// two bits set, above the vertex, edge-sample and face keys of the mesher.
const CRACK_KEY: u64 = 3 << 62;

/// A point of one face's mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct At {
    face: u32,
    point: u32,
}

/// A vertex of a shell's welded mesh: a weld key, or an unkeyed point of one face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Vertex {
    Key(u64),
    Lone(At),
}

/// Fills the cracks of every closed shell (solids' shells, shells the file declares closed)
/// of `mesh`; returns a note per face that received triangles.
pub(crate) fn close_cracks(model: &Model, mesh: &mut ModelMesh) -> Vec<FaceRepair> {
    let mut closed: Vec<usize> = model
        .solids
        .iter()
        .flat_map(|s| s.shells().map(|id| id.index()))
        .collect();
    closed.extend((0..model.shells.len()).filter(|&i| model.shells[i].closed));
    closed.sort_unstable();
    closed.dedup();
    let deflection = mesh.params.deflection;
    let mut notes = Vec::new();
    for shell in closed {
        let faces = &model.shells[shell].faces;
        let (cracks, edges) = find_cracks(mesh, faces);
        for crack in cracks {
            if let Some(note) = fill(model, mesh, faces, &crack, &edges, deflection) {
                notes.push(note);
            }
        }
    }
    notes
}

/// A loop of boundary edges, in the direction the fill must use them: each side `i → i+1`
/// is an edge the shell's triangles use once, from `i + 1` to `i`. With each vertex, a face
/// point it stands for, and per side the face whose triangle uses it.
struct Crack {
    vertices: Vec<Vertex>,
    points: Vec<At>,
    side_faces: Vec<u32>,
}

/// The vertex point `at` of the face mesh `fm` stands for.
fn vertex_of(fm: &FaceMesh, at: At) -> Vertex {
    match fm.points[at.point as usize].key {
        Some(k) => Vertex::Key(k),
        None => Vertex::Lone(at),
    }
}

/// Every edge of a shell's welded mesh, undirected, by dense vertex id.
struct ShellEdges {
    /// Dense id of each vertex met.
    ids: HashMap<Vertex, u32>,
    /// `(min id) << 32 | max id`, sorted.
    pairs: Vec<u64>,
}

impl ShellEdges {
    /// Whether the shell has an edge between `a` and `b`.
    fn has(&self, a: Vertex, b: Vertex) -> bool {
        match (self.ids.get(&a), self.ids.get(&b)) {
            (Some(&i), Some(&j)) => self.pairs.binary_search(&pair(i, j)).is_ok(),
            _ => false,
        }
    }
}

/// The undirected key of the edge between dense ids `i` and `j`.
fn pair(i: u32, j: u32) -> u64 {
    (u64::from(i.min(j)) << 32) | u64::from(i.max(j))
}

/// The boundary loops of the shell made of `faces` (each used forward or reversed), each
/// vertex once per loop, and every edge of the shell.
///
/// Vertices get dense ids once per face point and the edges are sorted, not hashed: on
/// trj7_b1-ec-214.stp (588,000 triangles) hashing every directed edge by its two vertices
/// took 3.2 s, more than meshing the file.
fn find_cracks(mesh: &ModelMesh, faces: &[(FaceId, bool)]) -> (Vec<Crack>, ShellEdges) {
    let mut ids: HashMap<Vertex, u32> = HashMap::new();
    let mut vertex: Vec<Vertex> = Vec::new();
    // Directed edges as the shell's triangles use them: (undirected key, from, to, face,
    // the point `to` stands for in that face).
    let mut directed: Vec<(u64, u32, u32, u32, u32)> = Vec::new();
    for &(face, forward) in faces {
        let Some(Some(fm)) = mesh.faces.get(face.index()) else {
            continue;
        };
        let f = face.0;
        let point_ids: Vec<u32> = (0..fm.points.len() as u32)
            .map(|i| {
                let v = vertex_of(fm, At { face: f, point: i });
                *ids.entry(v).or_insert_with(|| {
                    vertex.push(v);
                    (vertex.len() - 1) as u32
                })
            })
            .collect();
        directed.reserve(3 * fm.triangles.len());
        for t in &fm.triangles {
            let t = if forward { *t } else { [t[0], t[2], t[1]] };
            let v = t.map(|i| point_ids[i as usize]);
            if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                directed.push((pair(a, b), a, b, f, t[(k + 1) % 3]));
            }
        }
    }
    directed.sort_unstable_by_key(|d| d.0);
    // Boundary edges a → b (the only use of their pair); the fill runs them b → a.
    let mut from: HashMap<Vertex, Vec<(Vertex, u32, At)>> = HashMap::new();
    let mut pairs = Vec::with_capacity(directed.len() / 2);
    for group in directed.chunk_by(|x, y| x.0 == y.0) {
        pairs.push(group[0].0);
        if let [(_, a, b, f, pb)] = *group {
            let at = At { face: f, point: pb };
            from.entry(vertex[b as usize])
                .or_default()
                .push((vertex[a as usize], f, at));
        }
    }
    let edges = ShellEdges { ids, pairs };
    for outs in from.values_mut() {
        outs.sort_unstable_by_key(|&(to, face, _)| (face, to));
    }
    // Walk the boundary edges into cycles. At a vertex with several ways on (two holes
    // touching at a point) the way along the same face as the way in is taken first; a
    // vertex met again closes the cycle since then, which is cut off as its own crack.
    let mut used: HashSet<(Vertex, Vertex)> = HashSet::new();
    let mut cracks = Vec::new();
    let mut starts: Vec<Vertex> = from.keys().copied().collect();
    starts.sort_unstable();
    for start in starts {
        let mut path: Vec<(Vertex, u32, At)> = Vec::new();
        let mut on_path: HashMap<Vertex, usize> = HashMap::new();
        let mut at = start;
        let mut face_in = None;
        while let Some(outs) = from.get(&at) {
            let free = |&&(to, _, _): &&(Vertex, u32, At)| !used.contains(&(at, to));
            let Some(&(to, face, point)) = outs
                .iter()
                .filter(free)
                .find(|&&(_, f, _)| Some(f) == face_in)
                .or_else(|| outs.iter().find(free))
            else {
                break;
            };
            used.insert((at, to));
            on_path.insert(at, path.len());
            path.push((at, face, point));
            face_in = Some(face);
            if let Some(&first) = on_path.get(&to) {
                let cycle: Vec<(Vertex, u32, At)> = path.drain(first..).collect();
                for (v, _, _) in &cycle {
                    on_path.remove(v);
                }
                if (3..=MAX_CRACK_EDGES).contains(&cycle.len()) {
                    cracks.push(Crack {
                        vertices: cycle.iter().map(|c| c.0).collect(),
                        side_faces: cycle.iter().map(|c| c.1).collect(),
                        points: cycle.iter().map(|c| c.2).collect(),
                    });
                }
                if path.is_empty() {
                    break;
                }
            }
            at = to;
        }
    }
    (cracks, edges)
}

/// Whether triangle `t` (indices into the crack's loop) is no higher than `deflection` and
/// has no diagonal that is already an edge of the shell (which would make it non-manifold).
fn fits(t: &[usize; 3], crack: &Crack, xyz: &[Vec3], edges: &ShellEdges, deflection: f64) -> bool {
    let n = crack.vertices.len();
    for k in 0..3 {
        let (i, j) = (t[k], t[(k + 1) % 3]);
        if (i + 1) % n != j && (j + 1) % n != i {
            let (a, b) = (crack.vertices[i], crack.vertices[j]);
            if edges.has(a, b) {
                return false;
            }
        }
    }
    let h = height(xyz[t[0]], xyz[t[1]], xyz[t[2]]);
    !h.is_nan() && h <= deflection
}

/// Fills `crack` with a strip when every triangle of it is no higher than `deflection` and
/// none of its diagonals is an edge of the shell already (`edges`, undirected); the
/// triangles go to the face bordering the most of its sides.
fn fill(
    model: &Model,
    mesh: &mut ModelMesh,
    faces: &[(FaceId, bool)],
    crack: &Crack,
    edges: &ShellEdges,
    deflection: f64,
) -> Option<FaceRepair> {
    let point = |mesh: &ModelMesh, at: At| -> Option<MeshPoint> {
        let fm = mesh.faces.get(at.face as usize)?.as_ref()?;
        fm.points.get(at.point as usize).copied()
    };
    let sources: Vec<MeshPoint> = crack
        .points
        .iter()
        .map(|&a| point(mesh, a))
        .collect::<Option<_>>()?;
    let xyz: Vec<Vec3> = sources.iter().map(|p| p.xyz).collect();
    // The strip between the loop's two farthest points, else a fan from one of its
    // vertices: the first whose triangles are all thin and add no edge the shell has.
    let n = crack.vertices.len();
    let fan = |k: usize| -> Vec<[usize; 3]> {
        (1..n - 1)
            .map(|i| [k, (k + i) % n, (k + i + 1) % n])
            .collect()
    };
    let tris = std::iter::once(zip_strip(&xyz))
        .chain((0..n).map(fan))
        .find(|tris| tris.iter().all(|t| fits(t, crack, &xyz, edges, deflection)))?;
    // The face bordering most of the crack takes the triangles.
    let mut tally: HashMap<u32, usize> = HashMap::new();
    for &f in &crack.side_faces {
        *tally.entry(f).or_default() += 1;
    }
    let (&owner, _) = tally
        .iter()
        .max_by_key(|&(f, n)| (*n, std::cmp::Reverse(*f)))?;
    let forward = faces.iter().find(|(f, _)| f.0 == owner)?.1;
    let owner_face = &model.faces[owner as usize];
    let surface = &model.surfaces[owner_face.surface.index()];
    // Unkeyed points joined to another face get a key so both copies weld.
    let mut keys = Vec::with_capacity(crack.points.len());
    for (&v, &at) in crack.vertices.iter().zip(&crack.points) {
        let key = match v {
            Vertex::Key(k) => k,
            Vertex::Lone(_) => {
                let k = CRACK_KEY | (u64::from(at.face) << 30) | u64::from(at.point);
                if let Some(Some(fm)) = mesh.faces.get_mut(at.face as usize) {
                    fm.points[at.point as usize].key = Some(k);
                }
                k
            }
        };
        keys.push(key);
    }
    let fm = mesh.faces.get_mut(owner as usize)?.as_mut()?;
    let mut index_of: HashMap<u64, u32> = fm
        .points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.key.map(|k| (k, i as u32)))
        .collect();
    let mut ids = Vec::with_capacity(keys.len());
    for (&key, src) in keys.iter().zip(&sources) {
        let id = match index_of.get(&key) {
            Some(&i) => i,
            None => {
                // A point of another face: its (u, v) on this face's surface, from the
                // nearest point of this face.
                let hint = fm
                    .points
                    .iter()
                    .min_by(|a, b| {
                        (a.xyz - src.xyz)
                            .length_squared()
                            .total_cmp(&(b.xyz - src.xyz).length_squared())
                    })
                    .map(|p| (p.uv.x, p.uv.y));
                let uv = surface
                    .project(src.xyz, hint, Accuracy::default())
                    .map_or(src.uv, |(u, v)| cadre_geom::Vec2::new(u, v));
                fm.points.push(MeshPoint {
                    key: Some(key),
                    ..*src
                });
                fm.points.last_mut().expect("pushed").uv = uv;
                let i = (fm.points.len() - 1) as u32;
                index_of.insert(key, i);
                i
            }
        };
        ids.push(id);
    }
    for t in &tris {
        let [a, b, c] = t.map(|i| ids[i]);
        // The strip runs the shell's way; the face mesh stores its own.
        fm.triangles
            .push(if forward { [a, b, c] } else { [a, c, b] });
    }
    let mut others: Vec<u64> = tally
        .keys()
        .filter(|&&f| f != owner)
        .map(|&f| model.faces[f as usize].step_id)
        .collect();
    others.sort_unstable();
    let width = tris
        .iter()
        .map(|t| height(xyz[t[0]], xyz[t[1]], xyz[t[2]]))
        .fold(0.0, f64::max);
    let with = if others.is_empty() {
        String::new()
    } else {
        let list: Vec<String> = others.iter().map(|id| format!("#{id}")).collect();
        format!(" with face(s) {}", list.join(", "))
    };
    Some(FaceRepair {
        face: FaceId(owner),
        step_id: owner_face.step_id,
        note: format!(
            "a crack of {} boundary edges{with} ({width:.2e} mm wide, below the deflection) \
             was closed with {} triangle(s)",
            crack.vertices.len(),
            tris.len()
        ),
    })
}

#[cfg(test)]
mod tests {
    use cadre_brep::{Face, Model, Shell, ShellId, SurfaceId};
    use cadre_geom::{Frame, Surface, Vec2, Vec3};

    use super::*;
    use crate::MeshParams;
    use crate::weld::WeldedMesh;

    fn point(x: f64, y: f64, z: f64, key: Option<u64>) -> MeshPoint {
        MeshPoint {
            uv: Vec2::new(x, y),
            xyz: Vec3::new(x, y, z),
            normal: Vec3::Z,
            key,
        }
    }

    /// A closed "pillow" of two faces on one square (keys 0–3), the top one with its side
    /// 0 → 1 split at an unkeyed point `bulge` off the side, as a repaired trim leaves it:
    /// a crack of three boundary edges between the faces.
    fn pillow(bulge: f64) -> (Model, ModelMesh) {
        let mut model = Model::default();
        model.surfaces.push(Surface::Plane {
            frame: Frame::WORLD,
        });
        for step_id in [10, 20] {
            model.faces.push(Face {
                surface: SurfaceId(0),
                same_sense: true,
                loops: Vec::new(),
                step_id,
            });
        }
        model.shells.push(Shell {
            faces: vec![(FaceId(0), true), (FaceId(1), false)],
            closed: true,
            step_id: 30,
        });
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let mut top: Vec<MeshPoint> = corners
            .iter()
            .enumerate()
            .map(|(k, &(x, y))| point(x, y, 0.0, Some(k as u64)))
            .collect();
        top.push(point(0.5, bulge, 0.0, None));
        let top = FaceMesh {
            points: top,
            triangles: vec![[0, 4, 3], [4, 1, 2], [4, 2, 3]],
            ..FaceMesh::default()
        };
        let bottom = FaceMesh {
            points: top.points[..4].to_vec(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..FaceMesh::default()
        };
        let mesh = ModelMesh {
            faces: vec![Some(top), Some(bottom)],
            params: MeshParams {
                deflection: 0.01,
                ..MeshParams::default()
            },
            ..ModelMesh::default()
        };
        (model, mesh)
    }

    #[test]
    fn thin_crack_is_filled_and_reported() {
        let (model, mut mesh) = pillow(1e-4);
        let before = WeldedMesh::shell(&model, &mesh, ShellId(0)).census();
        assert_eq!(before.boundary, 3);
        let notes = close_cracks(&model, &mut mesh);
        let after = WeldedMesh::shell(&model, &mesh, ShellId(0)).census();
        assert_eq!(after, crate::EdgeCensus::default());
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0].note.contains("crack of 3 boundary edges"),
            "{}",
            notes[0].note
        );
    }

    /// Negative control: a gap wider than the deflection is a hole, left open.
    #[test]
    fn wide_gap_stays_open() {
        let (model, mut mesh) = pillow(0.1);
        let notes = close_cracks(&model, &mut mesh);
        assert!(notes.is_empty());
        let after = WeldedMesh::shell(&model, &mesh, ShellId(0)).census();
        assert_eq!(after.boundary, 3);
    }
}
