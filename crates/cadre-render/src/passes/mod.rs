//! The frame's passes, in order, each in its own folder with its WGSL:
//! [`visibility`] (every surface back-end writes depth, normal and ids) then [`shade`]
//! (lighting from the visibility buffer alone).

pub(crate) mod shade;
pub(crate) mod visibility;
