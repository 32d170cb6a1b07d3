// Shade pass, outlines: distances from the visibility buffer and silhouettes (see
// shade.wgsl).

// A distance beyond any surface: the background's, so it is always farther than a face.
const FAR_AWAY: f32 = 1e30;

// Distance from the eye (along the view axis) of the visibility buffer's surface at `p`;
// `FAR_AWAY` for background (depth 0, the cleared far plane) or outside the image. The
// reverse-Z depth is unprojected through the inverse projection: with a finite far plane
// depth is not proportional to 1/distance (it reaches 0 at the far plane, not at infinity),
// and orthographic depth is linear in distance, so relative gaps in depth are not relative
// gaps in distance. The depth target is read, not the ids (4 bytes, not 16: five reads a
// pixel), and only the view z and w rows of the unprojection are computed.
fn distance_at(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return FAR_AWAY;
    }
    let depth = textureLoad(depth_tex, p, 0).x;
    if depth <= 0.0 {
        return FAR_AWAY;
    }
    let centre = vec2<f32>(p) + 0.5;
    let ndc = vec4<f32>(centre.x / frame.viewport.x * 2.0 - 1.0, 1.0 - centre.y / frame.viewport.y * 2.0, depth, 1.0);
    let m = frame.inv_proj;
    let z = dot(vec4<f32>(m[0].z, m[1].z, m[2].z, m[3].z), ndc);
    let w = dot(vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w), ndc);
    return -z / w;
}

// Whether `p` lies on a silhouette: a neighbour farther from the eye by more than the
// relative jump `outline.y` (another part, the background, or the same part behind a fold).
// Only the nearer side of a jump is marked, so outlines stay one pixel wide and on the object.
fn on_silhouette(p: vec2<i32>) -> bool {
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    let limit = distance_at(p) * (1.0 + frame.tolerances.y);
    for (var k = 0; k < 4; k++) {
        if distance_at(p + offsets[k]) > limit {
            return true;
        }
    }
    return false;
}

// The ids at `p`, or `fallback` outside the image.
fn ids_at(p: vec2<i32>, fallback: vec4<u32>) -> vec4<u32> {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return fallback;
    }
    return textureLoad(ids_tex, p, 0);
}
