//! Mesh export: writers of the assembled [`Scene`] (meshes, materials, node tree,
//! [`crate::scene`]) for glTF 2.0 (`.glb`, `.gltf`), binary STL and Wavefront OBJ (+ MTL).
//!
//! - glTF keeps the node tree and writes each mesh once, shared by its instances (see
//!   [`gltf`] for the exact layout, the mm → m root scale and the `_FACE_ID`
//!   attribute).
//! - STL and OBJ flatten the scene: every [`Scene::instances`] entry is written with its world
//!   transform applied.
//!
//! Every writer validates the scene first ([`Scene::validate`]) and reports problems as a
//! typed error; none panics on bad input. [`write_scene`] picks the format from the file
//! extension.

pub mod gltf;
pub mod obj;
pub mod stl;

use std::path::{Path, PathBuf};

use crate::scene::Scene;

pub use self::gltf::{
    GltfDocument, GltfError, build_gltf, write_glb, write_glb_file, write_gltf, write_gltf_file,
};
pub use self::obj::{ObjError, write_mtl, write_obj, write_obj_file};
pub use self::stl::{StlError, write_stl, write_stl_file};

/// An export file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// glTF 2.0 JSON with embedded buffer (`.gltf`).
    Gltf,
    /// Binary STL (`.stl`).
    Stl,
    /// Wavefront OBJ with a companion `.mtl` (`.obj`).
    Obj,
}

impl Format {
    /// The format for `path`'s extension (case-insensitive), if supported.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "glb" => Format::Glb,
            "gltf" => Format::Gltf,
            "stl" => Format::Stl,
            "obj" => Format::Obj,
            _ => return None,
        })
    }

    /// The usual file extension, without dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Glb => "glb",
            Format::Gltf => "gltf",
            Format::Stl => "stl",
            Format::Obj => "obj",
        }
    }
}

/// Error of [`write_scene`].
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The path's extension is not one of the supported formats.
    #[error(
        "cannot export to {}: unsupported extension (expected .glb, .gltf, .stl or .obj)",
        path.display()
    )]
    UnsupportedExtension {
        /// The path.
        path: PathBuf,
    },
    /// The glTF writer failed.
    #[error("glTF export to {} failed: {source}", path.display())]
    Gltf {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: GltfError,
    },
    /// The STL writer failed.
    #[error("STL export to {} failed: {source}", path.display())]
    Stl {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: StlError,
    },
    /// The OBJ writer failed.
    #[error("OBJ export to {} failed: {source}", path.display())]
    Obj {
        /// The output path.
        path: PathBuf,
        /// The cause.
        source: ObjError,
    },
}

/// Writes `scene` to `path` in the format given by its extension: `.glb`, `.gltf`, `.stl` or
/// `.obj` (which also writes the `.mtl` next to it); any other extension is
/// [`ExportError::UnsupportedExtension`] and nothing is written.
pub fn write_scene(scene: &Scene, path: &Path) -> Result<Format, ExportError> {
    let format = Format::from_path(path).ok_or_else(|| ExportError::UnsupportedExtension {
        path: path.to_owned(),
    })?;
    let path_buf = || path.to_owned();
    match format {
        Format::Glb => write_glb_file(scene, path).map_err(|source| ExportError::Gltf {
            path: path_buf(),
            source,
        }),
        Format::Gltf => write_gltf_file(scene, path).map_err(|source| ExportError::Gltf {
            path: path_buf(),
            source,
        }),
        Format::Stl => write_stl_file(scene, path).map_err(|source| ExportError::Stl {
            path: path_buf(),
            source,
        }),
        Format::Obj => write_obj_file(scene, path).map_err(|source| ExportError::Obj {
            path: path_buf(),
            source,
        }),
    }?;
    Ok(format)
}
