// Shade pass, outlines: distances from the visibility buffer and silhouettes (see
// shade.wgsl).

// A distance beyond any surface: the background's, so it is always farther than a face.
const FAR_AWAY: f32 = 1e30;

// Distance from the eye (along the view axis) of the visibility buffer's surface at `p`;
// `FAR_AWAY` for background or outside the image. The reverse-Z depth is unprojected through
// the inverse projection: with a finite far plane depth is not proportional to 1/distance (it
// reaches 0 at the far plane, not at infinity), and orthographic depth is linear in distance,
// so relative gaps in depth are not relative gaps in distance.
fn distance_at(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return FAR_AWAY;
    }
    let ids = textureLoad(ids_tex, p, 0);
    if ids.y == 0u {
        return FAR_AWAY;
    }
    let centre = vec2<f32>(p) + 0.5;
    let ndc = vec2<f32>(centre.x / frame.viewport.x * 2.0 - 1.0, 1.0 - centre.y / frame.viewport.y * 2.0);
    let view_h = frame.inv_proj * vec4<f32>(ndc, bitcast<f32>(ids.w), 1.0);
    return -view_h.z / view_h.w;
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
