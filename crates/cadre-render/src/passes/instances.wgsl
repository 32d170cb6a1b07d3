// The scene's instances, for every pass that draws them (bind group 1,
// layout::INSTANCE_BINDINGS). A draw call's instance `i` is local placement
// `locals_first + i % locals_count` of draw record `record + i / locals_count`: a shared
// sub-assembly's placements are stored once and composed here, so 10⁶ placed parts need
// 10³ records, not 10⁶.

@group(1) @binding(0) var<uniform> call: Call;
@group(1) @binding(1) var<storage, read> draws: array<Draw>;
@group(1) @binding(2) var<storage, read> locals: array<Local>;

// Record and local placement of the call's instance `i`.
fn instance_parts(i: u32) -> vec2<u32> {
    let count = max(call.locals_count, 1u);
    return vec2<u32>(call.record + i / count, call.locals_first + i % count);
}

// The draw of the call's instance `i`: its record placed by its local placement, with the
// local's instance offset and mirror flag.
fn instance_draw(i: u32) -> Draw {
    return parts_draw(instance_parts(i));
}

// The draw of record `at.x` placed by local placement `at.y` (`instance_draw`'s, for a pass
// that kept an instance's parts).
fn parts_draw(at: vec2<u32>) -> Draw {
    var d = draws[at.x];
    let l = locals[at.y];
    d.model = d.model * l.model;
    let n = mat3x3<f32>(d.normal[0].xyz, d.normal[1].xyz, d.normal[2].xyz)
        * mat3x3<f32>(l.normal[0].xyz, l.normal[1].xyz, l.normal[2].xyz);
    d.normal = array<vec4<f32>, 3>(vec4<f32>(n[0], 0.0), vec4<f32>(n[1], 0.0), vec4<f32>(n[2], 0.0));
    d.instance += l.offset;
    d.flags ^= l.flags;
    return d;
}

// A call whose instances are their own records (the identity local list: nothing to
// compose) reads its record as instance-step vertex attributes (`layout::DRAW_ATTRIBUTES`,
// the twin of this struct). A CPU rasterizer fetches those once per instance and broadcasts
// them, where a storage read is a gather of every member for every vertex: on lavapipe the
// storage path cost 256 ms of a 1.1 M-triangle frame at 320×240 that drew in 148 ms without
// any per-vertex instance read.
struct DrawAttributes {
    @location(8) model_0: vec4<f32>,
    @location(9) model_1: vec4<f32>,
    @location(10) model_2: vec4<f32>,
    @location(11) model_3: vec4<f32>,
    @location(12) normal_0: vec4<f32>,
    @location(13) normal_1: vec4<f32>,
    @location(14) normal_2: vec4<f32>,
    // material, instance, flags, padding.
    @location(15) ids: vec4<u32>,
}

// The record `a` carries.
fn attribute_draw(a: DrawAttributes) -> Draw {
    var d: Draw;
    d.model = mat4x4<f32>(a.model_0, a.model_1, a.model_2, a.model_3);
    d.normal = array<vec4<f32>, 3>(a.normal_0, a.normal_1, a.normal_2);
    d.material = a.ids.x;
    d.instance = a.ids.y;
    d.flags = a.ids.z;
    return d;
}

// What a fragment needs of its instance (`InstanceIds`, common.wgsl) is looked up once per
// vertex and carried as a flat varying: a fragment that looked it up again would pay
// `instance_parts`' integer division and modulo per pixel, which a CPU rasterizer runs lane
// by lane (no vector integer division).

// `d`'s ids packed for a flat varying (`unpack_instance` reads them back).
fn pack_instance(d: Draw) -> vec3<u32> {
    return vec3<u32>(d.material, d.instance, d.flags);
}

fn unpack_instance(v: vec3<u32>) -> InstanceIds {
    return InstanceIds(v.x, v.y, v.z);
}
