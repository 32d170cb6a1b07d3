// Edges composite: the coverage `raster.wgsl` summed per pixel, blended over the image in the
// edge colour (one full-screen triangle; pixels no edge reached are discarded).

@group(0) @binding(1) var<storage, read> cover: array<u32>;

// As `raster.wgsl`.
const COVER_SCALE: f32 = 65536.0;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return screen_triangle(vi);
}

@fragment
fn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let sum = cover[u32(p.y) * u32(frame.viewport.x) + u32(p.x)];
    if sum == 0u {
        discard;
    }
    // 1 − Π(1 − aᵢ) of the fragments the quads would have blended one over the other.
    let alpha = 1.0 - exp(-f32(sum) / COVER_SCALE);
    return vec4<f32>(frame.edge_colour.rgb, alpha);
}
