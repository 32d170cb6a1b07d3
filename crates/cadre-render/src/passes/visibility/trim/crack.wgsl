// Exact crack fill (seed 000, Part IV, step 3b), after trim.wgsl in the crack pipeline's
// module: the trimmed faces drawn again over their whole (u, v) boxes (`TRIM_TEST` off: no
// cell culled, no fragment trimmed), and each fragment next to a pixel the crack detection
// flagged (passes/cracks/detect.wgsl) solves, by Newton's method from its own (u, v), for
// the point of its face's exact surface seen at the centre of that pixel; a solution that
// the face's exact trim keeps is a hit, pushed on the pixel's list of hits (the resolve
// pass, passes/cracks/resolve.wgsl, keeps the nearest). Before it, every flagged pixel is
// solved in compute from its seeds (`cs_seeded`, below), and the pixels flagged beside a
// silhouette only so.
// The layout of the crack buffers is `passes::cracks`' (cracks/layout.wgsl, placed before
// this file).

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
// The frame's trim draws, for the seeded solves' match (`FrameTrim`).
@group(0) @binding(14) var<storage, read> seed_calls: array<TrimCall>;
// Per entry, its seeds (cracks/layout.wgsl's `CRACK_SEED_VEC4S`), which the match completes
// and the solves mark settled.
@group(0) @binding(15) var<storage, read_write> crack_seeds: array<vec4<u32>>;


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

// The crack buffers' capacity in hits and in entries (`passes::cracks` sets them).
override CRACK_HIT_CAPACITY: u32 = 1024u;
override CRACK_ENTRY_CAPACITY: u32 = 1024u;

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
        let d = instance_draw(in.instance);
        if !crack_solve(entry, q, s, d, start, mat2x2<f32>(jx, jy)).converged {
            // Unsolved from this fragment: the face's mailbox slot freed, so that another
            // of its fragments about the pixel (a nearer start) tries.
            for (var slot = 0u; slot < CRACK_MAILBOX_SLOTS; slot++) {
                atomicCompareExchangeWeak(&crack_state[crack_word(entry, slot)], key, 0u);
            }
        }
    }
}

// What a solve found: whether Newton's method reached the pixel's ray, and the reverse-Z
// depth of the hit it pushed (0: none, the solution off the face or cut away).
struct CrackSolve {
    converged: bool,
    depth: f32,
}

// Newton's method on face `s` placed by `d`, from the face-local (u, v) `start`, for the
// point seen at the centre of pixel `q` (crack `entry`'s); a solution the face's exact trim
// keeps is pushed on the entry's hits, one off the face records how far off it is (the
// gaps; `footprint`: the (u, v) change over a pixel step in x and y, a fragment's
// derivatives; zeros record no miss: the seeded solves', as the raster fill solves the
// same face again where they do not close the pixel, and a face's miss counts once).
fn crack_solve(entry: u32, q: vec2<i32>, s: TrimSurface, d: Draw, start: vec2<f32>, footprint: mat2x2<f32>) -> CrackSolve {
    atomicAdd(&crack_state[CRACK_COUNT_SOLVES], 1u);
    var out: CrackSolve;
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
        return out;
    }
    out.converged = true;
    if screen.w <= 0.0 || screen.z <= 0.0 || screen.z > 1.0 {
        return out;
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
        return out;
    }
    if !in_box || (TRIM_TEST_CRACKS && !trim_classify(s.ids.z, kept)) {
        // Off the face: how far, in object space, for the gaps (a real gap narrower
        // than the user's tolerance is closed and shown as one).
        let jx = footprint[0];
        let jy = footprint[1];
        let known = any(jx != vec2<f32>(0.0)) | any(jy != vec2<f32>(0.0));
        var world = 0.0;
        if known && (!in_box || TRIM_TEST_CRACKS) {
            let pixels = trim_edge_pixels(s.ids.z, kept, jx, jy);
            let across = face_point(s, kept + jx).position - point.position;
            world = pixels * length((d.model * vec4<f32>(across, 0.0)).xyz);
        }
        if known && !in_box {
            let off = face_point(s, local).position - point.position;
            world += length((d.model * vec4<f32>(off, 0.0)).xyz);
        }
        if known && (world < 1e29) {
            // The two least misses, a face each: the gap's width where the ray passes
            // between two faces (the one displaced from the least goes on to the next).
            let bits = bitcast<u32>(world);
            let least = atomicMin(&crack_state[crack_word(entry, CRACK_WORD_MISS)], bits);
            atomicMin(&crack_state[crack_word(entry, CRACK_WORD_MISS_NEXT)], max(least, bits));
        }
        return out;
    }
    let hit = atomicAdd(&crack_state[CRACK_COUNT_HITS], 1u);
    if hit >= CRACK_HIT_CAPACITY {
        return out;
    }
    let n = normalize(placed.normal);
    let next = atomicExchange(&crack_state[crack_word(entry, CRACK_WORD_HEAD)], hit + 1u);
    crack_hits[2u * hit] = vec4<u32>(s.ids.y, d.instance + 1u, d.material, bitcast<u32>(screen.z));
    let uv = s.uv.xy + kept;
    crack_hits[2u * hit + 1u] = vec4<u32>(pack2x16unorm(octahedral(n)), bitcast<u32>(uv.x), bitcast<u32>(uv.y), next);
    out.depth = screen.z;
    return out;
}

// Instances of a call a seeded solve's match walks for its seed's (past them it is left
// unsolved: llvmpipe ends a shader's loops after 65,535 iterations in all).
const CRACK_SEED_WALK: u32 = 4096u;
// Workgroup rows a dispatch has at most (wgpu's limit on each dimension): the draw is the
// row plus this times the layer.
const CRACK_SEED_ROWS: u32 = 65535u;

// The seeded solves (seed 000's exact fill, started from the visibility buffer): each crack
// pixel's seeds — the texels of its pair's two neighbours, or of the grazing neighbour
// beside a silhouette (detect.wgsl) — solved on their own faces by Newton's method from
// their (u, v) for the point seen at the pixel's centre (`crack_solve`). Two passes:
// `cs_seed_match`, a workgroup row for each trim draw (`seed_calls`) and a column for each
// 64 entries, finds a seed's face among the draw's records by binary search (they are in
// ascending face id) and its instance by walking the draw's, and writes their indices into
// the seed; then `cs_seeded`, one dispatch over the entries, solves (a miss off the face
// left to the raster fill's solves), and marks the pixel settled where a hit closes it: the raster
// fill then draws no face for it (`vs_mask`, `cs_crack_faces`). It is left the pixels no
// seed closed — those whose seeds failed, and those the seeds' faces do not cover: with
// every seed that reached the pixel's ray taken as settling it, the bore fixture at 7 grid
// lines kept 1 of its 14 crack pixels (`cracks.rs`), which the raster fill closes. Matching first
// keeps a CPU rasterizer's lanes together: solved draw by draw, a batch of lanes ran
// Newton's method once for each draw its pixels' faces belonged to (PRO10363 at 1080p on
// lavapipe: 345 ms for 561 solves beside silhouettes). The raster fill costs a CPU
// rasterizer the vertex stage of every face about a pixel (809 ms for 565 pixels beside
// silhouettes).
@compute @workgroup_size(64)
fn cs_seed_match(@builtin(global_invocation_id) id: vec3<u32>) {
    let entry = id.x;
    let draw = id.y + CRACK_SEED_ROWS * id.z;
    let kept = min(atomicLoad(&crack_state[CRACK_COUNT_ENTRIES]), CRACK_ENTRY_CAPACITY);
    if (entry >= kept) || (draw >= arrayLength(&seed_calls)) {
        return;
    }
    let c = seed_calls[draw];
    let count = max(c.locals_count, 1u);
    let walked = min(c.instances, CRACK_SEED_WALK);
    for (var k = 0u; k < CRACK_SEEDS; k++) {
        let at = CRACK_SEED_VEC4S * entry + 2u * k;
        let seed = crack_seeds[at];
        if seed.y == 0u {
            continue;
        }
        var lo = 0u;
        var hi = c.faces;
        for (var b = 0u; (b < 32u) & (lo < hi); b++) {
            let mid = (lo + hi) / 2u;
            if surfaces[c.first_surface + mid].ids.y < seed.x {
                lo = mid + 1u;
            } else {
                hi = mid;
            }
        }
        if (lo >= c.faces) || (surfaces[c.first_surface + lo].ids.y != seed.x) {
            continue;
        }
        for (var i = 0u; i < walked; i++) {
            let parts = vec2<u32>(c.record + i / count, c.locals_first + i % count);
            if draws[parts.x].instance + locals[parts.y].offset + 1u == seed.y {
                crack_seeds[at + 1u] = vec4<u32>(c.first_surface + lo + 1u, parts, crack_seeds[at + 1u].w);
                break;
            }
        }
    }
}

@compute @workgroup_size(64)
fn cs_seeded(@builtin(global_invocation_id) id: vec3<u32>) {
    let entry = id.x;
    let kept = min(atomicLoad(&crack_state[CRACK_COUNT_ENTRIES]), CRACK_ENTRY_CAPACITY);
    if entry >= kept {
        return;
    }
    let head = crack_entries[3u * entry];
    let width = u32(frame.viewport.x);
    let q = vec2<i32>(i32(head.x % width), i32(head.x / width));
    let centre = vec2<f32>(q) + 0.5;
    let own = eye_distance(centre, bitcast<f32>(head.z));
    var closed = false;
    for (var k = 0u; k < CRACK_SEEDS; k++) {
        let at = CRACK_SEED_VEC4S * entry + 2u * k;
        let seed = crack_seeds[at];
        let found = crack_seeds[at + 1u];
        if seed.y == 0u {
            continue;
        }
        if found.x == 0u {
            continue;
        }
        let s = surfaces[found.x - 1u];
        let uv = bitcast<vec2<f32>>(seed.zw);
        let solve = crack_solve(entry, q, s, parts_draw(found.yz), uv - s.uv.xy, mat2x2<f32>(vec2<f32>(0.0), vec2<f32>(0.0)));
        closed = closed | ((solve.depth > 0.0) & (eye_distance(centre, solve.depth) + frame.tolerances.z <= own));
    }
    if closed {
        atomicAdd(&crack_state[CRACK_COUNT_SETTLED], 1u);
        let at = CRACK_SEED_VEC4S * entry + 1u;
        crack_seeds[at] = vec4<u32>(crack_seeds[at].xyz, 1u);
    }
}

// The trim test of the solutions (off only for the tests' negative control: every solution
// on the untrimmed surface kept).
override TRIM_TEST_CRACKS: bool = true;
