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

// The view-space point of the fragment at `frag` (its `@builtin(position)`: pixel centre
// and depth), through the inverse projection: a point of the triangle's plane, so its
// screen derivatives span that plane (also in a quad's helper lanes).
fn fragment_view_point(frag: vec4<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(frag.x / frame.viewport.x * 2.0 - 1.0, 1.0 - frag.y / frame.viewport.y * 2.0);
    let h = frame.inv_proj * vec4<f32>(ndc, frag.z, 1.0);
    return h.xyz / h.w;
}

// A tessellated surface's view-space shading normal and the side the eye sees.
struct Facing {
    normal: vec3<f32>,
    front: bool,
}

// The unit view-space direction from the fragment at `frag` towards the eye (the view
// direction's opposite when orthographic): the ray through the pixel's centre, for the
// symmetric perspective `Camera::projection_matrix` makes (two of the inverse
// projection's numbers, not its product with the point).
fn towards_eye(frag: vec4<f32>) -> vec3<f32> {
    return normalize(eye_ray(frag));
}

// `towards_eye` not normalised.
fn eye_ray(frag: vec4<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(frag.x / frame.viewport.x * 2.0 - 1.0, 1.0 - frag.y / frame.viewport.y * 2.0);
    let ray = vec3<f32>(-ndc.x * frame.inv_proj[0][0], -ndc.y * frame.inv_proj[1][1], 1.0);
    return select(ray, vec3<f32>(0.0, 0.0, 1.0), frame.modes.x == PROJECTION_ORTHOGRAPHIC);
}

// The normal to shade a tessellated surface with, and the side of it the eye sees. The
// normal interpolated between a triangle's vertices (exact normals there) can face away
// from the eye while the triangle faces it: a triangle across a curved face's silhouette
// holds points whose normals lie beyond it (a coarse mesh's long triangles, a grid's cells
// at the rim). The shade pass lights both sides of a face alike and turns a normal facing
// away round (−n): its part across the view turns round too, so such a pixel was lit as
// if from the other side — dark specks and bands along lit silhouettes. Where the two
// disagree, the normal is mirrored in the plane perpendicular to the view ray instead
// (n − 2 (n·v) v): it faces the eye by as much as it faced away, keeps its part across
// the view, and meets the unmirrored normals where n·v = 0 (no seam). The triangle's side
// is then the side seen (so a section does not cap the pixel as seen from inside). The
// converse (a triangle seen from behind whose normal faces the eye) is mirrored too on an
// open shell, seen from inside, but not on a closed solid (`closed`), whose back
// triangles show only where they tie with its front ones (an apex).
// `normal` is the interpolated one (any length), `v` towards the eye (`towards_eye`),
// `outward` whether the triangle's side the normals face is the one towards the eye.
// `frame.sky_up.w` at 1 keeps the interpolated normal (the tests' negative control,
// `Renderer::with_raw_silhouettes`).
fn side_facing(normal: vec3<f32>, v: vec3<f32>, outward: bool, closed: bool) -> Facing {
    let nv = dot(normal, v);
    let bend = ((nv > 0.0) != outward) && (outward || !closed) && (frame.sky_up.w == 0.0);
    var out: Facing;
    out.normal = select(normal, normal - 2.0 * nv * v, bend);
    out.front = select(nv > 0.0, outward, bend);
    return out;
}

// `side_facing` for a triangle whose winding says nothing of its normals' side (the trim
// back-end's grids): the side from `plane`, the triangle's normal in either sense (the
// cross product of the view point's screen derivatives), taken in the interpolated
// normal's sense where the two are within 60° (a normal from a singular point may be
// anything; elsewhere the normal stays as interpolated).
fn surface_facing(normal: vec3<f32>, plane: vec3<f32>, frag: vec4<f32>, closed: bool) -> Facing {
    let v = towards_eye(frag);
    let along = dot(plane, normal);
    let outward = dot(plane, v) * sign(along) > 0.0;
    let sure = abs(along) > 0.5 * length(plane) * length(normal);
    if sure {
        return side_facing(normal, v, outward, closed);
    }
    return Facing(normal, dot(normal, v) > 0.0);
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
