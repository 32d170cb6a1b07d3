//! Binary STL writer: every mesh instance of the scene flattened into one triangle soup in
//! world coordinates ([`Scene::unit_name`] units, mm for cadre; STL has no unit field).
//!
//! Layout: an 80-byte header (`cadre-mesh binary STL, unit: mm`, zero padded; never starting
//! with `solid`), the triangle count (`u32` LE), then per triangle the unit normal computed
//! from the transformed triangle, its three vertices (`f32` LE) and a zero attribute word.
//! Triangles of mirrored instances have their winding flipped so that they stay
//! counter-clockwise seen from outside. Materials and face ids are not written.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::scene::{Scene, SceneError, is_mirror, transform_point};

/// Error of the STL writers.
#[derive(Debug, thiserror::Error)]
pub enum StlError {
    /// The scene is inconsistent.
    #[error("invalid scene: {0}")]
    Scene(#[from] SceneError),
    /// More triangles than the `u32` count of binary STL allows.
    #[error("{0} triangles exceed the binary STL limit of 2^32 - 1")]
    TooManyTriangles(u64),
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

/// Writes `scene` as binary STL to `out` (pass a buffered writer for speed).
pub fn write_stl<W: Write>(scene: &Scene, mut out: W) -> Result<(), StlError> {
    scene.validate()?;
    let total = scene.instance_triangle_count();
    let count = u32::try_from(total).map_err(|_| StlError::TooManyTriangles(total))?;

    let mut header = [0u8; 80];
    let text = format!("cadre-mesh binary STL, unit: {}", scene.unit_name);
    let text = text.as_bytes();
    let n = text.len().min(80);
    header[..n].copy_from_slice(&text[..n]);
    out.write_all(&header)?;
    out.write_all(&count.to_le_bytes())?;

    for (node, world) in scene.instances() {
        let Some(mesh) = scene.nodes[node].mesh.map(|m| &scene.meshes[m]) else {
            continue;
        };
        let flip = is_mirror(&world);
        let world_positions: Vec<DVec3> = mesh
            .positions
            .iter()
            .map(|&p| transform_point(&world, p))
            .collect();
        for prim in &mesh.primitives {
            for tri in prim.indices.chunks_exact(3) {
                let a = world_positions[tri[0] as usize];
                let (b, c) = if flip {
                    (
                        world_positions[tri[2] as usize],
                        world_positions[tri[1] as usize],
                    )
                } else {
                    (
                        world_positions[tri[1] as usize],
                        world_positions[tri[2] as usize],
                    )
                };
                let normal = (b - a).cross(c - a).normalize_or_zero();
                let mut record = [0u8; 50];
                for (k, v) in [normal, a, b, c].iter().enumerate() {
                    for (j, x) in v.to_array().iter().enumerate() {
                        let at = 12 * k + 4 * j;
                        record[at..at + 4].copy_from_slice(&(*x as f32).to_le_bytes());
                    }
                }
                out.write_all(&record)?;
            }
        }
    }
    out.flush()?;
    Ok(())
}

/// [`write_stl`] to a new file at `path` (replaced if it exists).
pub fn write_stl_file(scene: &Scene, path: &Path) -> Result<(), StlError> {
    let file = File::create(path).map_err(|source| StlError::Create {
        path: path.to_owned(),
        source,
    })?;
    write_stl(scene, BufWriter::new(file))
}
