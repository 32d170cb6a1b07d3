//! From a meshed model to an export [`Scene`]: one mesh per part (faces keep their own
//! vertices so normals stay sharp at edges and each vertex knows its face), one node per
//! occurrence (the assembly tree), materials from the STEP colours.

use std::collections::{HashMap, HashSet};

use cadre_brep::trim::EdgeSamples;
use cadre_brep::{Body, EdgeId, FaceId, LoopKind, Model, PartId, ShellId, SolidId, Style};

use crate::ModelMesh;
use crate::scene::{
    Material, Primitive, Scene, SceneEdge, SceneIds, SceneMesh, SceneNode, SceneVertex,
};

/// Most nodes the scene may get (about 1 GB of scene and 2 GB of glTF at the most); wider
/// assembly expansions are cut. Commands that export check
/// [`cadre_brep::Model::placed_instances`] against it before meshing and refuse, so the cut
/// is never silent there.
pub const MAX_NODES: usize = 4_000_000;

/// Part instances past which the scene shares a sub-assembly's nodes between its uses (a
/// node graph, one node per occurrence in the file) instead of expanding the tree: the
/// renderer then draws the shared nodes by instancing (10⁶ placed cubes from 60 nodes, where
/// the tree took 2.4 GB), and the writers expand what they write.
pub const SHARE_NODES_ABOVE: u64 = 1 << 18;

/// sRGB-encoded component (as CAD colours are given) to linear (as glTF wants).
fn linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Material key: colour quantised to 1/1000 and opacity.
type MaterialKey = Option<[u16; 4]>;

struct Builder<'a> {
    model: &'a Model,
    mesh: &'a ModelMesh,
    materials: Vec<Material>,
    material_index: HashMap<[u16; 4], usize>,
    /// Faces added to the part being built, for its edges and vertices.
    part_faces: Vec<FaceId>,
    /// The model's dense ids.
    ids: SceneIds,
}

impl Builder<'_> {
    fn material(&mut self, style: &Style) -> Option<usize> {
        let key: MaterialKey = style.color.map(|c| {
            let q = |x: f32| (x.clamp(0.0, 1.0) * 1000.0).round() as u16;
            [q(c.r), q(c.g), q(c.b), q(1.0 - style.transparency)]
        });
        let key = key?;
        if let Some(&i) = self.material_index.get(&key) {
            return Some(i);
        }
        let c = style.color.expect("key implies colour");
        let i = self.materials.len();
        self.materials.push(Material {
            name: format!("colour {:.3} {:.3} {:.3}", c.r, c.g, c.b),
            base_color: [
                linear(c.r),
                linear(c.g),
                linear(c.b),
                (1.0 - style.transparency).clamp(0.0, 1.0),
            ],
            // CAD parts read best as slightly glossy dielectrics unless told otherwise.
            metallic: 0.0,
            roughness: 0.45,
        });
        self.material_index.insert(key, i);
        Some(i)
    }

    /// Appends one face's triangles (own vertices) to `out`, into the primitive of its
    /// material.
    fn add_face(
        &mut self,
        out: &mut SceneMesh,
        prims: &mut HashMap<Option<usize>, usize>,
        face: FaceId,
        forward: bool,
        style: Style,
    ) {
        if style.invisible {
            return;
        }
        let Some(Some(fm)) = self.mesh.faces.get(face.index()) else {
            return;
        };
        self.part_faces.push(face);
        let material = self.material(&style);
        let slot = *prims.entry(material).or_insert_with(|| {
            out.primitives.push(Primitive {
                indices: Vec::new(),
                material,
                face_ids: Vec::new(),
            });
            out.primitives.len() - 1
        });
        let base = out.positions.len() as u32;
        let sign = if forward { 1.0 } else { -1.0 };
        // Meshes from the file have no (u, v): pad so every vertex of a part keeps its own.
        out.surface_uv.resize(out.positions.len(), [0.0; 2]);
        for p in &fm.points {
            out.positions.push(p.xyz.as_vec3().to_array());
            out.normals.push((p.normal * sign).as_vec3().to_array());
            out.surface_uv.push(p.uv.as_vec2().to_array());
        }
        let face_id = SceneIds::face_id(face);
        let surface = &self.model.surfaces[self.model.faces[face.index()].surface.index()];
        // Which parameter each point leaves undefined (a pole, an apex): there its (u, v) is a
        // convention, and every triangle needs its own copy with the value that continues its
        // other corners (or (u, v) interpolated across the triangle points the wrong way).
        let degenerate: Vec<Option<bool>> = fm
            .points
            .iter()
            .map(|p| singular_parameter(surface, p.uv))
            .collect();
        let mut triangles = Vec::with_capacity(fm.triangles.len());
        for t in &fm.triangles {
            // Triangles that weld to a segment (two corners with one key) are degenerate.
            let keys = t.map(|i| fm.points[i as usize].key);
            if keys[0].is_some() && (keys[0] == keys[1] || keys[0] == keys[2])
                || keys[1].is_some() && keys[1] == keys[2]
            {
                continue;
            }
            let mut corners = t.map(|i| base + i);
            for k in 0..3 {
                let i = t[k] as usize;
                let Some(u_degenerate) = degenerate[i] else {
                    continue;
                };
                let others = [t[(k + 1) % 3], t[(k + 2) % 3]].map(|j| fm.points[j as usize].uv);
                let mut uv = fm.points[i].uv;
                if u_degenerate {
                    uv.x = 0.5 * (others[0].x + others[1].x);
                } else {
                    uv.y = 0.5 * (others[0].y + others[1].y);
                }
                // The normal there too, where the surface has one per value of the free
                // parameter: a cone's apex has one per ruling, and the point's own (the
                // convention's ruling) faced the other way from the triangles across the
                // apex, shading them as the cone's far side.
                let other = t[(k + 1) % 3] as usize;
                let normal = corner_normal(surface, uv, &fm.points[other])
                    .map_or(out.normals[base as usize + i], |n| {
                        (n * sign).as_vec3().to_array()
                    });
                corners[k] = out.positions.len() as u32;
                out.positions.push(out.positions[base as usize + i]);
                out.normals.push(normal);
                out.surface_uv.push(uv.as_vec2().to_array());
            }
            triangles.push(corners);
        }
        let prim = &mut out.primitives[slot];
        for [a, b, c] in triangles {
            prim.indices
                .extend(if forward { [a, b, c] } else { [a, c, b] });
            prim.face_ids.push(face_id);
        }
    }

    fn shell(
        &mut self,
        out: &mut SceneMesh,
        prims: &mut HashMap<Option<usize>, usize>,
        shell: ShellId,
        solid: Option<SolidId>,
        part: PartId,
    ) {
        for &(face, forward) in &self.model.shells[shell.index()].faces {
            let style = self.model.face_style(face, Some(shell), solid, Some(part));
            self.add_face(out, prims, face, forward, style);
        }
    }

    fn part_mesh(&mut self, part: PartId) -> Option<SceneMesh> {
        let p = self.model.part(part);
        let mut out = SceneMesh {
            name: p.name.clone(),
            ..SceneMesh::default()
        };
        let mut prims = HashMap::new();
        self.part_faces.clear();
        for body in &p.bodies {
            match body {
                Body::Solid(s) => {
                    for shell in self.model.solids[s.index()].shells() {
                        self.shell(&mut out, &mut prims, shell, Some(*s), part);
                    }
                }
                Body::Shell(s) => self.shell(&mut out, &mut prims, *s, None, part),
                Body::Face(f) => {
                    let style = self.model.face_style(*f, None, None, Some(part));
                    self.add_face(&mut out, &mut prims, *f, true, style);
                }
                Body::Mesh(m) => {
                    let tm = &self.model.meshes[m.index()];
                    let style = self
                        .model
                        .styles
                        .get(&cadre_brep::StyleTarget::Mesh(*m))
                        .copied()
                        .unwrap_or_default()
                        .over(
                            self.model
                                .styles
                                .get(&cadre_brep::StyleTarget::Part(part))
                                .copied()
                                .unwrap_or_default(),
                        );
                    if style.invisible {
                        continue;
                    }
                    let material = self.material(&style);
                    let base = out.positions.len() as u32;
                    out.positions
                        .extend(tm.positions.iter().map(|p| p.as_vec3().to_array()));
                    let normals = smooth_normals(tm);
                    out.normals.extend(normals);
                    out.primitives.push(Primitive {
                        indices: tm.triangles.iter().flatten().map(|i| base + i).collect(),
                        material,
                        face_ids: vec![self.ids.mesh_face_id(*m); tm.triangles.len()],
                    });
                }
                Body::Edge(e) => {
                    let samples = self.mesh.edges.samples(*e);
                    add_polyline(&mut out.lines, samples.iter().map(|s| s.xyz));
                }
                Body::Wire(w) => {
                    let curve = &self.model.curves[w.curve.index()];
                    if let Some((t0, t1)) = w.range.or_else(|| curve.domain()) {
                        let points = crate::edges::sample_curve(curve, t0, t1, &self.mesh.params);
                        add_polyline(&mut out.lines, points.into_iter().map(|(_, p)| p));
                    }
                }
                // A lone point has nothing to draw yet.
                Body::Point(_) => {}
            }
        }
        out.primitives.retain(|p| !p.indices.is_empty());
        self.add_edges_and_vertices(&mut out);
        (!out.primitives.is_empty() || !out.lines.is_empty()).then_some(out)
    }

    /// The B-Rep edges and vertices of the part's faces ([`Builder::part_faces`]), once each:
    /// seams (an edge a face uses twice) are left out, as CAD viewers do not draw them.
    fn add_edges_and_vertices(&mut self, out: &mut SceneMesh) {
        let model = self.model;
        let mut edges: Vec<EdgeId> = Vec::new();
        let mut seen_edges = HashSet::new();
        for &face in &self.part_faces {
            let mut uses: HashMap<EdgeId, u32> = HashMap::new();
            for lp in &model.faces[face.index()].loops {
                if let LoopKind::Edges(oriented) = &lp.kind {
                    for oe in oriented {
                        *uses.entry(oe.edge).or_default() += 1;
                    }
                }
            }
            let mut own: Vec<EdgeId> = uses
                .into_iter()
                .filter(|&(_, n)| n == 1)
                .map(|(e, _)| e)
                .collect();
            own.sort_unstable_by_key(|e| e.index());
            edges.extend(own.into_iter().filter(|&e| seen_edges.insert(e)));
        }
        let mut seen_vertices = HashSet::new();
        for e in edges {
            let Some(edge) = model.edges.get(e.index()) else {
                continue;
            };
            let points: Vec<[f32; 3]> = self
                .mesh
                .edges
                .samples(e)
                .iter()
                .filter(|s| s.xyz.is_finite())
                .map(|s| s.xyz.as_vec3().to_array())
                .collect();
            if points.len() < 2 {
                continue;
            }
            for v in [edge.start, edge.end] {
                if let Some(vertex) = model.vertices.get(v.index())
                    && vertex.point.is_finite()
                    && seen_vertices.insert(v)
                {
                    out.vertices.push(SceneVertex {
                        id: SceneIds::vertex_id(v),
                        position: vertex.point.as_vec3().to_array(),
                    });
                }
            }
            out.edges.push(SceneEdge {
                id: SceneIds::edge_id(e),
                points,
            });
        }
    }
}

/// Appends the segments between consecutive finite points.
fn add_polyline(lines: &mut Vec<[[f32; 3]; 2]>, points: impl Iterator<Item = cadre_geom::Vec3>) {
    let mut prev: Option<[f32; 3]> = None;
    for p in points.filter(|p| p.is_finite()) {
        let p = p.as_vec3().to_array();
        if let Some(q) = prev
            && q != p
        {
            lines.push([q, p]);
        }
        prev = Some(p);
    }
}

/// `Some(true)` where `u` is undefined at `uv` (|∂S/∂u| vanishes: a sphere's pole, a cone's
/// apex), `Some(false)` where `v` is, `None` at a regular point.
fn singular_parameter(surface: &cadre_geom::Surface, uv: cadre_geom::Vec2) -> Option<bool> {
    let d = surface.derivs(uv.x, uv.y);
    let (su, sv) = (d.du.length(), d.dv.length());
    let scale = su.max(sv);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    if su <= 1e-9 * scale {
        Some(true)
    } else if sv <= 1e-9 * scale {
        Some(false)
    } else {
        None
    }
}

/// The face's normal at `uv` (a singular point's (u, v) as one triangle continues it), in
/// the face's sense, which the mesh point `regular` of the same triangle shows (its normal
/// against the surface's there); `None` where the surface has no normal at either.
fn corner_normal(
    surface: &cadre_geom::Surface,
    uv: cadre_geom::Vec2,
    regular: &crate::face::MeshPoint,
) -> Option<cadre_geom::Vec3> {
    let n = surface.normal(uv.x, uv.y)?;
    let raw = surface.normal(regular.uv.x, regular.uv.y)?;
    let sense = raw.dot(regular.normal);
    (sense != 0.0).then(|| n * sense.signum())
}

/// Normals of a file's mesh: its own when given, else area-weighted vertex normals.
fn smooth_normals(m: &cadre_brep::TriangleMesh) -> Vec<[f32; 3]> {
    if m.normals.len() == m.positions.len() {
        return m
            .normals
            .iter()
            .map(|n| n.normalize_or_zero().as_vec3().to_array())
            .collect();
    }
    let mut acc = vec![cadre_geom::Vec3::ZERO; m.positions.len()];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let n = (b - a).cross(c - a);
        for i in t {
            acc[*i as usize] += n;
        }
    }
    acc.iter()
        .map(|n| n.normalize_or_zero().as_vec3().to_array())
        .collect()
}

/// The scene of a meshed model: its assembly tree with shared part meshes.
pub fn build_scene(model: &Model, mesh: &ModelMesh) -> Scene {
    let mut b = Builder {
        model,
        mesh,
        materials: Vec::new(),
        material_index: HashMap::new(),
        part_faces: Vec::new(),
        ids: SceneIds::of(model),
    };
    let mut scene = Scene::new("mm");
    let mut part_mesh: Vec<Option<usize>> = Vec::with_capacity(model.parts.len());
    for i in 0..model.parts.len() {
        let m = b.part_mesh(PartId(i as u32));
        part_mesh.push(m.map(|m| {
            scene.meshes.push(m);
            scene.meshes.len() - 1
        }));
    }
    scene.materials = b.materials;
    scene.ids = b.ids;
    let name_of = |part: PartId| {
        let p = model.part(part);
        if p.name.is_empty() {
            p.product_id.clone()
        } else {
            p.name.clone()
        }
    };
    if model.placed_instances() > SHARE_NODES_ABOVE {
        shared_nodes(model, &mut scene, &part_mesh, name_of);
        return scene;
    }
    // Expand the assembly DAG into a tree of nodes (glTF nodes have one parent).
    let mut stack: Vec<(usize, PartId, usize)> = Vec::new();
    for &root in &model.roots {
        scene.nodes.push(SceneNode {
            name: name_of(root),
            mesh: part_mesh[root.index()],
            ..SceneNode::default()
        });
        let n = scene.nodes.len() - 1;
        scene.roots.push(n);
        stack.push((n, root, 0));
    }
    while let Some((node, part, depth)) = stack.pop() {
        if depth >= cadre_brep::assembly::MAX_ASSEMBLY_DEPTH {
            continue;
        }
        for occ in &model.part(part).children {
            if scene.nodes.len() >= MAX_NODES {
                break;
            }
            let name = if occ.name.is_empty() {
                name_of(occ.part)
            } else {
                occ.name.clone()
            };
            scene.nodes.push(SceneNode {
                name,
                transform: occ.transform,
                mesh: part_mesh.get(occ.part.index()).copied().flatten(),
                children: Vec::new(),
            });
            let child = scene.nodes.len() - 1;
            scene.nodes[node].children.push(child);
            stack.push((child, occ.part, depth + 1));
        }
    }
    scene
}

/// The assembly as a node graph: a node per root and per occurrence in the file, the nodes
/// of a part's occurrences shared as the children of every use of that part.
fn shared_nodes(
    model: &Model,
    scene: &mut Scene,
    part_mesh: &[Option<usize>],
    name_of: impl Fn(PartId) -> String,
) {
    // First node of each part's occurrences, which follow in order.
    let mut first_of = Vec::with_capacity(model.parts.len());
    for part in &model.parts {
        first_of.push(scene.nodes.len());
        for occ in &part.children {
            scene.nodes.push(SceneNode {
                name: if occ.name.is_empty() {
                    name_of(occ.part)
                } else {
                    occ.name.clone()
                },
                transform: occ.transform,
                mesh: part_mesh.get(occ.part.index()).copied().flatten(),
                children: Vec::new(),
            });
        }
    }
    let occurrences_of = |part: PartId| {
        let first = first_of.get(part.index()).copied().unwrap_or(0);
        let count = model
            .parts
            .get(part.index())
            .map_or(0, |p| p.children.len());
        (first..first + count).collect::<Vec<usize>>()
    };
    for (p, part) in model.parts.iter().enumerate() {
        for (k, occ) in part.children.iter().enumerate() {
            scene.nodes[first_of[p] + k].children = occurrences_of(occ.part);
        }
    }
    for &root in &model.roots {
        scene.nodes.push(SceneNode {
            name: name_of(root),
            mesh: part_mesh.get(root.index()).copied().flatten(),
            children: occurrences_of(root),
            ..SceneNode::default()
        });
        scene.roots.push(scene.nodes.len() - 1);
    }
}
