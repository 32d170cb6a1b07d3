// Declarations shared by every pass, prepended to each pass's own WGSL when its module is
// built (and by the naga test): the GPU twins of `cadre_render::layout`, and the frame's
// uniform at group 0, binding 0.

struct Frame {
    view_proj: mat4x4<f32>,
    inv_proj: mat4x4<f32>,
    background: vec4<f32>,
    viewport: vec4<f32>,
    edges: vec4<f32>,
    edge_colour: vec4<f32>,
    hidden_colour: vec4<f32>,
    outline: vec4<f32>,
    sky_up: vec4<f32>,
    counts: vec4<u32>,
}

struct Draw {
    model: mat4x4<f32>,
    normal0: vec4<f32>,
    normal1: vec4<f32>,
    normal2: vec4<f32>,
    material: u32,
    instance: u32,
    pad: vec2<u32>,
}

struct Material {
    base_color: vec4<f32>,
    params: vec4<f32>,
}

struct Segment {
    a: vec4<f32>,
    b: vec4<f32>,
}

struct Light {
    position: vec4<f32>,
    direction: vec4<f32>,
    colour: vec4<f32>,
    params: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
