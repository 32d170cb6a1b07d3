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
//! Still to come (issue 16): the tree's GPU layout and the classifier on the same bytes,
//! tolerances from each face's surface, statistics over the corpus.

pub mod fit;
pub mod quad;
pub mod quadtree;

pub use fit::{UvTolerance, fit_points};
pub use quad::{Implicit, QuadPiece};
pub use quadtree::{Leaf, Node, TrimTree};

/// A point of the (u, v) domain.
pub type Uv = glam::DVec2;
