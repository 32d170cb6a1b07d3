//! Wavefront OBJ writer (plus MTL materials): every mesh instance flattened in world
//! coordinates ([`Scene::unit_name`] units).
//!
//! Per instance: `o name` and `g name` (the node name with whitespace replaced by `_`,
//! `node<N>` when empty), its `v` (and `vn`, transformed by the inverse transpose and
//! renormalised) lines, then per primitive `usemtl` and `f v//vn` faces (`f v` when the mesh
//! has no normals), indices global and 1-based. Mirrored instances have their winding
//! flipped. Primitives without material use `cadre_default`.
//!
//! The MTL gives per material `Kd` (linear base colour), `d` (alpha), and the common PBR
//! extension `Pm`/`Pr` (metallic, roughness). Face ids are not written.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::scene::{
    Scene, SceneError, is_mirror, normal_matrix, transform_normal, transform_point,
};

/// Material name used for primitives without material.
pub const DEFAULT_MATERIAL: &str = "cadre_default";

/// Error of the OBJ writers.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The scene is inconsistent.
    #[error("invalid scene: {0}")]
    Scene(#[from] SceneError),
    /// An output file could not be created.
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

/// Writes `scene` as OBJ to `out`; with `mtllib`, references that material library file
/// (written separately with [`write_mtl`]), otherwise no `mtllib` line is written.
pub fn write_obj<W: Write>(
    scene: &Scene,
    mut out: W,
    mtllib: Option<&str>,
) -> Result<(), ObjError> {
    scene.validate()?;
    let names = material_names(scene);
    writeln!(out, "# cadre-mesh OBJ, unit: {}", scene.unit_name)?;
    if let Some(lib) = mtllib {
        writeln!(out, "mtllib {lib}")?;
    }
    let mut base = 1u64; // OBJ indices are 1-based and global.
    for (node, world) in scene.instances() {
        let src = &scene.nodes[node];
        let Some(mesh) = src.mesh.map(|m| &scene.meshes[m]) else {
            continue;
        };
        let name = sanitize(&src.name).unwrap_or_else(|| format!("node{node}"));
        writeln!(out, "o {name}")?;
        writeln!(out, "g {name}")?;
        for &p in &mesh.positions {
            let w = transform_point(&world, p).as_vec3();
            writeln!(out, "v {} {} {}", w.x, w.y, w.z)?;
        }
        let normals = !mesh.normals.is_empty();
        let nm = normal_matrix(&world);
        for &n in &mesh.normals {
            let w = transform_normal(&nm, n).as_vec3();
            writeln!(out, "vn {} {} {}", w.x, w.y, w.z)?;
        }
        let flip = is_mirror(&world);
        for prim in &mesh.primitives {
            if prim.indices.is_empty() {
                continue;
            }
            let mat = prim
                .material
                .map_or(DEFAULT_MATERIAL, |m| names[m].as_str());
            writeln!(out, "usemtl {mat}")?;
            for tri in prim.indices.chunks_exact(3) {
                let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| base + u64::from(i));
                let (b, c) = if flip { (c, b) } else { (b, c) };
                if normals {
                    writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
                } else {
                    writeln!(out, "f {a} {b} {c}")?;
                }
            }
        }
        base += mesh.positions.len() as u64;
    }
    out.flush()?;
    Ok(())
}

/// Writes the MTL material library of `scene`: its materials (names made unique and
/// whitespace-free, as [`write_obj`] references them) and [`DEFAULT_MATERIAL`].
pub fn write_mtl<W: Write>(scene: &Scene, mut out: W) -> Result<(), ObjError> {
    scene.validate()?;
    writeln!(out, "# cadre-mesh MTL (linear colours)")?;
    let default = crate::scene::Material::default();
    let names = material_names(scene);
    let all = scene
        .materials
        .iter()
        .zip(names.iter().map(String::as_str))
        .chain(std::iter::once((&default, DEFAULT_MATERIAL)));
    for (mat, name) in all {
        let [r, g, b, a] = mat.base_color.map(|c| c.clamp(0.0, 1.0));
        writeln!(out, "newmtl {name}")?;
        writeln!(out, "Kd {r} {g} {b}")?;
        writeln!(out, "d {a}")?;
        writeln!(out, "Pm {}", mat.metallic.clamp(0.0, 1.0))?;
        writeln!(out, "Pr {}", mat.roughness.clamp(0.0, 1.0))?;
        writeln!(out, "illum 2")?;
        writeln!(out)?;
    }
    out.flush()?;
    Ok(())
}

/// Writes `path` (OBJ) and, next to it, the material library with the same stem and the
/// `.mtl` extension, referenced by `mtllib`. Both are replaced if they exist.
pub fn write_obj_file(scene: &Scene, path: &Path) -> Result<(), ObjError> {
    let mtl_path = path.with_extension("mtl");
    let mtl_name = mtl_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "materials.mtl".to_owned());
    scene.validate()?;
    let create = |p: &Path| {
        File::create(p)
            .map(BufWriter::new)
            .map_err(|source| ObjError::Create {
                path: p.to_owned(),
                source,
            })
    };
    write_mtl(scene, create(&mtl_path)?)?;
    write_obj(scene, create(path)?, Some(&mtl_name))
}

/// `name` with whitespace and control characters replaced by `_`; `None` when empty.
fn sanitize(name: &str) -> Option<String> {
    let s: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_whitespace() || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    (!s.is_empty()).then_some(s)
}

/// Unique MTL names of the scene's materials, in order.
fn material_names(scene: &Scene) -> Vec<String> {
    let mut seen = std::collections::HashSet::new();
    seen.insert(DEFAULT_MATERIAL.to_owned());
    scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let base = sanitize(&m.name).unwrap_or_else(|| format!("material{i}"));
            let mut name = base.clone();
            let mut k = 1;
            while !seen.insert(name.clone()) {
                k += 1;
                name = format!("{base}_{k}");
            }
            name
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_clean() {
        let mut s = Scene::default();
        for n in ["steel part", "steel_part", "", "cadre_default"] {
            s.materials.push(crate::scene::Material {
                name: n.into(),
                ..Default::default()
            });
        }
        assert_eq!(
            material_names(&s),
            ["steel_part", "steel_part_2", "material2", "cadre_default_2"]
        );
    }
}
