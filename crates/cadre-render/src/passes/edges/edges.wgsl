// Edges pass: B-Rep edges as anti-aliased lines of constant pixel width. Each segment is a
// quad of two triangles built here from a storage buffer (wgpu has no wide lines). Visibility
// is decided against the visibility buffer's depth (a small relative
// tolerance keeps edges from fighting with their own faces): hidden fragments are dropped,
// drawn dashed, or drawn like the others, by the edge mode.
//
// The fragments are much of what a CPU rasterizer spends on this pass (a 1.5-pixel line's
// quad carries half a pixel of fringe on every side, and a 4×4 block is shaded for every
// block a thin quad touches): what each fragment needs is found per corner (the highlight, flat), and where
// hidden fragments are only dropped (`DEPTH_TESTED`, the visible-edges mode) the pass tests
// them against the visibility depth as its depth attachment, so that the rasterizer drops
// them before shading.

// The pipeline tests fragments against the visibility depth (read only, `GreaterEqual`):
// the corners' depth is divided by (1 − tolerance), which makes that test the shader's own
// `depth < scene × (1 − tolerance)` for hidden fragments. Only in the visible-edges mode.
override DEPTH_TESTED: bool = false;
// Section planes are set (the frame's `counts.z > 0`): fragments in a cut-away half-space are
// dropped. Compiled out otherwise: a CPU rasterizer pays for code under a false uniform
// branch at every fragment.
override SECTIONS: bool = true;
// The frame's other segments were rasterized in compute (`raster.wgsl`): these quads draw
// only the highlighted ones, which that rasterizer leaves to them.
override RASTERED: bool = false;
// The hidden-line mode: the dashes of hidden edges run on each edge's screen arc length from
// its first piece (the pieces before a segment summed each frame), not from each segment's
// start, so they do not restart at every sampled piece of a curved edge.
override DASH_ARC: bool = false;
// The most pieces summed before a segment: a longer polyline's dashes restart every this many
// pieces.
const MAX_DASH_WALK: u32 = 512u;

// The screen arc length (pixels) of the pieces of its polyline before segment `index`, the
// `place`-th, placed by `d`.
fn arc_before(index: u32, place: u32, d: Draw) -> f32 {
    var s = 0.0;
    let n = min(min(place, MAX_DASH_WALK), index);
    for (var j = 1u; j <= n; j++) {
        let e = screen_segment(segments[index - j], d);
        s += select(e.len, 0.0, e.both_behind);
    }
    return s;
}

struct EdgeOut {
    @builtin(position) clip: vec4<f32>,
    // Signed distance across the line and distance along it, in pixels.
    @location(0) @interpolate(linear) across: f32,
    @location(1) @interpolate(linear) along: f32,
    // The segment's colour (the edge colour or its highlight) and its core's half width.
    @location(2) @interpolate(flat) colour: vec4<f32>,
    @location(3) @interpolate(flat) half_width: f32,
    // Camera-relative world position, for the section planes.
    @location(4) world: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) draw_index: u32) -> EdgeOut {
    return edge_corner(vi, instance_draw(draw_index));
}

// `vs_main` for the calls whose records are their instances' (`DrawAttributes`).
@vertex
fn vs_main_direct(@builtin(vertex_index) vi: u32, record: DrawAttributes) -> EdgeOut {
    return edge_corner(vi, attribute_draw(record));
}

// Corner `vi` of its segment's quad, placed by `d`.
fn edge_corner(vi: u32, d: Draw) -> EdgeOut {
    let seg = segments[vi / 4u];
    var width = frame.viewport.z;
    var colour = frame.edge_colour;
    let highlight = highlight_of(seg, d.instance);
    if highlight.w > 0.0 {
        colour = vec4<f32>(highlight.rgb, 1.0);
        width = max(2.0 * width, width + 2.0);
    }
    let line = segment_quad(seg, vi, d, 0.5 * width, 0.5);
    var out: EdgeOut;
    out.clip = line.clip;
    if behind_its_solid(seg, d) | (RASTERED & (highlight.w <= 0.0)) {
        // Every corner outside the clip volume: the quad is dropped before rasterization.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    } else if DEPTH_TESTED {
        // Reverse Z: z / (1 − tolerance) ≥ scene ⟺ z ≥ scene × (1 − tolerance); kept in
        // the clip volume (a depth of 1 passes every test).
        out.clip.z = min(line.clip.z / (1.0 - frame.tolerances.x), line.clip.w);
    }
    out.across = line.across;
    out.along = line.along;
    if DASH_ARC {
        out.along += arc_before(vi / 4u, seg.pad.x, d);
    }
    out.colour = colour;
    out.half_width = 0.5 * width;
    out.world = line.world;
    return out;
}

@fragment
fn fs_main(in: EdgeOut) -> @location(0) vec4<f32> {
    if SECTIONS && section_cut(in.world) {
        discard;
    }
    var colour = in.colour;
    if !DEPTH_TESTED {
        let scene_depth = textureLoad(depth_tex, vec2<i32>(in.clip.xy), 0).x;
        // Reverse Z: nearer is larger. The tolerance keeps an edge on its own faces visible.
        let hidden = in.clip.z < scene_depth * (1.0 - frame.tolerances.x);
        // Each test joins `hidden` (see `section_cut`, common.wgsl, on uniform-only tests).
        let mode = frame.modes.z;
        if hidden & (mode == EDGES_VISIBLE) {
            discard;
        }
        if hidden & (mode == EDGES_HIDDEN_DASHED) {
            // 4 on, 4 off (at 1×: `viewport.w` is the period), box-filtered over the pixel.
            let bit = max(frame.viewport.w, 8.0) / 8.0;
            colour = frame.hidden_colour;
            colour.a *= stipple_coverage(0x0f0fu, bit, in.along - 0.5, in.along + 0.5);
            if colour.a <= 0.0 {
                discard;
            }
        }
    }
    let coverage = clamp(in.half_width + 0.5 - abs(in.across), 0.0, 1.0);
    if coverage <= 0.0 {
        discard;
    }
    return vec4<f32>(colour.rgb, colour.a * coverage);
}
