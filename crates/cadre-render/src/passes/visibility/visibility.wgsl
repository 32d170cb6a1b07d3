// Visibility pass, mesh back-end: writes reverse-Z depth, the view-space normal, the ids
// (face id, instance + 1, material, depth bits) and the (u, v) on the face's exact surface of
// the nearest surface at every pixel. The
// depth is repeated in the ids so later passes need not read a depth texture (GLSL cannot).
//
// Section planes: fragments in a cut-away half-space are discarded. A closed solid seen from
// inside (a back face, kept) is seen through a cut, so the pixel shows a cap: the point where
// the view ray leaves the kept region towards the eye, on the nearest plane it crosses. The
// cap takes the back face's place in the depth test (its own depth, not the cap's): the
// nearest kept surface along the ray after the cap point is a back face exactly when the cap
// point lies inside the solid, so a front face nearer than the back face (a non-convex solid
// whose cut shows through a hole) correctly wins. The ids keep the cap's own depth.

@group(0) @binding(1) var<storage, read> draws: array<Draw>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) @interpolate(flat) face: u32,
    @location(2) @interpolate(flat) draw: u32,
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
    let placed = place_vertex(draws[draw_index], position, normal);
    var out: VertexOut;
    out.clip = placed.clip;
    out.world = placed.world;
    out.normal = placed.normal;
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

// Where the view ray through the camera-relative point `p` (kept) leaves the kept region
// towards the eye: the index of the plane crossed first (-1 when the ray reaches the eye
// inside the kept region: no cap) and the point.
struct Cap {
    plane: i32,
    point: vec3<f32>,
}

fn cap_of(p: vec3<f32>) -> Cap {
    // From the eye through `p` (perspective) or along the view direction (orthographic).
    var dir = normalize(p);
    if frame.modes.x == PROJECTION_ORTHOGRAPHIC {
        dir = frame.forward.xyz;
    }
    // Crossings behind the eye (or its plane) do not count.
    var best = dot(p, dir);
    var cap: Cap;
    cap.plane = -1;
    for (var i = 0u; i < frame.counts.z; i++) {
        let plane = frame.planes[i];
        let towards = dot(plane.xyz, dir);
        // Walking back (−dir) leaves this half-space only where the normal faces the eye.
        if towards < 0.0 {
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

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> VisibilityOut {
    if section_cut(in.world) {
        discard;
    }
    let d = draws[in.draw];
    var out: VisibilityOut;
    let len = length(in.normal);
    out.normal = vec4<f32>(select(vec3<f32>(0.0, 0.0, 1.0), in.normal / len, len > 0.0), 1.0);
    out.ids = vec4<u32>(in.face, d.instance + 1u, d.material, bitcast<u32>(in.clip.z));
    out.uv = bitcast<vec2<u32>>(in.uv);
    // Triangles wind counter-clockwise seen from outside, unless the draw is inside out.
    let from_inside = front == ((d.flags & DRAW_INSIDE_OUT) != 0u);
    if frame.counts.z > 0u && (d.flags & DRAW_CLOSED) != 0u && from_inside {
        let cap = cap_of(in.world);
        if cap.plane >= 0 {
            let clip = frame.view_proj * vec4<f32>(cap.point, 1.0);
            let depth = clamp(clip.z / clip.w, 0.0, 1.0);
            out.normal = vec4<f32>(frame.plane_normals[cap.plane].xyz, 1.0);
            let material = SECTION_CAP | (u32(cap.plane) << 28u) | (d.material & CAP_MATERIAL);
            out.ids = vec4<u32>(0u, d.instance + 1u, material, bitcast<u32>(depth));
            out.uv = vec2<u32>(0u);
        }
    }
    return out;
}
