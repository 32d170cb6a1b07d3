// X-ray pass: every triangle drawn see-through, without depth test, more opaque where it is
// seen edge-on (a Fresnel-like rim), so the inside of an assembly shows through its shell.

@group(0) @binding(1) var<storage, read> materials: array<Material>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) material: u32,
    // Camera-relative world position, for the section planes.
    @location(2) world: vec3<f32>,
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
    out.material = d.material;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if section_cut(in.world) {
        discard;
    }
    let m = materials[in.material];
    let len = length(in.normal);
    let facing = select(1.0, abs(in.normal.z) / len, len > 0.0);
    let rim = (1.0 - facing) * (1.0 - facing);
    let alpha = mix(0.06, 0.45, rim);
    return vec4<f32>(m.base_color.rgb * (0.55 + 0.45 * facing), alpha);
}

// A see-through part of an opaque view: its material's colour lit by a headlight, with the
// material's opacity.
@fragment
fn fs_transparent(in: VertexOut) -> @location(0) vec4<f32> {
    if section_cut(in.world) {
        discard;
    }
    let m = materials[in.material];
    let len = length(in.normal);
    let facing = select(1.0, abs(in.normal.z) / len, len > 0.0);
    return vec4<f32>(m.base_color.rgb * (0.35 + 0.65 * facing), m.base_color.a);
}
