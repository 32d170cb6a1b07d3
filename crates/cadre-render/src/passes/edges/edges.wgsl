// Edges pass: B-Rep edges as anti-aliased lines of constant pixel width. Each segment is a
// quad of two triangles built here from a storage buffer (wgpu has no wide lines). Visibility
// is decided against the visibility buffer's depth (a small relative
// tolerance keeps edges from fighting with their own faces): hidden fragments are dropped,
// drawn dashed, or drawn like the others, by the edge mode.

@group(0) @binding(1) var<storage, read> segments: array<Segment>;
// The visibility depth, 0 where nothing is (4 bytes a fragment, where the ids are 16).
@group(0) @binding(2) var depth_tex: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> selection: array<vec4<u32>>;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) draw_index: u32) -> LineOut {
    let seg = segments[vi / 4u];
    let d = instance_draw(draw_index);
    var width = frame.viewport.z;
    if is_highlighted(seg, d.instance) {
        width = max(2.0 * width, width + 2.0);
    }
    return segment_quad(seg, vi, d, 0.5 * width);
}

// Whether the segment's edge (or part) of instance `instance` is hovered or selected.
fn is_highlighted(seg: Segment, instance: u32) -> bool {
    return highlight_of(seg, instance).w > 0.0;
}

// The highlight colour of the segment's edge: selection over hover, alpha 0 for none.
fn highlight_of(seg: Segment, instance: u32) -> vec4<f32> {
    let id = bitcast<u32>(seg.a.w);
    if bitcast<u32>(seg.b.w) != 1u {
        return vec4<f32>(0.0);
    }
    for (var i = 0u; i < frame.counts.y; i++) {
        if is_target(selection[i], 2u, instance + 1u, id) {
            return frame.selection_colour;
        }
    }
    if is_target(frame.hover, 2u, instance + 1u, id) {
        return frame.hover_colour;
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<f32> {
    if section_cut(in.world) {
        discard;
    }
    let scene_depth = textureLoad(depth_tex, vec2<i32>(in.clip.xy), 0).x;
    let seg = segments[in.segment];
    let highlight = highlight_of(seg, in.instance);
    // Reverse Z: nearer is larger. The tolerance keeps an edge on its own faces visible.
    let hidden = in.clip.z < scene_depth * (1.0 - frame.tolerances.x);
    let mode = frame.modes.z;
    var colour = frame.edge_colour;
    var width = frame.viewport.z;
    if highlight.w > 0.0 {
        colour = vec4<f32>(highlight.rgb, 1.0);
        width = max(2.0 * width, width + 2.0);
    }
    if hidden {
        if mode == EDGES_VISIBLE {
            discard;
        }
        if mode == EDGES_HIDDEN_DASHED {
            if fract(in.along / max(frame.viewport.w, 1.0)) > 0.5 {
                discard;
            }
            colour = frame.hidden_colour;
        }
    }
    let coverage = clamp(0.5 * width + 0.5 - abs(in.across), 0.0, 1.0);
    if coverage <= 0.0 {
        discard;
    }
    return vec4<f32>(colour.rgb, colour.a * coverage);
}
