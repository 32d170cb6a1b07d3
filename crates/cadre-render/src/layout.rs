//! GPU struct layouts, one source for Rust and WGSL: each struct here has a twin of the same
//! name in the passes' `.wgsl` files, and the `layouts_match_the_shaders` test checks the sizes
//! naga computes for those twins against these.

use bytemuck::{Pod, Zeroable};

/// One mesh vertex: position and unit normal (mesh-local), and the STEP id of its B-Rep face.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Vertex {
    /// Position, model units, mesh-local.
    pub position: [f32; 3],
    /// Unit normal, mesh-local.
    pub normal: [f32; 3],
    /// STEP id of the face (0 = none).
    pub face_id: u32,
}

/// Per-frame constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Frame {
    /// Projection × rotation-only view (positions are camera-relative).
    pub view_proj: [[f32; 4]; 4],
    /// Inverse projection, to rebuild view-space positions from depth.
    pub inv_proj: [[f32; 4]; 4],
    /// Background colour, linear RGBA.
    pub background: [f32; 4],
    /// Width, height, 1 when orthographic, unused.
    pub viewport: [f32; 4],
}

/// One draw: a primitive of a mesh placed by one instance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Draw {
    /// Mesh-local → camera-relative world (column-major).
    pub model: [[f32; 4]; 4],
    /// Mesh-local normals → view space (columns, xyz used).
    pub normal: [[f32; 4]; 3],
    /// Index into the material buffer.
    pub material: u32,
    /// Instance number (scene instance order).
    pub instance: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}

/// A metallic-roughness material.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Material {
    /// Linear base colour and alpha.
    pub base_color: [f32; 4],
    /// Metalness, perceptual roughness, unused, unused.
    pub params: [f32; 4],
}
