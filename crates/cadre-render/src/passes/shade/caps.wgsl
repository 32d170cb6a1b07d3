// Shade pass, section caps: where a cap ends and its hatch lines (see shade.wgsl).

// Whether the cap pixel `p` (ids `ids`) lies within the outline width of where its cap ends:
// a pixel that is not a cap of the same part and plane.
fn on_cap_boundary(p: vec2<i32>, ids: vec4<u32>) -> bool {
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    // No farther than the image: the bound then is not the uniform value alone, which
    // lavapipe would inline and recompile the pass for at every frame (see `section_cut`,
    // common.wgsl).
    let reach = min(max(i32(frame.section.z + 0.5), 1), i32(textureDimensions(ids_tex).x));
    for (var k = 0; k < 4; k++) {
        for (var r = 1; r <= reach; r++) {
            let q = ids_at(p + offsets[k] * r, ids);
            if q.y != ids.y || q.z != ids.z {
                return true;
            }
        }
    }
    return false;
}

// Coverage (0..1, anti-aliased) of the cap hatch lines at pixel centre `pos`: 45° lines every
// `section.x` pixels, `section.y` wide, the other diagonal for every other part and plane.
fn hatch(pos: vec2<f32>, ids: vec4<u32>) -> f32 {
    let plane = (ids.z >> 28u) & 3u;
    let flip = ((ids.y + plane) & 1u) == 1u;
    let u = select(pos.x + pos.y, pos.x - pos.y, flip) * 0.70710678;
    let spacing = max(frame.section.x, 2.0);
    let d = abs(u - spacing * round(u / spacing));
    return clamp(0.5 * frame.section.y + 0.5 - d, 0.0, 1.0);
}
