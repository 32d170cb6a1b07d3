// The mesh back-end's see-through phases: every triangle blended without depth test (x-ray
// mode), or the see-through parts of an opaque view blended over it behind the visibility
// depth. The colours are `see_through.wgsl`'s, shared with the other back-ends.

@group(0) @binding(1) var<storage, read> materials: array<Material>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) material: u32,
    // Camera-relative world position, for the section planes.
    @location(2) world: vec3<f32>,
}

@vertex
fn vs_main(v: MeshVertex, @builtin(instance_index) draw_index: u32) -> VertexOut {
    let d = instance_draw(draw_index);
    let placed = place_vertex(d, v.position, v.normal);
    var out: VertexOut;
    out.clip = placed.clip;
    out.world = placed.world;
    out.normal = placed.normal;
    out.material = d.material;
    return out;
}

@fragment
fn fs_xray(in: VertexOut) -> @location(0) vec4<f32> {
    if section_cut(in.world) {
        discard;
    }
    return xray_colour(materials[in.material].base_color, in.normal);
}

@fragment
fn fs_transparent(in: VertexOut) -> @location(0) vec4<f32> {
    if section_cut(in.world) {
        discard;
    }
    return transparent_colour(materials[in.material].base_color, in.normal);
}
