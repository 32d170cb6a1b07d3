// Lines pass: each segment of the set is one quad (a strip of four corners from the vertex
// index, instanced over the segments: a third fewer vertices than two triangles), clipped at the near plane, at the clip box and at the travel
// shown, and widened in screen space past its ends by what its cap or its join needs. The
// fragment shader finds the pixel's place in the segment's frame and covers it:
// - inside the segment (0 ≤ t ≤ length): the box-filtered coverage across the line;
// - before its start or past its end at a polyline's end (or a clipped end): the cap;
// - past its end at a joint: the join, drawn by this segment only, in the wedge between the
//   two segments' end perpendiculars, which opens to the outer side of the turn (miter: the
//   outer edges' continuations; bevel: the cut through the outer corners; round: a disc).
// Segments meet on hard boundaries (t = 0, t = length, the wedge), so no pixel takes two
// fringes' coverage there. The stipple is the box-filtered pattern at s = arc[i] + t, the
// screen arc length the scan wrote (the join takes the joint's).

@group(0) @binding(3) var<storage, read> arc: array<f32>;
@group(0) @binding(4) var<storage, read> polyline_styles: array<u32>;
@group(0) @binding(5) var<storage, read> styles: array<LineStyle>;
@group(0) @binding(6) var depth_tex: texture_2d<f32>;

// Where a segment's end stops: inside a polyline (the next segment's join or this one's
// start), a polyline end with the style's cap, or a clipped end (butt).
const END_JOINT: u32 = 0u;
const END_CAP: u32 = 1u;
const END_CUT: u32 = 2u;

struct LineVary {
    @builtin(position) position: vec4<f32>,
    // The segment's start on screen (pixels) and its unit direction.
    @location(0) @interpolate(flat) start: vec2<f32>,
    @location(1) @interpolate(flat) dir: vec2<f32>,
    // The next segment's unit direction on screen, for the join.
    @location(2) @interpolate(flat) next: vec2<f32>,
    // The segment's end on screen: the next segment's start, bit for bit, so that the two
    // tell which of them a pixel on the joint's perpendicular belongs to alike.
    @location(7) @interpolate(flat) end: vec2<f32>,
    // Length (pixels), half width (pixels), arc length at the start, miter limit.
    @location(3) @interpolate(flat) geometry: vec4<f32>,
    // Reverse-Z depth at the start and at the end.
    @location(4) @interpolate(flat) depth: vec2<f32>,
    @location(5) @interpolate(flat) colour: vec4<f32>,
    // Style index, start's end kind, end's end kind, the style's cap | join << 8.
    @location(6) @interpolate(flat) kinds: vec4<u32>,
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

// The parameter range of segment p0–p1 (set-local) inside the clip box (Liang–Barsky),
// within `range`.
fn box_range(p0: vec3<f32>, p1: vec3<f32>, range: vec2<f32>) -> vec2<f32> {
    var r = range;
    let d = p1 - p0;
    for (var axis = 0u; axis < 3u; axis++) {
        let lo = lf.clip_lo[axis];
        let hi = lf.clip_hi[axis];
        if abs(d[axis]) < 1e-30 {
            if (p0[axis] < lo) | (p0[axis] > hi) {
                r = vec2<f32>(1.0, 0.0);
            }
        } else {
            let t0 = (lo - p0[axis]) / d[axis];
            let t1 = (hi - p0[axis]) / d[axis];
            r = vec2<f32>(max(r.x, min(t0, t1)), min(r.y, max(t0, t1)));
        }
    }
    // Chosen by `select`, not an `if` on the uniform alone (see `section_cut`, common.wgsl).
    return select(r, range, lf.clip_lo.w == 0.0);
}

// Every corner outside the clip volume: the quad is dropped before rasterization.
fn dropped() -> LineVary {
    var out: LineVary;
    out.position = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    return out;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) i: u32) -> LineVary {
    let a = points[i];
    let b = points[i + 1u];
    if a.polyline != b.polyline {
        return dropped();
    }
    let style_index = polyline_styles[a.polyline];
    let style = styles[style_index];
    // The part shown: up to the travel, inside the box, in front of the near plane.
    var range = vec2<f32>(0.0, 1.0);
    let whole = (style.flags & LINE_WHOLE) != 0u;
    if (b.travel > lf.limits.x) & !whole {
        range.y = select(0.0, (lf.limits.x - a.travel) / (b.travel - a.travel), b.travel > a.travel);
    }
    range = select(box_range(a.position, b.position, range), range, whole);
    let ca = lf.to_clip * vec4<f32>(a.position, 1.0);
    let cb = lf.to_clip * vec4<f32>(b.position, 1.0);
    let near = near_range(ca, cb);
    let shown = vec2<f32>(max(range.x, near.x), min(range.y, near.y));
    if shown.x >= shown.y {
        return dropped();
    }
    let c0 = mix(ca, cb, shown.x);
    let c1 = mix(ca, cb, shown.y);
    let p0 = to_pixels(c0);
    let p1 = to_pixels(c1);
    let along = p1 - p0;
    let length = length(along);
    // How each end stops.
    var start_kind = END_JOINT;
    if shown.x > 0.0 {
        start_kind = END_CUT;
    } else if starts_polyline(i) {
        start_kind = END_CAP;
    }
    var end_kind = END_JOINT;
    var next = vec2<f32>(0.0);
    let last = (i + 2u >= lf.counts.x) || starts_polyline(i + 2u);
    if shown.y < 1.0 {
        end_kind = END_CUT;
    } else if last {
        end_kind = END_CAP;
    } else {
        // The next segment as far as it is in front of the near plane.
        let cn = lf.to_clip * vec4<f32>(points[i + 2u].position, 1.0);
        let r = near_range(cb, cn);
        if r.x >= r.y {
            end_kind = END_CUT;
        } else {
            let towards = to_pixels(mix(cb, cn, r.y)) - p1;
            if dot(towards, towards) > 1e-12 {
                next = normalize(towards);
            }
        }
    }
    var dir = vec2<f32>(1.0, 0.0);
    if length > 1e-6 {
        dir = along / length;
    } else if dot(next, next) > 0.0 {
        dir = next;
    }
    // Width, target pixels: a model-space width at the segment's middle, one pixel at least.
    let scale = lf.viewport.z;
    var width = clamp(style.width, 0.25, 64.0) * scale;
    if (style.flags & LINE_WORLD_WIDTH) != 0u {
        let w = max(0.5 * (c0.w + c1.w), 1e-30);
        width = max(style.width * lf.limits.y / w, scale);
    }
    let half = 0.5 * width;
    let limit = max(style.miter_limit, 1.0);
    // How far the quad reaches past each end.
    var before = 0.0;
    if start_kind != END_JOINT {
        before = select(1.0, half + 1.0, style.cap != LINE_CAP_BUTT);
    }
    var after = select(1.0, half + 1.0, style.cap != LINE_CAP_BUTT);
    if end_kind == END_JOINT {
        after = select(half + 1.0, half * limit + 1.0, style.join == LINE_JOIN_MITER);
    } else if end_kind == END_CUT {
        after = 1.0;
    }
    if start_kind == END_CUT {
        before = 1.0;
    }
    // A triangle strip of four corners: bit 0 the end (start, end), bit 1 the side.
    let corner = vi % 4u;
    let u = f32(corner & 1u);
    let v = select(-1.0, 1.0, (corner & 2u) != 0u);
    let normal = vec2<f32>(-dir.y, dir.x);
    let pixel = p0 + dir * mix(-before, length + after, u) + normal * v * (half + 1.0);
    var out: LineVary;
    out.position = vec4<f32>(
        pixel.x / lf.viewport.x * 2.0 - 1.0,
        1.0 - pixel.y / lf.viewport.y * 2.0,
        0.5,
        1.0,
    );
    out.start = p0;
    out.end = p1;
    out.dir = dir;
    out.next = next;
    // The arc length at the drawn start: the scan's at the near-clipped start, plus what
    // the box or the travel cut off.
    let near_start = to_pixels(mix(ca, cb, near.x));
    out.geometry = vec4<f32>(length, half, arc[i] + distance(near_start, p0), limit);
    out.depth = vec2<f32>(c0.z / c0.w, c1.z / c1.w);
    var colour = style.colour;
    if (style.flags & LINE_POINT_COLOURS) != 0u {
        let c = unpack4x8unorm(a.colour);
        colour = vec4<f32>(srgb_to_linear(c.rgb), c.a);
    }
    out.colour = colour;
    out.kinds = vec4<u32>(style_index, start_kind, end_kind, style.cap | (style.join << 8u));
    return out;
}

// The box-filtered coverage of a pixel at distance `d` from the centre line of a line of
// half width `half`: the overlap of [d − ½, d + ½] with [−half, half].
fn across_coverage(d: f32, half: f32) -> f32 {
    let a = abs(d);
    return clamp(min(half, a + 0.5) - max(-half, a - 0.5), 0.0, 1.0);
}

// The coverage past an end (`q`: the pixel from the end point, `t` along the direction away
// from the segment) by a cap of `cap` (a cut end is butt).
fn cap_coverage(kind: u32, cap: u32, q: vec2<f32>, t: f32, across: f32, half: f32) -> f32 {
    if (kind == END_CAP) && (cap == LINE_CAP_ROUND) {
        return clamp(half + 0.5 - length(q), 0.0, 1.0);
    }
    var reach = 0.0;
    if (kind == END_CAP) && (cap == LINE_CAP_SQUARE) {
        reach = half;
    }
    return across_coverage(across, half) * clamp(reach + 0.5 - t, 0.0, 1.0);
}

// The coverage of the join past the segment's end: `q` is the pixel from the joint, `d` and
// `n` the two segments' directions. Outside the wedge between their end perpendiculars: 0
// (the next segment draws it).
fn join_coverage(q: vec2<f32>, d: vec2<f32>, n: vec2<f32>, join: u32, half: f32, limit: f32) -> f32 {
    if (dot(n, n) == 0.0) || (dot(q, n) >= 0.0) {
        return 0.0;
    }
    let turn = d.x * n.y - d.y * n.x;
    let side = select(1.0, -1.0, turn > 0.0);
    let o1 = side * vec2<f32>(-d.y, d.x);
    let o2 = side * vec2<f32>(-n.y, n.x);
    // cos of half the angle between the outer normals.
    let c = sqrt(max(0.5 * (1.0 + dot(d, n)), 0.0));
    var sdf = length(q) - half;
    if (join == LINE_JOIN_MITER) && (c * limit >= 1.0) {
        sdf = max(dot(q, o1), dot(q, o2)) - half;
    } else if join != LINE_JOIN_ROUND {
        if c < 1e-4 {
            return 0.0;
        }
        sdf = dot(q, normalize(o1 + o2)) - half * c;
    }
    return clamp(0.5 - sdf, 0.0, 1.0);
}

@fragment
fn fs_main(in: LineVary) -> @location(0) vec4<f32> {
    let p = in.position.xy - in.start;
    let length = in.geometry.x;
    let half = in.geometry.y;
    let t = dot(p, in.dir);
    // Past the end: the same test as the next segment's `t < 0`, negated (half-open).
    let past_end = dot(in.position.xy - in.end, in.dir) >= 0.0;
    let across = dot(p, vec2<f32>(-in.dir.y, in.dir.x));
    let cap = in.kinds.w & 0xffu;
    let join = in.kinds.w >> 8u;
    var coverage = 0.0;
    if t < 0.0 {
        if in.kinds.y == END_JOINT {
            discard;
        }
        coverage = cap_coverage(in.kinds.y, cap, p, -t, across, half);
    } else if !past_end {
        coverage = across_coverage(across, half);
        // A butt or cut start's fringe reaches into the segment too.
        if (in.kinds.y != END_JOINT) && ((cap == LINE_CAP_BUTT) || (in.kinds.y == END_CUT)) {
            coverage *= clamp(t + 0.5, 0.0, 1.0);
        }
        if (in.kinds.z != END_JOINT) && ((cap == LINE_CAP_BUTT) || (in.kinds.z == END_CUT)) {
            coverage *= clamp(length - t + 0.5, 0.0, 1.0);
        }
    } else {
        let q = in.position.xy - in.end;
        if in.kinds.z == END_JOINT {
            coverage = join_coverage(q, in.dir, in.next, join, half, in.geometry.w);
        } else {
            coverage = cap_coverage(in.kinds.z, cap, q, t - length, across, half);
        }
    }
    if coverage <= 0.0 {
        discard;
    }
    // Hidden behind the visibility buffer's surfaces (reverse Z: nearer is larger)?
    let depth = mix(in.depth.x, in.depth.y, clamp(t / max(length, 1e-6), 0.0, 1.0));
    let scene = textureLoad(depth_tex, vec2<i32>(in.position.xy), 0).x;
    let hidden = depth < scene * (1.0 - frame.tolerances.x);
    let style = styles[in.kinds.x];
    var colour = in.colour;
    var pattern = style.pattern;
    var factor = style.factor;
    if hidden {
        if (style.flags & LINE_HIDDEN_STYLED) != 0u {
            colour = style.hidden_colour;
            pattern = style.hidden_pattern;
            factor = style.hidden_factor;
        } else if (style.flags & LINE_HIDDEN_SHOWN) == 0u {
            discard;
        }
    }
    // The pixel's window along the line, kept inside it at a polyline's ends: there the
    // cap's coverage is the part of the pixel the line reaches, and the pattern is averaged
    // over that part alone.
    let s = in.geometry.z + t;
    var lo = s - 0.5;
    var hi = s + 0.5;
    if in.kinds.y != END_JOINT {
        lo = max(lo, in.geometry.z);
        hi = max(hi, lo);
    }
    if in.kinds.z != END_JOINT {
        hi = min(hi, in.geometry.z + length);
        lo = min(lo, hi);
    }
    coverage *= stipple_coverage(pattern, max(factor * lf.viewport.z, 1.0), lo, hi);
    if coverage <= 0.0 {
        discard;
    }
    return vec4<f32>(colour.rgb, colour.a * coverage);
}
