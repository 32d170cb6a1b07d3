//! The boundary-representation model of cadre.
//!
//! A [`Model`] keeps the exact geometry (surfaces and curves from `cadre-geom`) and the
//! topology (vertices, edges, loops, faces, shells, solids) in flat arenas indexed by typed
//! ids, plus tessellated meshes that files carry as such (AP242). Parts form an assembly tree:
//! a [`Part`] owns bodies and places child parts through [`Occurrence`]s, so a part used a
//! thousand times is stored once.
//!
//! Faces keep their bounds as oriented edges that carry the file's pcurves where present;
//! [`trim`] turns them into closed loops in each face's (u, v) domain.

pub mod assembly;
pub mod bounds;
pub mod closure;
pub mod ids;
pub mod measure;
pub mod model;
pub mod pmi;
pub mod repair;
pub mod stats;
pub mod step_index;
pub mod style;
pub mod topology;
pub mod triangle_mesh;
pub mod trim;
pub mod units;

pub use assembly::{Body, InstanceVisit, Occurrence, Part};
pub use ids::*;
pub use model::{Model, StyleTarget, Warning};
pub use pmi::Pmi;
pub use stats::Counts;
pub use step_index::{Entity, StepIndex};
pub use style::{Rgb, Style};
pub use topology::{Edge, Face, Loop, LoopKind, OrientedEdge, Shell, Solid, Vertex, Wire};
pub use triangle_mesh::TriangleMesh;
pub use units::Units;
