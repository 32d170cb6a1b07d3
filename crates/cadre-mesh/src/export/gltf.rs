//! glTF 2.0 writer: binary `.glb` and self-contained `.gltf` (buffer as a base64 data URI).
//!
//! Layout of what is written:
//! - one scene whose only root node is named after [`Scene::unit_name`] and scales by the
//!   unit's size in metres (0.001 for mm), so buffers and node translations stay in model
//!   units while the file is in metres as glTF requires; its children are the scene roots;
//! - one glTF node per node visit of the scene tree (a node reachable along several paths is
//!   duplicated, since glTF nodes must form a strict tree; cycles and over-deep nesting are
//!   cut as in [`Scene::instances`]); transforms are `translation`/`rotation`/`scale` when
//!   the transform is a rotation with positive scales, `matrix` otherwise (mirrors, shear —
//!   note glTF requires matrices to be decomposable to TRS, so a sheared transform is
//!   reported by the Khronos validator);
//! - one glTF mesh per scene mesh used by an exported node, shared by all its instances,
//!   with `POSITION` (with `min`/`max`), `NORMAL` (when present), `_FACE_ID` (when any face
//!   id is given) and `u16`/`u32` indices, one primitive per non-empty
//!   [`Primitive`](crate::scene::Primitive);
//! - PBR metallic-roughness materials (blended when alpha < 1), for the materials used.
//!
//! `_FACE_ID` is a `FLOAT` scalar per vertex (glTF forbids `UNSIGNED_INT` for vertex
//! attributes): the STEP face id of the first triangle using the vertex, 0 for unused
//! vertices; ids above 2^24 cannot be stored exactly and are an error
//! ([`GltfError::FaceIdTooLarge`]).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::{DAffine3, DMat4, DVec3};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};

use crate::scene::{Scene, SceneError, SceneIds, SceneMesh, Visit};

/// Largest face id that `_FACE_ID` (a `FLOAT` attribute) stores exactly: 2^24.
pub const MAX_EXACT_FACE_ID: u32 = 1 << 24;

/// Name of the custom vertex attribute holding the STEP face ids (without the leading `_`,
/// as [`gltf_json::mesh::Semantic::Extras`] wants it).
pub const FACE_ID_ATTRIBUTE: &str = "FACE_ID";

/// Error of the glTF writers.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// The scene is inconsistent.
    #[error("invalid scene: {0}")]
    Scene(#[from] SceneError),
    /// [`Scene::unit_name`] is not a unit [`Scene::metres_per_unit`] knows.
    #[error("unknown length unit {0:?} (expected mm, cm, m, um, in or ft)")]
    UnknownUnit(String),
    /// A face id is too large to be stored exactly in the `_FACE_ID` float attribute.
    #[error("mesh {mesh}: face id {id} exceeds {MAX_EXACT_FACE_ID}, not exact as a glTF float")]
    FaceIdTooLarge {
        /// The mesh.
        mesh: usize,
        /// The face's STEP id.
        id: u64,
    },
    /// The binary buffer or the GLB file exceeds the 4 GiB GLB limit.
    #[error("{0} bytes exceed the 4 GiB GLB size limit")]
    TooLarge(u64),
    /// JSON serialisation failed.
    #[error("JSON serialisation failed: {0}")]
    Json(#[from] serde_json::Error),
    /// The output file could not be created.
    #[error("cannot create {}: {source}", path.display())]
    Create {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: io::Error,
    },
    /// Writing failed.
    #[error("write failed: {0}")]
    Io(#[from] io::Error),
}

/// A built glTF document: the JSON root and its single binary buffer (padded to 4 bytes;
/// `root.buffers[0]` describes it and has no `uri` yet). `bin` is empty and `root.buffers`
/// too when the scene has no geometry.
#[derive(Clone, Debug)]
pub struct GltfDocument {
    /// The JSON document.
    pub root: json::Root,
    /// Contents of buffer 0.
    pub bin: Vec<u8>,
}

/// Builds the glTF document of `scene` (see the [module docs](self) for its layout).
pub fn build_gltf(scene: &Scene) -> Result<GltfDocument, GltfError> {
    scene.validate()?;
    let metres = scene
        .metres_per_unit()
        .ok_or_else(|| GltfError::UnknownUnit(scene.unit_name.clone()))?;
    let visits: Vec<Visit> = scene.walk().collect();

    let mut b = Builder::default();
    b.root.asset.generator = Some(format!("cadre-mesh {}", env!("CARGO_PKG_VERSION")));

    // Meshes (and the materials they use), in scene order, only those placed somewhere.
    let mut used = vec![false; scene.meshes.len()];
    for v in &visits {
        if let Some(m) = scene.nodes[v.node].mesh {
            used[m] = true;
        }
    }
    let mut material_map: Vec<Option<json::Index<json::Material>>> =
        vec![None; scene.materials.len()];
    let mut mesh_map: Vec<Option<json::Index<json::Mesh>>> = vec![None; scene.meshes.len()];
    for (m, mesh) in scene.meshes.iter().enumerate() {
        if used[m] {
            mesh_map[m] = b.mesh(scene, m, mesh, &mut material_map)?;
        }
    }

    // Nodes: one per visit, in visit order, then the unit root.
    let mut nodes: Vec<json::Node> = visits
        .iter()
        .map(|v| {
            let src = &scene.nodes[v.node];
            let mut node = json::Node {
                name: Some(src.name.clone()).filter(|n| !n.is_empty()),
                mesh: src.mesh.and_then(|m| mesh_map[m]),
                ..Default::default()
            };
            set_transform(&mut node, &src.transform);
            node
        })
        .collect();
    let mut roots = Vec::new();
    for (i, v) in visits.iter().enumerate() {
        let index = json::Index::new(i as u32);
        match v.parent {
            Some(p) => nodes[p].children.get_or_insert_with(Vec::new).push(index),
            None => roots.push(index),
        }
    }
    b.root.nodes = nodes;
    let unit_root = b.root.push(json::Node {
        name: Some(scene.unit_name.clone()).filter(|n| !n.is_empty()),
        scale: (metres != 1.0).then_some([metres as f32; 3]),
        children: Some(roots).filter(|r| !r.is_empty()),
        ..Default::default()
    });
    let scene_index = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![unit_root],
    });
    b.root.scene = Some(scene_index);

    pad4(&mut b.bin, 0);
    if !b.bin.is_empty() {
        b.root.buffers.push(json::Buffer {
            byte_length: USize64::from(b.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
    }
    Ok(GltfDocument {
        root: b.root,
        bin: b.bin,
    })
}

/// Writes `scene` as a binary glTF (GLB): header, JSON chunk, and a BIN chunk when there is
/// geometry, each chunk padded to 4 bytes (JSON with spaces, BIN with zeros).
pub fn write_glb<W: Write>(scene: &Scene, mut out: W) -> Result<(), GltfError> {
    let doc = build_gltf(scene)?;
    let mut json_bytes = doc.root.to_vec()?;
    pad4(&mut json_bytes, b' ');
    let bin_chunk = if doc.bin.is_empty() {
        0
    } else {
        8 + doc.bin.len() as u64
    };
    let total = 12 + 8 + json_bytes.len() as u64 + bin_chunk;
    let total = u32::try_from(total).map_err(|_| GltfError::TooLarge(total))?;
    out.write_all(b"glTF")?;
    out.write_all(&2u32.to_le_bytes())?;
    out.write_all(&total.to_le_bytes())?;
    out.write_all(&(json_bytes.len() as u32).to_le_bytes())?;
    out.write_all(b"JSON")?;
    out.write_all(&json_bytes)?;
    if !doc.bin.is_empty() {
        out.write_all(&(doc.bin.len() as u32).to_le_bytes())?;
        out.write_all(b"BIN\0")?;
        out.write_all(&doc.bin)?;
    }
    out.flush()?;
    Ok(())
}

/// Writes `scene` as a self-contained glTF JSON file: the buffer is embedded as a
/// `data:application/octet-stream;base64,` URI.
pub fn write_gltf<W: Write>(scene: &Scene, mut out: W) -> Result<(), GltfError> {
    let mut doc = build_gltf(scene)?;
    if let Some(buffer) = doc.root.buffers.first_mut() {
        let mut uri = String::from("data:application/octet-stream;base64,");
        base64_encode(&doc.bin, &mut uri);
        buffer.uri = Some(uri);
    }
    doc.root.to_writer_pretty(&mut out)?;
    out.write_all(b"\n")?;
    out.flush()?;
    Ok(())
}

/// [`write_glb`] to a new file at `path` (replaced if it exists).
pub fn write_glb_file(scene: &Scene, path: &Path) -> Result<(), GltfError> {
    write_glb(scene, create(path)?)
}

/// [`write_gltf`] to a new file at `path` (replaced if it exists).
pub fn write_gltf_file(scene: &Scene, path: &Path) -> Result<(), GltfError> {
    write_gltf(scene, create(path)?)
}

fn create(path: &Path) -> Result<BufWriter<File>, GltfError> {
    File::create(path)
        .map(BufWriter::new)
        .map_err(|source| GltfError::Create {
            path: path.to_owned(),
            source,
        })
}

/// Accumulates the JSON root and the binary buffer.
#[derive(Default)]
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// Appends `data` as a new buffer view (4-byte aligned) and an accessor over it.
    fn accessor(
        &mut self,
        data: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: json::buffer::Target,
        min_max: Option<(json::Value, json::Value)>,
    ) -> json::Index<json::Accessor> {
        pad4(&mut self.bin, 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(data);
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(data.len()),
            byte_offset: Some(USize64::from(offset)).filter(|&o| o.0 != 0),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: Default::default(),
        });
        let (min, max) = match min_max {
            Some((min, max)) => (Some(min), Some(max)),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn vec3_accessor(
        &mut self,
        values: &[[f32; 3]],
        with_bounds: bool,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let min_max = with_bounds.then(|| {
            let mut min = [f32::INFINITY; 3];
            let mut max = [f32::NEG_INFINITY; 3];
            for p in values {
                for k in 0..3 {
                    min[k] = min[k].min(p[k]);
                    max[k] = max[k].max(p[k]);
                }
            }
            (serde_json::json!(min), serde_json::json!(max))
        });
        self.accessor(
            &bytes,
            values.len(),
            json::accessor::ComponentType::F32,
            json::accessor::Type::Vec3,
            json::buffer::Target::ArrayBuffer,
            min_max,
        )
    }

    /// Writes mesh `m`; `None` when it has no triangles (nothing to write).
    fn mesh(
        &mut self,
        scene: &Scene,
        m: usize,
        mesh: &SceneMesh,
        material_map: &mut [Option<json::Index<json::Material>>],
    ) -> Result<Option<json::Index<json::Mesh>>, GltfError> {
        if mesh.positions.is_empty() || mesh.primitives.iter().all(|p| p.indices.is_empty()) {
            return Ok(None);
        }
        let face_ids = vertex_face_ids(m, mesh, &scene.ids)?;
        let position = self.vec3_accessor(&mesh.positions, true);
        let normal = (!mesh.normals.is_empty()).then(|| self.vec3_accessor(&mesh.normals, false));
        let face_id = face_ids.map(|ids| {
            let bytes: Vec<u8> = ids
                .iter()
                .flat_map(|&id| (id as f32).to_le_bytes())
                .collect();
            self.accessor(
                &bytes,
                ids.len(),
                json::accessor::ComponentType::F32,
                json::accessor::Type::Scalar,
                json::buffer::Target::ArrayBuffer,
                None,
            )
        });
        let small = mesh.positions.len() <= u16::MAX as usize;
        let mut primitives = Vec::new();
        for prim in mesh.primitives.iter().filter(|p| !p.indices.is_empty()) {
            let (bytes, component): (Vec<u8>, _) = if small {
                let b = prim
                    .indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect();
                (b, json::accessor::ComponentType::U16)
            } else {
                let b = prim.indices.iter().flat_map(|&i| i.to_le_bytes()).collect();
                (b, json::accessor::ComponentType::U32)
            };
            let indices = self.accessor(
                &bytes,
                prim.indices.len(),
                component,
                json::accessor::Type::Scalar,
                json::buffer::Target::ElementArrayBuffer,
                None,
            );
            let mut attributes = BTreeMap::new();
            attributes.insert(Valid(json::mesh::Semantic::Positions), position);
            if let Some(normal) = normal {
                attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
            }
            if let Some(face_id) = face_id {
                attributes.insert(
                    Valid(json::mesh::Semantic::Extras(FACE_ID_ATTRIBUTE.to_owned())),
                    face_id,
                );
            }
            let material = prim.material.map(|i| {
                *material_map[i].get_or_insert_with(|| self.material(&scene.materials[i]))
            });
            primitives.push(json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(indices),
                material,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            });
        }
        Ok(Some(self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.clone()).filter(|n| !n.is_empty()),
            primitives,
            weights: None,
        })))
    }

    fn material(&mut self, mat: &crate::scene::Material) -> json::Index<json::Material> {
        let opaque = mat.base_color[3] >= 1.0;
        let unit = |x: f32| x.clamp(0.0, 1.0);
        self.root.push(json::Material {
            name: Some(mat.name.clone()).filter(|n| !n.is_empty()),
            alpha_mode: Valid(if opaque {
                json::material::AlphaMode::Opaque
            } else {
                json::material::AlphaMode::Blend
            }),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(mat.base_color.map(unit)),
                metallic_factor: json::material::StrengthFactor(unit(mat.metallic)),
                roughness_factor: json::material::StrengthFactor(unit(mat.roughness)),
                ..Default::default()
            },
            ..Default::default()
        })
    }
}

/// Per-vertex STEP face ids of `mesh` (looked up in `ids`; first triangle wins, 0 for unused
/// vertices), or `None` when no primitive has face ids.
fn vertex_face_ids(
    m: usize,
    mesh: &SceneMesh,
    scene_ids: &SceneIds,
) -> Result<Option<Vec<u32>>, GltfError> {
    if mesh.primitives.iter().all(|p| p.face_ids.is_empty()) {
        return Ok(None);
    }
    let mut ids = vec![0u32; mesh.positions.len()];
    let mut set = vec![false; mesh.positions.len()];
    for prim in &mesh.primitives {
        for (tri, &id) in prim.indices.chunks_exact(3).zip(&prim.face_ids) {
            let step_id = scene_ids.face_step_id(id);
            let id = match u32::try_from(step_id) {
                Ok(id) if id <= MAX_EXACT_FACE_ID => id,
                _ => {
                    return Err(GltfError::FaceIdTooLarge {
                        mesh: m,
                        id: step_id,
                    });
                }
            };
            for &v in tri {
                let v = v as usize;
                if !set[v] {
                    set[v] = true;
                    ids[v] = id;
                }
            }
        }
    }
    Ok(Some(ids))
}

/// Sets the node's TRS (rotation with positive scale, no shear) or `matrix` (anything else:
/// mirror, shear); nothing for the identity.
fn set_transform(node: &mut json::Node, t: &DAffine3) {
    if *t == DAffine3::IDENTITY {
        return;
    }
    if t.matrix3.determinant() > 0.0 {
        let (s, r, tr) = t.to_scale_rotation_translation();
        let back = DAffine3::from_scale_rotation_translation(s, r, tr);
        let scale = t
            .matrix3
            .to_cols_array()
            .iter()
            .fold(1.0f64, |a, c| a.max(c.abs()));
        let lin_ok = back.matrix3.abs_diff_eq(t.matrix3, 1e-9 * scale);
        if lin_ok && s.is_finite() && r.is_finite() {
            if tr != DVec3::ZERO {
                node.translation = Some(tr.as_vec3().to_array());
            }
            let q = r.as_quat().normalize();
            if q != glam::Quat::IDENTITY {
                node.rotation = Some(json::scene::UnitQuaternion(q.to_array()));
            }
            if s != DVec3::ONE {
                node.scale = Some(s.as_vec3().to_array());
            }
            return;
        }
    }
    node.matrix = Some(DMat4::from(*t).as_mat4().to_cols_array());
}

/// Pads `v` with `byte` to a multiple of 4 bytes.
fn pad4(v: &mut Vec<u8>, byte: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(byte);
    }
}

/// Appends the standard (RFC 4648, padded) base64 encoding of `data` to `out`.
pub(crate) fn base64_encode(data: &[u8], out: &mut String) {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    out.reserve(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_vectors() {
        for (input, expected) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let mut s = String::new();
            base64_encode(input.as_bytes(), &mut s);
            assert_eq!(s, expected);
        }
        let mut s = String::new();
        base64_encode(&[0xff, 0xfe, 0x00], &mut s);
        assert_eq!(s, "//4A");
    }

    #[test]
    fn transforms() {
        let mut n = json::Node::default();
        set_transform(&mut n, &DAffine3::IDENTITY);
        assert!(n.translation.is_none() && n.rotation.is_none() && n.matrix.is_none());

        let mut n = json::Node::default();
        let t = DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, 2.0, 2.0),
            glam::DQuat::from_rotation_z(0.5),
            DVec3::new(1.0, 2.0, 3.0),
        );
        set_transform(&mut n, &t);
        assert!(n.matrix.is_none());
        assert_eq!(n.translation, Some([1.0, 2.0, 3.0]));
        assert_eq!(n.scale, Some([2.0, 2.0, 2.0]));
        assert!(n.rotation.is_some());

        let mut n = json::Node::default();
        set_transform(&mut n, &DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0)));
        assert!(n.matrix.is_some() && n.scale.is_none());

        let mut n = json::Node::default();
        let shear = DAffine3::from_cols(DVec3::X, DVec3::new(0.5, 1.0, 0.0), DVec3::Z, DVec3::ZERO);
        set_transform(&mut n, &shear);
        assert!(n.matrix.is_some());
    }

    #[test]
    fn face_id_limit() {
        let mesh = SceneMesh {
            positions: vec![[0.0; 3]; 3],
            primitives: vec![crate::scene::Primitive {
                indices: vec![0, 1, 2],
                material: None,
                face_ids: vec![MAX_EXACT_FACE_ID + 1],
            }],
            ..SceneMesh::default()
        };
        assert!(matches!(
            vertex_face_ids(0, &mesh, &SceneIds::default()),
            Err(GltfError::FaceIdTooLarge { .. })
        ));
    }
}
