// Mesh back-end of the visibility pass: triangles of the scene's meshes, placed by their
// draw records (instances.wgsl), each fragment written by `visibility_texel` (texel.wgsl, before this file).

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) face: u32,
    @location(2) @interpolate(flat) instance: vec3<u32>,
    @location(3) uv: vec2<f32>,
    // Camera-relative world position, for the section planes.
    @location(4) world: vec3<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) face: u32,
    @location(3) uv: vec2<f32>,
    @builtin(instance_index) draw_index: u32,
) -> VertexOut {
    let d = instance_draw(draw_index);
    let placed = place_vertex(d, position, normal);
    var out: VertexOut;
    out.clip = placed.clip;
    out.world = placed.world;
    out.normal = placed.normal;
    out.face = face;
    out.instance = pack_instance(d);
    out.uv = uv;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> VisibilityOut {
    if section_cut(in.world) {
        discard;
    }
    let ids = unpack_instance(in.instance);
    return visibility_texel(in.world, in.normal, in.face, ids, in.clip.z, in.uv, front);
}
