//! Trim structures for rendering B-Rep faces exactly on the GPU (seed 000, Part III; issue 16).
//!
//! A face is its support surface cut by trim loops in the surface's (u, v) domain. The GPU
//! back-end tessellates the surface to the screen and decides per fragment whether its
//! (u, v) lies on the face. This crate builds what that test reads, from the loops the model
//! already has (`cadre_brep::trim`):
//!
//! - [`fit`]: each loop segment (one B-Rep edge's trace in (u, v)) approximated by quadratic
//!   Bézier pieces under *separate* tolerances in u and in v ([`UvTolerance`]): a surface's
//!   domain is anisotropic (a cylinder's u is an angle, its v a length), so one parametric
//!   tolerance would be far too tight on one axis or too loose on the other;
//! - [`quad`]: the pieces, split where they turn in u or v (monotone pieces, for bounding
//!   boxes and crossing counts), each with its local implicit form (Loop–Blinn), whose sign
//!   says on which side of the piece a point lies.
//!
//! - [`quadtree`]: the multiresolution trim quadtree over the domain, whose leaves hold at
//!   most two pieces (parted by a line), with a coverage bit per node and an exact fallback
//!   (crossing parity) where more pieces meet at the depth cap; its CPU classifier.
//!
//! - [`layout`]: many faces' trees packed in the words a GPU reads, face-local in `f32`, and
//!   the classifier on those words (the oracle of the GPU's test).
//!
//! - [`model`]: every face of a model, in parallel: its trim loops, its (u, v) tolerances
//!   from an object-space tolerance and the surface's speeds, its tree, packed; counts.
//!
//! Still to come (issue 16): the GPU back-end that reads the words.

pub mod fit;
pub mod layout;
pub mod model;
pub mod quad;
pub mod quadtree;

pub use fit::{UvTolerance, fit_points};
pub use layout::{CellClass, FaceRecord, LayoutError, TrimBuffers};
pub use model::{ModelTrees, TrimStats, model_trees};
pub use quad::{Implicit, QuadPiece};
pub use quadtree::{Leaf, Node, TrimTree};

/// The GPU's trim test (`trim_classify`), the twin of [`TrimBuffers::classify`]: the including
/// shader declares the buffers it reads (see the file's header).
pub const TRIM_WGSL: &str = include_str!("trim.wgsl");

/// A point of the (u, v) domain.
pub type Uv = glam::DVec2;
