// Shade pass, outlines: distances from the visibility buffer and silhouettes (see
// shade.wgsl).

// Whether `p`, whose surface is at `depth`, lies on a silhouette: a neighbour farther from
// the eye by more than the relative jump `tolerances.y` (another part, the background, the
// image's border, or the same part behind a fold). Only the nearer side of a jump is marked,
// so outlines stay one pixel wide and on the object. Written without branches or divisions
// per neighbour (one for the centre): a CPU rasterizer runs every lane through both sides of
// a branch with mask bookkeeping, and the early-return form cost 10 ms of a 1280×960 frame.
fn on_silhouette(p: vec2<i32>, depth: f32) -> bool {
    let m = frame.inv_proj;
    // The z and w rows of the unprojection (the distance from the eye is -z / w).
    let z_row = vec4<f32>(m[0].z, m[1].z, m[2].z, m[3].z);
    let w_row = vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w);
    let scale = vec2<f32>(2.0, -2.0) / frame.viewport.xy;
    let ndc = (vec2<f32>(p) + 0.5) * scale + vec2<f32>(-1.0, 1.0);
    let centre = vec4<f32>(ndc, depth, 1.0);
    let limit = -dot(z_row, centre) / dot(w_row, centre) * (1.0 + frame.tolerances.y);
    let s = Silhouette(p, ndc, scale, limit, z_row, w_row);
    return farther(s, vec2<i32>(1, 0)) | farther(s, vec2<i32>(-1, 0))
        | farther(s, vec2<i32>(0, 1)) | farther(s, vec2<i32>(0, -1));
}

// What `on_silhouette` compares each neighbour with.
struct Silhouette {
    p: vec2<i32>,
    ndc: vec2<f32>,
    scale: vec2<f32>,
    limit: f32,
    z_row: vec4<f32>,
    w_row: vec4<f32>,
}

// Whether the neighbour of `s.p` at `offset` is farther than `s.limit`: -z / w > limit, with
// w > 0 in front of the eye; the background (depth 0, the cleared far plane) and outside the
// image are farther.
fn farther(s: Silhouette, offset: vec2<i32>) -> bool {
    let size = vec2<i32>(frame.viewport.xy);
    let q = s.p + offset;
    let inside = all(q >= vec2<i32>(0)) & all(q < size);
    let d = textureLoad(depth_tex, clamp(q, vec2<i32>(0), size - 1), 0).x;
    let n = vec4<f32>(s.ndc + vec2<f32>(offset) * s.scale, d, 1.0);
    return !inside | (d <= 0.0) | (-dot(s.z_row, n) > s.limit * dot(s.w_row, n));
}

// The ids at `p`, or `fallback` outside the image.
fn ids_at(p: vec2<i32>, fallback: vec4<u32>) -> vec4<u32> {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return fallback;
    }
    return textureLoad(ids_tex, p, 0);
}
