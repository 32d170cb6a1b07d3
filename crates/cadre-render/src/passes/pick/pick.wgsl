// Pick pass: the B-Rep edges and vertices of every visible instance drawn into an id target
// (model id, instance + 1, kind: 2 edge, 3 vertex), one pixel wide and hidden by the
// visibility depth like the edges pass, vertices after edges so they win where both fall. The
// viewer reads a small window around the cursor and takes the nearest vertex, else the
// nearest edge, else the face under the cursor. Only the window around the cursor is drawn
// (pick.rs: cropped projection, runs culled by their bounding spheres).

@group(0) @binding(1) var<storage, read> segments: array<Segment>;
@group(0) @binding(2) var ids_tex: texture_2d<u32>;
// The target is the pick window alone (the frame's projection cropped to it): its pixel
// (0, 0) is the frame's pixel `region.origin`.
@group(0) @binding(3) var<uniform> region: PickRegion;
// The visibility depth: a pixel's ids count only where it is not 0 (a frame may leave the
// ids of uncovered pixels uncleared, `VisibilityTargets`).
@group(0) @binding(4) var depth_tex: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) draw_index: u32) -> LineOut {
    let seg = segments[vi / 4u];
    // Vertices a little larger than the one-pixel edges, so an edge's end still shows them.
    let vertex = bitcast<u32>(seg.b.w) == 2u;
    return segment_quad(seg, vi, instance_draw(draw_index), select(0.0, 1.0, vertex), 1.0);
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<u32> {
    // Edges and vertices cut away by a section plane cannot be picked.
    if section_cut(in.world) {
        discard;
    }
    let seg = segments[in.segment];
    let vertex = bitcast<u32>(seg.b.w) == 2u;
    // The quads carry a pixel of fringe: keep the core only.
    if abs(in.across) > select(0.5, 1.5, vertex) {
        discard;
    }
    let p = vec2<i32>(in.clip.xy) + vec2<i32>(region.origin);
    let ids = textureLoad(ids_tex, p, 0);
    let drawn = textureLoad(depth_tex, p, 0).x > 0.0;
    // Reverse Z: nearer is larger; the tolerance keeps edges on their own faces.
    if in.clip.z < select(0.0, scene_depth_at(ids), drawn) * (1.0 - frame.tolerances.x) {
        discard;
    }
    let kind = select(2u, 3u, vertex);
    return vec4<u32>(bitcast<u32>(seg.a.w), in.instance + 1u, kind, 0u);
}

// The faces under the window: the visibility buffer's ids, zero (nothing) where the depth is
// 0. A frame may leave the ids of uncovered pixels as the last frame wrote them
// (`VisibilityTargets`), so the viewer reads this copy, not the ids themselves. One
// triangle covering the window.
@vertex
fn vs_faces(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return screen_triangle(vi);
}

@fragment
fn fs_faces(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<u32> {
    let p = vec2<i32>(pos.xy) + vec2<i32>(region.origin);
    let drawn = textureLoad(depth_tex, p, 0).x > 0.0;
    return select(vec4<u32>(0u), textureLoad(ids_tex, p, 0), drawn);
}
