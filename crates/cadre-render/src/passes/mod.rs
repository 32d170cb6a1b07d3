//! The frame's passes, in order, each in its own folder with its WGSL:
//! [`visibility`] (every surface back-end writes depth, normal and ids), [`cracks`] (the
//! gaps between faces the trim back-end tessellated apart, closed), [`shade`]
//! (lighting from the visibility buffer alone), the see-through phase every surface back-end
//! answers too (transparent parts, or everything in x-ray mode: `visibility::Phase`), then
//! [`edges`] (B-Rep edges as lines) and [`lines`] (polylines and toolpaths with joins, caps and
//! stipples); [`pick`] (edge and vertex ids) runs when a viewer picks.

pub(crate) mod backdrop;
pub(crate) mod common;
pub(crate) mod cracks;
pub(crate) mod edges;
pub(crate) mod instances;
pub(crate) mod lines;
pub(crate) mod pick;
pub(crate) mod shade;
pub(crate) mod text;
pub(crate) mod visibility;
