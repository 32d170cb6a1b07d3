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
fn vs_main(v: MeshVertex, @builtin(instance_index) draw_index: u32) -> VertexOut {
    return full_vertex(instance_draw(draw_index), v);
}

// `vs_main` for the calls whose records are their instances' (`DrawAttributes`).
@vertex
fn vs_main_direct(v: MeshVertex, record: DrawAttributes) -> VertexOut {
    return full_vertex(attribute_draw(record), v);
}

fn full_vertex(d: Draw, v: MeshVertex) -> VertexOut {
    let placed = place_vertex(d, v.position, v.normal);
    var out: VertexOut;
    out.clip = placed.clip;
    out.world = placed.world;
    out.normal = placed.normal;
    out.face = v.face;
    out.instance = pack_instance(d);
    out.uv = v.uv;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> VisibilityOut {
    if SECTIONS && section_cut(in.world) {
        discard;
    }
    let ids = unpack_instance(in.instance);
    let normal = mesh_normal(in.normal, in.clip, front, ids);
    return visibility_texel(in.world, normal, in.face, ids, in.clip.z, in.uv, front);
}

// The interpolated vertex normal `normal` of the fragment at `frag`, mirrored where it
// faces away from the eye across a silhouette (`side_facing`). A mesh's triangles wind
// outward, as its normals face (the rasterizer's `front`, which the inside-out draws turn
// over), so the side needs no derivatives, and the ray no normalising: lavapipe, 1080p,
// 1.1 M triangles, the visibility pass's median 73 ms before the rule, 83 ms with a
// normalised ray, 76 ms as here (BENCHMARKS.md).
fn mesh_normal(normal: vec3<f32>, frag: vec4<f32>, front: bool, ids: InstanceIds) -> vec3<f32> {
    let outward = front != ((ids.flags & DRAW_INSIDE_OUT) != 0u);
    let closed = (ids.flags & DRAW_CLOSED) != 0u;
    // `side_facing` without normalising the ray (a CPU rasterizer pays for each operation
    // of every fragment): the sign of n·r decides, r / (r·r) scales the mirror.
    let r = eye_ray(frag);
    let nr = dot(normal, r);
    let bend = ((nr > 0.0) != outward) && (outward || !closed) && (frame.sky_up.w == 0.0);
    return select(normal, normal - (2.0 * nr / dot(r, r)) * r, bend);
}

// The entry points of frames without section planes that read no (u, v) (every image and
// viewer frame but the exact-surface tests): only what the texel needs is interpolated.
// A CPU rasterizer sets up and interpolates every varying of every triangle, and the
// camera-relative position and the (u, v) are 5 of the 12 floats of `VertexOut`.
struct PlainOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) face: u32,
    @location(2) @interpolate(flat) instance: vec3<u32>,
}

@vertex
fn vs_plain(v: MeshVertex, @builtin(instance_index) draw_index: u32) -> PlainOut {
    return plain_vertex(instance_draw(draw_index), v);
}

// `vs_plain` for the calls whose records are their instances' (`DrawAttributes`).
@vertex
fn vs_plain_direct(v: MeshVertex, record: DrawAttributes) -> PlainOut {
    return plain_vertex(attribute_draw(record), v);
}

// The (u, v) is not carried: nothing reads it without sections.
fn plain_vertex(d: Draw, v: MeshVertex) -> PlainOut {
    let placed = place_vertex(d, v.position, v.normal);
    var out: PlainOut;
    out.clip = placed.clip;
    out.normal = placed.normal;
    out.face = v.face;
    out.instance = pack_instance(d);
    return out;
}

@fragment
fn fs_plain(in: PlainOut, @builtin(front_facing) front: bool) -> VisibilityOut {
    let ids = unpack_instance(in.instance);
    return visibility_texel(vec3<f32>(0.0), mesh_normal(in.normal, in.clip, front, ids), in.face, ids, in.clip.z, vec2<f32>(0.0), front);
}
