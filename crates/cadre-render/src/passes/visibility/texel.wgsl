// The one writer of a visibility texel, shared by every surface back-end (it follows the
// shared declarations of common.wgsl in each back-end's shader): the ids (face id,
// instance + 1, material, depth bits), the view-space normal and the (u, v) on the face's
// exact surface of a kept surface point, or the section cap it shows.
//
// Section planes: a back-end discards fragments in a cut-away half-space (`section_cut`)
// before calling `visibility_texel`. A closed solid seen from inside (a back face, kept) is
// seen through a cut, so the pixel shows a cap: the point where the view ray leaves the kept
// region towards the eye, on the nearest plane it crosses. The cap takes the back face's
// place in the depth test (its own depth, not the cap's): the nearest kept surface along the
// ray after the cap point is a back face exactly when the cap point lies inside the solid, so
// a front face nearer than the back face (a non-convex solid whose cut shows through a hole)
// correctly wins. The ids keep the cap's own depth.

// Section planes and caps compiled in (`MeshVariant` in mesh/mod.rs): a CPU rasterizer runs
// both sides of a branch under lane masks, so the cap search would cost every fragment of a
// frame without sections its full price.
override SECTIONS: bool = true;

struct VisibilityOut {
    @location(0) normal: vec4<f32>,
    @location(1) ids: vec4<u32>,
    @location(2) uv: vec2<u32>,
}

// Where the view ray through the camera-relative point `p` (kept) leaves the kept region
// towards the eye: the index of the plane crossed first (-1 when the ray reaches the eye
// inside the kept region: no cap) and the point.
struct Cap {
    plane: i32,
    point: vec3<f32>,
}

// The normal target's texel of the unit normal `n`: its octahedral map (common.wgsl), then
// the texel's coverage — 1, but for the trim back-end's pixels on a trimmed edge (the
// shade pass blends those with their neighbours across the edge) — and 1.
fn encode_normal(n: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(octahedral(n), 1.0, 1.0);
}

fn cap_of(p: vec3<f32>) -> Cap {
    // From the eye through `p` (perspective) or along the view direction (orthographic).
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let dir = select(normalize(p), frame.forward.xyz, ortho);
    // Crossings behind the eye (or its plane) do not count.
    var best = dot(p, dir);
    var cap: Cap;
    cap.plane = -1;
    // Every plane slot, the count tested inside (see `section_cut`).
    for (var i = 0u; i < MAX_SECTIONS; i++) {
        let plane = frame.planes[i];
        let towards = dot(plane.xyz, dir);
        // Walking back (−dir) leaves this half-space only where the normal faces the eye.
        if (i < frame.counts.z) & (towards < 0.0) {
            let t = max((dot(plane.xyz, p) - plane.w) / towards, 0.0);
            if t < best {
                best = t;
                cap.plane = i32(i);
            }
        }
    }
    cap.point = p - best * dir;
    return cap;
}

// The texel of the surface point `world` (camera-relative) with view-space `normal` (any
// length), on face `face` of instance `d`, at reverse-Z `depth`, with parameters `uv`; `front`
// is whether the point is seen from the side its triangles (or surface) face.
fn visibility_texel(
    world: vec3<f32>,
    normal: vec3<f32>,
    face: u32,
    d: InstanceIds,
    depth: f32,
    uv: vec2<f32>,
    front: bool,
) -> VisibilityOut {
    var out: VisibilityOut;
    let len = length(normal);
    out.normal = encode_normal(select(vec3<f32>(0.0, 0.0, 1.0), normal / len, len > 0.0));
    out.ids = vec4<u32>(face, d.instance + 1u, d.material, bitcast<u32>(depth));
    out.uv = bitcast<vec2<u32>>(uv);
    // Seen from inside: from the back, unless the draw is inside out.
    let from_inside = front == ((d.flags & DRAW_INSIDE_OUT) != 0u);
    if SECTIONS && frame.counts.z > 0u && (d.flags & DRAW_CLOSED) != 0u && from_inside {
        let cap = cap_of(world);
        if cap.plane >= 0 {
            let clip = frame.view_proj * vec4<f32>(cap.point, 1.0);
            let cap_depth = clamp(clip.z / clip.w, 0.0, 1.0);
            out.normal = encode_normal(frame.plane_normals[cap.plane].xyz);
            let material = SECTION_CAP | (u32(cap.plane) << 28u) | (d.material & CAP_MATERIAL);
            out.ids = vec4<u32>(0u, d.instance + 1u, material, bitcast<u32>(cap_depth));
            out.uv = vec2<u32>(0u);
        }
    }
    return out;
}
