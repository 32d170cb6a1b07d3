// Declarations shared by every pass, prepended to each pass's own WGSL when its module is
// built (and by the naga test): the GPU twins of `cadre_render::layout`, and the frame's
// uniform at group 0, binding 0.

struct FrameUniform {
    view_proj: mat4x4<f32>,
    inv_proj: mat4x4<f32>,
    background: vec4<f32>,
    viewport: vec4<f32>,
    tolerances: vec4<f32>,
    modes: vec4<u32>,
    edge_colour: vec4<f32>,
    hidden_colour: vec4<f32>,
    sky_up: vec4<f32>,
    counts: vec4<u32>,
    hover: vec4<u32>,
    hover_colour: vec4<f32>,
    selection_colour: vec4<f32>,
    planes: array<vec4<f32>, MAX_SECTIONS>,
    plane_normals: array<vec4<f32>, 3>,
    forward: vec4<f32>,
    section: vec4<f32>,
    shadow: mat4x4<f32>,
    shadow_params: vec4<f32>,
}

struct Draw {
    model: mat4x4<f32>,
    normal: array<vec4<f32>, 3>,
    material: u32,
    instance: u32,
    flags: u32,
    pad: u32,
}

struct Local {
    model: mat4x4<f32>,
    normal: array<vec4<f32>, 3>,
    offset: u32,
    flags: u32,
    pad: vec2<u32>,
}

struct Call {
    record: u32,
    locals_first: u32,
    locals_count: u32,
    instances: u32,
    // A segment call's segments (first, count), each drawn once per instance; a trim call's
    // first surface and first tessellation task.
    range: vec2<u32>,
    pad: vec2<u32>,
}

struct Material {
    base_color: vec4<f32>,
    params: vec4<f32>,
}

struct Segment {
    a: vec4<f32>,
    b: vec4<f32>,
    // The outward normals of its two faces (`pack4x8snorm`), 0 for none.
    faces: vec2<u32>,
    // x: its place in its polyline (`layout::Segment::pad`); y: padding.
    pad: vec2<u32>,
}

struct Primitive {
    model: mat4x4<f32>,
    to_local: mat4x4<f32>,
    normal: array<vec4<f32>, 3>,
    size: vec4<f32>,
    linear: vec4<f32>,
    ray: array<vec4<f32>, 6>,
    depth: vec4<f32>,
    screen: vec4<f32>,
    kind: u32,
    face: u32,
    instance: u32,
    material: u32,
    planes: vec2<u32>,
    flags: u32,
    pad: u32,
}

struct PickRegion {
    origin: vec2<u32>,
    pad: vec2<u32>,
}

struct Light {
    position: vec4<f32>,
    direction: vec4<f32>,
    colour: vec4<f32>,
    params: vec4<f32>,
}

// `layout::MAX_LIGHTS` lights.
struct LightRig {
    lights: array<Light, 8>,
}

struct LinePoint {
    position: vec3<f32>,
    polyline: u32,
    travel: f32,
    colour: u32,
    pad: vec2<u32>,
}

struct LineStyle {
    colour: vec4<f32>,
    hidden_colour: vec4<f32>,
    width: f32,
    factor: f32,
    hidden_factor: f32,
    miter_limit: f32,
    pattern: u32,
    hidden_pattern: u32,
    join: u32,
    cap: u32,
    flags: u32,
    pad: array<u32, 3>,
}

struct BackdropUniform {
    inv_view_proj: mat4x4<f32>,
    top: vec4<f32>,
    bottom: vec4<f32>,
    grid_colour: vec4<f32>,
    plane: vec4<f32>,
    origin: vec4<f32>,
    axes: vec4<f32>,
    params: vec4<f32>,
    modes: vec4<u32>,
}

struct TextGlyph {
    plane: vec4<f32>,
    texels: vec4<f32>,
    label: u32,
    kind: u32,
    pad: vec2<u32>,
}

struct TextLabel {
    origin: vec4<f32>,
    x_axis: vec4<f32>,
    y_axis: vec4<f32>,
    colour: vec4<f32>,
    background: vec4<f32>,
    params: vec4<f32>,
    leader: vec4<f32>,
    flags: vec4<u32>,
}

struct TextFrame {
    to_clip: mat4x4<f32>,
    viewport: vec4<f32>,
    atlas: vec4<f32>,
}

// `TextGlyph.kind` and `TextLabel.flags[0]` (layout::TEXT_*).
const TEXT_QUAD_GLYPH: u32 = 0u;
const TEXT_QUAD_BOX: u32 = 1u;
const TEXT_QUAD_LEADER: u32 = 2u;
const TEXT_QUAD_FILL: u32 = 3u;
const TEXT_ANCHOR_SCREEN: u32 = 0u;
const TEXT_ANCHOR_BILLBOARD: u32 = 1u;
const TEXT_ANCHOR_PLANE: u32 = 2u;

struct LineFrame {
    to_clip: mat4x4<f32>,
    viewport: vec4<f32>,
    clip_lo: vec4<f32>,
    clip_hi: vec4<f32>,
    limits: vec4<f32>,
    counts: vec4<u32>,
}

// `LineStyle.join`, `.cap` and `.flags` (layout::LINE_*).
const LINE_JOIN_MITER: u32 = 0u;
const LINE_JOIN_ROUND: u32 = 1u;
const LINE_JOIN_BEVEL: u32 = 2u;
const LINE_CAP_BUTT: u32 = 0u;
const LINE_CAP_SQUARE: u32 = 1u;
const LINE_CAP_ROUND: u32 = 2u;
const LINE_WORLD_WIDTH: u32 = 1u;
const LINE_POINT_COLOURS: u32 = 2u;
const LINE_HIDDEN_SHOWN: u32 = 4u;
const LINE_HIDDEN_STYLED: u32 = 8u;
const LINE_WHOLE: u32 = 16u;

@group(0) @binding(0) var<uniform> frame: FrameUniform;

// What the visibility texel writer needs of the instance a surface point belongs to
// (instances.wgsl carries it from the draw records for meshes; the analytic primitives
// hold it themselves).
struct InstanceIds {
    material: u32,
    instance: u32,
    flags: u32,
}

// Whether the item (kind: 1 face, 2 edge, 3 vertex; instance + 1; model id) is `wanted`
// itself or, for a whole part (kind 4), belongs to its instance.
// A unit normal in the visibility buffer's normal target: its octahedral map into [0, 1]²
// (x, y; 10 bits each, about 0.1° apart), so that the third channel is free for the texel's
// coverage (`encode_normal`, texel.wgsl).
fn octahedral(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    let sign = select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    let folded = select(p, (1.0 - abs(p.yx)) * sign, n.z < 0.0);
    return 0.5 * folded + 0.5;
}

// The unit normal of an `octahedral` map.
fn from_octahedral(e: vec2<f32>) -> vec3<f32> {
    let f = 2.0 * e - 1.0;
    var n = vec3<f32>(f, 1.0 - abs(f.x) - abs(f.y));
    let t = max(-n.z, 0.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.y += select(t, -t, n.y >= 0.0);
    return normalize(n);
}

fn is_target(wanted: vec4<u32>, kind: u32, instance1: u32, id: u32) -> bool {
    if wanted.x == 0u || wanted.y != instance1 {
        return false;
    }
    return wanted.x == 4u || (wanted.x == kind && wanted.z == id);
}

// `FrameUniform.modes` lanes (layout::PROJECTION_*, FILL_*, EDGES_*): projection, face fill, edge
// mode, outlines (0 off, 1 on).
const PROJECTION_PERSPECTIVE: u32 = 0u;
const PROJECTION_ORTHOGRAPHIC: u32 = 1u;
const FILL_SHADED: u32 = 0u;
const FILL_BACKGROUND: u32 = 1u;
const FILL_NONE: u32 = 2u;
const EDGES_VISIBLE: u32 = 0u;
const EDGES_ALL: u32 = 1u;
const EDGES_HIDDEN_DASHED: u32 = 2u;

// Flags of `Draw.flags` (layout::DRAW_CLOSED, layout::DRAW_INSIDE_OUT).
const DRAW_CLOSED: u32 = 1u;
const DRAW_INSIDE_OUT: u32 = 2u;
// Set by the trim back-end's vertex shaders (not in `Draw.flags`): the placement mirrors.
const DRAW_MIRRORED: u32 = 4u;

// Material channel of a section cap's ids (view::SECTION_CAP): the flag, the plane's index in
// bits 28–29, the material in the bits below.
const SECTION_CAP: u32 = 0x80000000u;
// The section planes the frame uniform holds (`MAX_SECTIONS`).
const MAX_SECTIONS: u32 = 3u;
const CAP_MATERIAL: u32 = 0x0fffffffu;

// The distance from the eye plane (world units) of the point at the target position `pos`
// (pixels, a pixel's centre at + 0.5) of reverse-Z `depth`; the background (depth 0)
// counts as infinitely far. The crack passes compare neighbours' depths in world units.
fn eye_distance(pos: vec2<f32>, depth: f32) -> f32 {
    if depth <= 0.0 {
        return 3.0e38;
    }
    let ndc = vec2<f32>(pos.x / frame.viewport.x * 2.0 - 1.0, 1.0 - pos.y / frame.viewport.y * 2.0);
    let v = frame.inv_proj * vec4<f32>(ndc, depth, 1.0);
    return -v.z / v.w;
}

// Material bits of a crack the crack pass filled and of a real gap it closed
// (view::CRACK_FILLED, view::GAP_CLOSED), set in the inspection view only.
const CRACK_FILLED: u32 = 0x40000000u;
const GAP_CLOSED: u32 = 0x20000000u;

// Whether the ids of a pixel show a section cap.
fn is_cap(ids: vec4<u32>) -> bool {
    return ids.y != 0u && (ids.z & SECTION_CAP) != 0u;
}

// Whether the camera-relative point `p` lies in a half-space a section plane cuts away.
//
// The loop runs over every plane slot with the count tested inside: lavapipe inlines the
// uniform-buffer values that alone decide a loop's bound or an `if` and compiles the shader
// again each time that buffer is bound again, which was once per draw call (measured: 8–20
// ms of a frame). `tests/shaders.rs` checks that no loop or `if` is decided so; such
// choices are made with `select`, or joined with a per-fragment value.
fn section_cut(p: vec3<f32>) -> bool {
    var cut = false;
    for (var i = 0u; i < MAX_SECTIONS; i++) {
        let plane = frame.planes[i];
        cut = cut | ((i < frame.counts.z) & (dot(plane.xyz, p) > plane.w));
    }
    return cut;
}

// A segment of `segments` as a screen-aligned quad `half_width` pixels wide each side (plus
// `fringe`, also past the ends): corner `vi % 4` of segment `vi / 4`, placed by draw record
// `d`. A segment of zero length is a square (a B-Rep vertex).
struct LineOut {
    @builtin(position) clip: vec4<f32>,
    // Signed distance across the line and distance along it, in pixels.
    @location(0) @interpolate(linear) across: f32,
    @location(1) @interpolate(linear) along: f32,
    @location(2) @interpolate(flat) segment: u32,
    // The instance number of the segment's draw.
    @location(3) @interpolate(flat) instance: u32,
    // Camera-relative world position, for the section planes.
    @location(4) world: vec3<f32>,
}

//
// `fringe`: how far past `half_width` the quad reaches across (and past the ends): the edges
// pass needs half a pixel (its coverage is 0 at half_width + 0.5 from the line, so a wider
// quad only adds fragments it discards: a third more of them for a 1.5-pixel line), picking
// a pixel of tolerance.
fn segment_quad(seg: Segment, vi: u32, d: Draw, half_width: f32, fringe: f32) -> LineOut {
    // Corner `vi % 4`: bit 0 the end (a or b), bit 1 the side (−, +); the index buffer
    // makes the triangles (a−, b−, b+) and (a−, b+, a+).
    let corner = vi % 4u;
    let e = screen_segment(seg, d);
    let side = vec2<f32>(-e.dir.y, e.dir.x);
    let half = half_width + fringe;
    let at_b = (corner & 1u) == 1u;
    let across = select(-1.0, 1.0, (corner & 2u) != 0u);
    let c = select(e.ca, e.cb, at_b);
    let s = select(e.sa, e.sb, at_b) + side * across * half
        + e.dir * select(-1.0, 1.0, at_b) * select(fringe, half, e.len <= 1e-6);
    var out: LineOut;
    out.clip = vec4<f32>(s / (0.5 * frame.viewport.xy) * c.w, c.z, c.w);
    if e.both_behind {
        // Every corner outside the clip volume: nothing of the segment is in front.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    }
    out.across = across * half;
    // The distance along from a, the corners past the ends included.
    let reach = select(fringe, half, e.len <= 1e-6);
    out.along = select(-reach, e.len + reach, at_b);
    out.segment = vi / 4u;
    out.instance = d.instance;
    // The corners past the ends keep the end's position: the fringe is a pixel or two.
    out.world = select(e.wa.xyz, e.wb.xyz, at_b);
    return out;
}

// A segment placed by a draw record and projected: its ends in clip space and camera-relative
// world space, clipped to the near plane, and on screen in pixels from the image's centre
// (y up), with its length there and its direction ((1, 0) for a point).
struct ScreenSegment {
    ca: vec4<f32>,
    cb: vec4<f32>,
    wa: vec4<f32>,
    wb: vec4<f32>,
    sa: vec2<f32>,
    sb: vec2<f32>,
    len: f32,
    dir: vec2<f32>,
    // Nothing of the segment is in front of the near plane.
    both_behind: bool,
}

// `seg` placed by `d`, as the edges pass's quads and its compute rasterizer both see it.
fn screen_segment(seg: Segment, d: Draw) -> ScreenSegment {
    var e: ScreenSegment;
    e.wa = d.model * vec4<f32>(seg.a.xyz, 1.0);
    e.wb = d.model * vec4<f32>(seg.b.xyz, 1.0);
    e.ca = frame.view_proj * e.wa;
    e.cb = frame.view_proj * e.wb;
    // The segment clipped to the near plane (reverse Z: in front where z ≤ w) before its
    // ends are divided by w: an end behind the eye has w ≤ 0, and its division would throw
    // the quad across the screen. The rasterizer clips triangles, not the line the quad
    // was built from.
    let da = e.ca.w - e.ca.z;
    let db = e.cb.w - e.cb.z;
    let t = da / (da - db);
    let a_behind = (da < 0.0) & (db >= 0.0);
    let b_behind = (db < 0.0) & (da >= 0.0);
    e.both_behind = (da < 0.0) & (db < 0.0);
    let on_near = mix(e.ca, e.cb, t);
    let world_on_near = mix(e.wa, e.wb, t);
    e.ca = select(e.ca, on_near, a_behind);
    e.wa = select(e.wa, world_on_near, a_behind);
    e.cb = select(e.cb, on_near, b_behind);
    e.wb = select(e.wb, world_on_near, b_behind);
    let size = frame.viewport.xy;
    e.sa = (e.ca.xy / e.ca.w) * 0.5 * size;
    e.sb = (e.cb.xy / e.cb.w) * 0.5 * size;
    let dir = e.sb - e.sa;
    e.len = length(dir);
    e.dir = select(vec2<f32>(1.0, 0.0), dir / e.len, e.len > 1e-6);
    return e;
}

// Reverse-Z depth kept in the visibility buffer's ids at `p` (0 for the background).
fn scene_depth_at(ids: vec4<u32>) -> f32 {
    return select(0.0, bitcast<f32>(ids.w), ids.y != 0u);
}

// A mesh vertex as the mesh passes read it (`layout::Vertex`, `MESH_ATTRIBUTES`).
struct MeshVertex {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) face: u32,
    @location(3) uv: vec2<f32>,
}

// A mesh vertex placed by draw record `d`: clip position, camera-relative world position
// (for the section planes) and view-space normal; the mesh passes' vertex shaders share it.
struct PlacedVertex {
    clip: vec4<f32>,
    world: vec3<f32>,
    normal: vec3<f32>,
}

fn place_vertex(d: Draw, position: vec3<f32>, normal: vec3<f32>) -> PlacedVertex {
    let world = d.model * vec4<f32>(position, 1.0);
    var out: PlacedVertex;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = mat3x3<f32>(d.normal[0].xyz, d.normal[1].xyz, d.normal[2].xyz) * normal;
    return out;
}

// Corner `vi` (0..3) of one triangle covering the whole target, at depth 0: the full-screen
// passes' vertex (edges composite, pick faces).
// The share of [lo, hi] (arc length, at most a pixel long) whose bits of the 16-bit `pattern`
// (bit 0 first, `factor` ≥ 1 pixel a bit) are set: the pattern box-filtered over a pixel's
// window, which meets at most two bits. An empty window takes the bit at `lo`.
fn stipple_coverage(pattern: u32, factor: f32, lo: f32, hi: f32) -> f32 {
    if pattern == 0xffffu {
        return 1.0;
    }
    let k0 = floor(lo / factor);
    let k1 = floor(hi / factor);
    let b0 = f32((pattern >> u32(((i32(k0) % 16) + 16) % 16)) & 1u);
    let b1 = f32((pattern >> u32(((i32(k1) % 16) + 16) % 16)) & 1u);
    if (k0 == k1) || (hi <= lo) {
        return b0;
    }
    let edge = k1 * factor;
    return (b0 * (edge - lo) + b1 * (hi - edge)) / (hi - lo);
}

fn screen_triangle(vi: u32) -> vec4<f32> {
    let uv = vec2<f32>(f32((vi << 1u) & 2u), f32(vi & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Corner `vi` (0..36) of the cube [−1, 1]³ as 12 triangles (the ray casters' proxies): face `vi / 6` (axis, sign),
// corner `vi % 6` of its two triangles.
fn cube_corner(vi: u32) -> vec3<f32> {
    let face = vi / 6u;
    let quad = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vi % 6u];
    let axis = face / 2u;
    let sign = select(-1.0, 1.0, (face & 1u) == 1u);
    let a = select(-1.0, 1.0, quad == 1u || quad == 2u);
    let b = select(-1.0, 1.0, quad >= 2u);
    var p = vec3<f32>(0.0);
    p[axis] = sign;
    p[(axis + 1u) % 3u] = a;
    p[(axis + 2u) % 3u] = b;
    return p;
}
