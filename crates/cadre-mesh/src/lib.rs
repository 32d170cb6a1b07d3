//! Tessellation of cadre B-Rep models into watertight triangle meshes, and mesh export.
//!
//! Each edge is discretised once in 3D ([`MeshParams`] deflection and angle) and the samples
//! are shared by every face that uses the edge ([`edges`]); each face is then triangulated in
//! its (u, v) domain from its trim loops ([`face`]), so closed shells give closed meshes
//! ([`model`] meshes every face in parallel).

pub mod assemble;
pub mod bbox;
mod crack;
pub mod defects;
pub mod deviation;
pub mod edges;
pub mod export;
pub mod face;
pub mod face_area;
pub mod model;
pub mod params;
pub mod periodic;
pub mod scene;
pub mod stats;
mod strip;
pub mod weld;

pub use bbox::{deflection_diagonal, quick_bbox};
pub use defects::{ShellDefect, shell_defects};
pub use model::{FaceFailure, FaceRepair, ModelMesh, mesh_face, mesh_model};
pub use params::{Deflection, MeshParams};
pub use stats::{MeshStats, mesh_stats};
pub use weld::{EdgeCensus, WeldedMesh};
