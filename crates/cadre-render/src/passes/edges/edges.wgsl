// Edges pass: B-Rep edges as anti-aliased lines of constant pixel width. Each segment is a
// quad of two triangles built here from a storage buffer (wgpu has no wide lines). Visibility
// is decided against the depth kept in the visibility buffer's ids (a small relative
// tolerance keeps edges from fighting with their own faces): hidden fragments are dropped,
// drawn dashed, or drawn like the others, by the edge mode.

@group(0) @binding(1) var<storage, read> draws: array<Draw>;
@group(0) @binding(2) var<storage, read> segments: array<Segment>;
@group(0) @binding(3) var ids_tex: texture_2d<u32>;

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    // Signed distance across the line and distance along it, in pixels.
    @location(0) @interpolate(linear) across: f32,
    @location(1) @interpolate(linear) along: f32,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) draw_index: u32) -> LineOut {
    let seg = segments[vi / 6u];
    let corner = vi % 6u;
    let d = draws[draw_index];
    let ca = frame.view_proj * (d.model * vec4<f32>(seg.a.xyz, 1.0));
    let cb = frame.view_proj * (d.model * vec4<f32>(seg.b.xyz, 1.0));
    let size = frame.viewport.xy;
    let sa = (ca.xy / ca.w) * 0.5 * size;
    let sb = (cb.xy / cb.w) * 0.5 * size;
    var dir = sb - sa;
    let len = length(dir);
    dir = select(vec2<f32>(1.0, 0.0), dir / len, len > 1e-6);
    let side = vec2<f32>(-dir.y, dir.x);
    // One pixel beyond the half width for the anti-aliased fringe, and past the ends.
    let half = 0.5 * frame.edges.x + 1.0;
    // Corners: (end, side) for the two triangles (0,0) (1,0) (1,1) / (0,0) (1,1) (0,1).
    var ends = array<u32, 6>(0u, 1u, 1u, 0u, 1u, 0u);
    var sides = array<f32, 6>(-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
    let at_b = ends[corner] == 1u;
    let c = select(ca, cb, at_b);
    let s = select(sa, sb, at_b) + side * sides[corner] * half
        + dir * select(-1.0, 1.0, at_b);
    var out: LineOut;
    out.clip = vec4<f32>(s / (0.5 * size) * c.w, c.z, c.w);
    out.across = sides[corner] * half;
    out.along = select(0.0, len, at_b);
    return out;
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<f32> {
    let ids = textureLoad(ids_tex, vec2<i32>(in.clip.xy), 0);
    let scene_depth = select(0.0, bitcast<f32>(ids.w), ids.y != 0u);
    // Reverse Z: nearer is larger. The tolerance keeps an edge on its own faces visible.
    let hidden = in.clip.z < scene_depth * (1.0 - frame.edges.w);
    let mode = u32(frame.edges.y + 0.5);
    var colour = frame.edge_colour;
    if hidden {
        if mode == 0u {
            discard;
        }
        if mode == 2u {
            if fract(in.along / max(frame.edges.z, 1.0)) > 0.5 {
                discard;
            }
            colour = frame.hidden_colour;
        }
    }
    let coverage = clamp(0.5 * frame.edges.x + 0.5 - abs(in.across), 0.0, 1.0);
    if coverage <= 0.0 {
        discard;
    }
    return vec4<f32>(colour.rgb, colour.a * coverage);
}
