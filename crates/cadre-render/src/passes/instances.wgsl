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
    let at = instance_parts(i);
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
