// Exact crack fill (seed 000, Part IV, step 3b), after trim.wgsl in the crack pipeline's
// module: the trimmed faces drawn again over their whole (u, v) boxes (`TRIM_TEST` off: no
// cell culled, no fragment trimmed), and each fragment next to a pixel the crack detection
// flagged (passes/cracks/detect.wgsl) solves, by Newton's method from its own (u, v), for
// the point of its face's exact surface seen at the centre of that pixel; a solution that
// the face's exact trim keeps is a hit, pushed on the pixel's list of hits (the resolve
// pass, passes/cracks/resolve.wgsl, keeps the nearest). The layout of the crack buffers is
// `passes::cracks`' (cracks/layout.wgsl, placed before this file).

// Per pixel: 0, or 1 + the index of its crack entry.
@group(0) @binding(10) var<storage, read> crack_map: array<u32>;
// Per entry, three vec4: (pixel, pair, the pixel's own depth bits, 0), the fast fill's ids,
// its normal texel's bits.
@group(0) @binding(11) var<storage, read> crack_entries: array<vec4<u32>>;
// Counters (the first `CRACK_HEADER` words), then `CRACK_ENTRY_WORDS` atomics an entry.
@group(0) @binding(12) var<storage, read_write> crack_state: array<atomic<u32>>;
// Per hit, two vec4: ids (face, instance + 1, material, depth bits), then the octahedral
// normal (`pack2x16unorm`), u and v bits, and 1 + the next hit of the same pixel (0: none).
@group(0) @binding(13) var<storage, read_write> crack_hits: array<vec4<u32>>;


// Newton's iterations at most, and the distance to the pixel's centre, in pixels, at which
// a point is on its ray (the seed stops at ‖F‖ < ε and gives up after 4–5 steps; starting
// within a pixel or two of the answer, the tests converge in 2–3). Near a silhouette of the
// face (a cylinder seen edge-on), where the map from (u, v) to the screen folds, Newton's
// method converges only linearly: past the steps, a point within `CRACK_ACCEPT_PX` of the
// centre is taken (the surface crosses the pixel there; the grids themselves keep half a
// pixel).
const CRACK_NEWTON_STEPS: u32 = 10u;
const CRACK_NEWTON_PX: f32 = 0.01;
const CRACK_ACCEPT_PX: f32 = 0.1;

// The crack buffers' capacity in hits (`passes::cracks` sets it).
override CRACK_HIT_CAPACITY: u32 = 1024u;

struct CrackOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) local: vec2<f32>,
    @location(1) @interpolate(flat) surface: u32,
    // The draw's instance index (`instance_draw` places the solution as the vertices).
    @location(2) @interpolate(flat) instance: u32,
    // A ray-cast face's proxy (trim.wgsl's `TrimOut`).
    @location(3) ray_point: vec3<f32>,
    @location(4) @interpolate(flat) ray_eye: vec4<f32>,
}

@vertex
fn vs_crack(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> CrackOut {
    let t = trim_vertex(vertex, instance);
    var out: CrackOut;
    out.clip = t.clip;
    out.local = t.local;
    out.surface = t.surface;
    out.instance = instance;
    out.ray_point = t.ray_point;
    out.ray_eye = t.ray_eye;
    return out;
}

// Where the face-local (u, v) `local` of face `s` placed by `d` lands: target pixels (x, y),
// reverse-Z depth (z) and clip w.
fn crack_screen(s: TrimSurface, d: Draw, local: vec2<f32>) -> vec4<f32> {
    let point = face_point(s, local);
    let clip = frame.view_proj * (d.model * vec4<f32>(point.position, 1.0));
    let ndc = clip.xyz / clip.w;
    return vec4<f32>((0.5 + 0.5 * ndc.x) * frame.viewport.x, (0.5 - 0.5 * ndc.y) * frame.viewport.y, ndc.z, clip.w);
}

fn crack_word(entry: u32, word: u32) -> u32 {
    return CRACK_HEADER + entry * CRACK_ENTRY_WORDS + word;
}

// `local` a turn round (2π) in each angle of `s`'s surface (u of the surfaces of revolution
// and of the closed forms but the plane, v of the torus) where that takes it into the box.
fn crack_unwrapped(s: TrimSurface, local: vec2<f32>) -> vec2<f32> {
    let tau = 6.283185307;
    let kind = s.ids.x;
    let angles = vec2<bool>(
        (kind == SURFACE_CYLINDER) | (kind == SURFACE_CONE) | (kind == SURFACE_SPHERE)
            | (kind == SURFACE_TORUS) | (kind == SURFACE_REVOLUTION),
        kind == SURFACE_TORUS,
    );
    var out = local;
    for (var axis = 0u; axis < 2u; axis++) {
        let size = s.uv[2u + axis];
        if angles[axis] & (out[axis] < 0.0) & (out[axis] + tau <= size) {
            out[axis] += tau;
        } else if angles[axis] & (out[axis] > size) & (out[axis] - tau >= 0.0) {
            out[axis] -= tau;
        }
    }
    return out;
}

@fragment
fn fs_crack(in: CrackOut) {
    // The (u, v) change over a pixel step, before any early return (derivatives need every
    // lane): the miss distance of a solution off the face.
    // A ray-cast face's fragment starts from the (u, v) of its own ray's nearest hit (its
    // proxy's parameters are none).
    let face = surfaces[in.surface];
    var start = in.local;
    if is_ray_cast(face) {
        let ray = frame_ray(in.ray_point, in.ray_eye);
        start = cast_face(face, ray.o, ray.d).local[0];
    }
    var jx = dpdx(start);
    var jy = dpdy(start);
    if is_ray_cast(face) {
        jx = short_way(face, jx);
        jy = short_way(face, jy);
    }
    let width = u32(frame.viewport.x);
    let height = u32(frame.viewport.y);
    let p = vec2<i32>(floor(in.clip.xy));
    let s = surfaces[in.surface];
    // The mailbox key of this face of this instance (never 0, the entries' first value).
    let key = ((in.surface * 2654435761u) ^ (in.instance * 40503u)) | 1u;
    for (var k = 0u; k < 9u; k++) {
        let q = p + vec2<i32>(i32(k % 3u) - 1, i32(k / 3u) - 1);
        let inside = (q.x >= 0) & (q.y >= 0) & (q.x < i32(width)) & (q.y < i32(height));
        if !inside {
            continue;
        }
        let at = crack_map[u32(q.y) * width + u32(q.x)];
        if at == 0u {
            continue;
        }
        let entry = at - 1u;
        // Solved already for this pixel by another fragment of the same face: the seed's
        // mailbox, with a slot for each of the first few faces about the pixel, so that a
        // face's miss distance counts once (past them a face may be solved again).
        var solved = false;
        for (var slot = 0u; slot < CRACK_MAILBOX_SLOTS; slot++) {
            let was = atomicCompareExchangeWeak(&crack_state[crack_word(entry, slot)], 0u, key);
            if was.exchanged {
                break;
            }
            if was.old_value == key {
                solved = true;
                break;
            }
        }
        if solved {
            continue;
        }
        atomicAdd(&crack_state[CRACK_COUNT_SOLVES], 1u);
        let d = instance_draw(in.instance);
        let goal = vec2<f32>(q) + 0.5;
        // h: a thousandth of the box, for the Jacobian's differences.
        let h = max(abs(s.uv.zw) * 1e-3, vec2<f32>(1e-6));
        var local = start;
        var at_goal = false;
        var screen = crack_screen(s, d, local);
        for (var step = 0u; step < CRACK_NEWTON_STEPS; step++) {
            let f = screen.xy - goal;
            if length(f) < CRACK_NEWTON_PX {
                at_goal = true;
                break;
            }
            let su = (crack_screen(s, d, local + vec2<f32>(h.x, 0.0)).xy - screen.xy) / h.x;
            let sv = (crack_screen(s, d, local + vec2<f32>(0.0, h.y)).xy - screen.xy) / h.y;
            let det = su.x * sv.y - su.y * sv.x;
            if abs(det) < 1e-20 {
                break;
            }
            var delta = vec2<f32>(sv.y * f.x - sv.x * f.y, -su.y * f.x + su.x * f.y) / det;
            // Steps held within a quarter of the box (by halves: one past it is near a fold,
            // where the Jacobian all but vanishes, and would leave for a far part of the
            // surface).
            let limit = 0.25 * abs(s.uv.zw) + h;
            for (var k = 0u; (k < 8u) & any(abs(delta) > limit); k++) {
                delta *= 0.5;
            }
            local -= delta;
            screen = crack_screen(s, d, local);
        }
        if !at_goal {
            at_goal = length(screen.xy - goal) < CRACK_ACCEPT_PX;
        }
        if !at_goal {
            // Unsolved from this fragment: the face's mailbox slot freed, so that another
            // of its fragments about the pixel (a nearer start) tries.
            for (var slot = 0u; slot < CRACK_MAILBOX_SLOTS; slot++) {
                atomicCompareExchangeWeak(&crack_state[crack_word(entry, slot)], key, 0u);
            }
            continue;
        }
        if screen.w <= 0.0 || screen.z <= 0.0 || screen.z > 1.0 {
            continue;
        }
        // An angle's solution a turn away from the box (across a closed face's seam, where
        // a cylinder seen from the side has its silhouette) taken back into it.
        local = crack_unwrapped(s, local);
        // A solution past the tree's box (whose side is often the trim's own edge) is off
        // the face by its distance to the box, plus the box point's to the trim.
        let kept = clamp(local, vec2<f32>(0.0), s.uv.zw);
        let in_box = all(kept == local);
        let point = face_point(s, kept);
        let placed = place_vertex(d, point.position, point.normal * s.axis_y.w);
        if SECTIONS && section_cut(placed.world) {
            continue;
        }
        if !in_box || (TRIM_TEST_CRACKS && !trim_classify(s.ids.z, kept)) {
            // Off the face: how far, in object space, for the gaps (a real gap narrower
            // than the user's tolerance is closed and shown as one).
            var world = 0.0;
            if !in_box || TRIM_TEST_CRACKS {
                let pixels = trim_edge_pixels(s.ids.z, kept, jx, jy);
                let across = face_point(s, kept + jx).position - point.position;
                world = pixels * length((d.model * vec4<f32>(across, 0.0)).xyz);
            }
            if !in_box {
                let off = face_point(s, local).position - point.position;
                world += length((d.model * vec4<f32>(off, 0.0)).xyz);
            }
            if world < 1e29 {
                // The two least misses, a face each: the gap's width where the ray passes
                // between two faces (the one displaced from the least goes on to the next).
                let bits = bitcast<u32>(world);
                let least = atomicMin(&crack_state[crack_word(entry, CRACK_WORD_MISS)], bits);
                atomicMin(&crack_state[crack_word(entry, CRACK_WORD_MISS_NEXT)], max(least, bits));
            }
            continue;
        }
        let hit = atomicAdd(&crack_state[CRACK_COUNT_HITS], 1u);
        if hit >= CRACK_HIT_CAPACITY {
            continue;
        }
        let n = normalize(placed.normal);
        let next = atomicExchange(&crack_state[crack_word(entry, CRACK_WORD_HEAD)], hit + 1u);
        crack_hits[2u * hit] = vec4<u32>(s.ids.y, d.instance + 1u, d.material, bitcast<u32>(screen.z));
        let uv = s.uv.xy + kept;
        crack_hits[2u * hit + 1u] = vec4<u32>(pack2x16unorm(octahedral(n)), bitcast<u32>(uv.x), bitcast<u32>(uv.y), next);
    }
}

// The trim test of the solutions (off only for the tests' negative control: every solution
// on the untrimmed surface kept).
override TRIM_TEST_CRACKS: bool = true;
