// What the edges pass's quads and its compute rasterizer share (both prepend it): bind group
// 0's segments, visibility depth and selection, which segments are dropped behind their own
// solid, and which are highlighted.

@group(0) @binding(1) var<storage, read> segments: array<Segment>;
// The visibility depth, 0 where nothing is (4 bytes a fragment, where the ids are 16).
@group(0) @binding(2) var depth_tex: texture_2d<f32>;
@group(0) @binding(3) var<storage, read> selection: array<vec4<u32>>;

// Segments hidden behind their own solid are dropped (`behind_its_solid`); unset only by the
// tests' reference drawing.
override CULL_BEHIND: bool = true;
// How far past edge-on (the cosine between a face's normal and the view direction) both
// faces along a segment must turn away for it to be dropped: a hidden edge just behind a
// curved silhouette still shows part of its width past the silhouette (at 0.05, 8 of 30,000
// pixels of a pin at 200×150 changed; at 0.25 none). Set otherwise only by the tests'
// negative control.
override BACK_MARGIN: f32 = 0.25;

// Whether the segment lies on the far side of its own closed solid, hidden by it: both faces
// along it turn away from the eye (`Segment::faces`; `edge_faces.rs`). Only where hidden
// edges are not drawn, and without section planes (a cut opens the solid).
fn behind_its_solid(seg: Segment, d: Draw) -> bool {
    let closed = (d.flags & DRAW_CLOSED) != 0u;
    let two_faces = (seg.faces.x != 0u) & (seg.faces.y != 0u);
    if !CULL_BEHIND | !closed | !two_faces | SECTIONS | (frame.modes.z != EDGES_VISIBLE) {
        return false;
    }
    // The view direction at the segment's middle, in view space (the eye at the origin),
    // chosen by `select`: an `if` on a uniform value alone is one lavapipe inlines and
    // recompiles the shader for at every bind (see `section_cut`, common.wgsl).
    let middle = d.model * vec4<f32>(0.5 * (seg.a.xyz + seg.b.xyz), 1.0);
    let view = frame.inv_proj * (frame.view_proj * middle);
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let v = normalize(select(-view.xyz / view.w, vec3<f32>(0.0, 0.0, 1.0), ortho));
    let to_view = mat3x3<f32>(d.normal[0].xyz, d.normal[1].xyz, d.normal[2].xyz);
    let n1 = normalize(to_view * unpack4x8snorm(seg.faces.x).xyz);
    let n2 = normalize(to_view * unpack4x8snorm(seg.faces.y).xyz);
    return (dot(n1, v) < -BACK_MARGIN) & (dot(n2, v) < -BACK_MARGIN);
}

// The highlight colour of the segment's edge: selection over hover, alpha 0 for none.
fn highlight_of(seg: Segment, instance: u32) -> vec4<f32> {
    let id = bitcast<u32>(seg.a.w);
    if bitcast<u32>(seg.b.w) != 1u {
        return vec4<f32>(0.0);
    }
    // Bounded by the buffer too: a loop bounded by a uniform value alone is recompiled by
    // lavapipe whenever the uniforms are bound again (see `section_cut`, common.wgsl).
    for (var i = 0u; i < min(frame.counts.y, arrayLength(&selection)); i++) {
        if is_target(selection[i], 2u, instance + 1u, id) {
            return frame.selection_colour;
        }
    }
    if is_target(frame.hover, 2u, instance + 1u, id) {
        return frame.hover_colour;
    }
    return vec4<f32>(0.0);
}
