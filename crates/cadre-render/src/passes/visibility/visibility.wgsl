// Visibility pass, mesh back-end: writes reverse-Z depth, the view-space normal, the ids
// (face id, instance + 1, material, depth bits) and the (u, v) on the face's exact surface of
// the nearest surface at every pixel. The
// depth is repeated in the ids so later passes need not read a depth texture (GLSL cannot).

@group(0) @binding(1) var<storage, read> draws: array<Draw>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) face: u32,
    @location(2) @interpolate(flat) draw: u32,
    @location(3) uv: vec2<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) face: u32,
    @location(3) uv: vec2<f32>,
    @builtin(instance_index) draw_index: u32,
) -> VertexOut {
    let d = draws[draw_index];
    var out: VertexOut;
    out.clip = frame.view_proj * (d.model * vec4<f32>(position, 1.0));
    out.normal = mat3x3<f32>(d.normal0.xyz, d.normal1.xyz, d.normal2.xyz) * normal;
    out.face = face;
    out.draw = draw_index;
    out.uv = uv;
    return out;
}

struct VisibilityOut {
    @location(0) normal: vec4<f32>,
    @location(1) ids: vec4<u32>,
    @location(2) uv: vec2<u32>,
}

@fragment
fn fs_main(in: VertexOut) -> VisibilityOut {
    let d = draws[in.draw];
    var out: VisibilityOut;
    let len = length(in.normal);
    out.normal = vec4<f32>(select(vec3<f32>(0.0, 0.0, 1.0), in.normal / len, len > 0.0), 1.0);
    out.ids = vec4<u32>(in.face, d.instance + 1u, d.material, bitcast<u32>(in.clip.z));
    out.uv = bitcast<vec2<u32>>(in.uv);
    return out;
}
