// Crack detection (seed 000, Part IV, step 2), a pass over the visibility buffer
// after every back-end has drawn: pixel p is a crack when, for one of the four pairs of
// opposite neighbours (left–right, up–down, both diagonals), both neighbours show a face
// nearer than p by at least `frame.tolerances.z` (d_min, world units) and neither shows p's
// face (p's face of the same instance): a gap between two faces tessellated apart, through
// which the background or a face behind shows. The rule keeps silhouettes out: past a
// silhouette one neighbour shows p's face, or nothing.
//
// Beside the seed's rule, a second one for the silhouettes of tessellated faces: a grid held
// within half a pixel of its curved surface ends short of the surface's true silhouette, so
// a pixel there shows the face behind. Pixel p is flagged (`CRACK_PAIR_SILHOUETTE`) when it
// shows a face, one of its four edge neighbours shows another face nearer by d_min, and that
// face is seen there at a grazing angle (its normal more than 45° from the view ray: near
// its silhouette). It is asked for (`CrackOptions::silhouettes`, `frame.forward.w` = 1): its
// cost follows the silhouettes, not the cracks. Only the exact fill acts on these: the surface's exact point at p's
// centre, where the exact surface covers it, is nearer and taken; otherwise p is left as
// drawn (the true silhouette passes before it) and not counted as open. Their seed is the
// grazing neighbour's texel (ids and (u, v)), from which the exact fill solves that face
// alone (`cs_seeded`, visibility/trim/crack.wgsl) instead of drawing faces again. Each
// crack between faces carries its pair's two neighbours as seeds the same way.
//
// Two full-screen passes: the flags
// (`fs_flag`, the crack mask's depth), then at the flagged pixels the entries (`fs_detect`:
// its pixel, the pair, and the fast fill — the face most of its nearer neighbours show, at
// their mean depth) and the pixel's entry number in the map; the exact fill and the resolve
// pass read them.

@group(0) @binding(1) var depth_tex: texture_2d<f32>;
@group(0) @binding(2) var ids_tex: texture_2d<u32>;
@group(0) @binding(3) var normal_tex: texture_2d<f32>;
// Per pixel: 0, or 1 + its entry's index (cleared each frame, the cracks written here).
@group(0) @binding(4) var<storage, read_write> crack_map: array<u32>;
// Per entry, three vec4: (pixel, pair, the pixel's own depth bits, 0), the fast fill's ids,
// its normal texel's bits.
@group(0) @binding(5) var<storage, read_write> crack_entries: array<vec4<u32>>;
// Counters (the first `CRACK_HEADER` words, cleared each frame), then the entries' atomics.
@group(0) @binding(6) var<storage, read_write> crack_state: array<atomic<u32>>;
// The indirect draw of the mask's and the resolve's quads, a quad (6 vertices) a crack,
// then the indirect dispatch of the seeded solves, 64 entries a workgroup (`cs_args`).
@group(0) @binding(7) var<storage, read_write> crack_args: array<u32>;
// The (u, v) target (f32 bits), read for the seeds: bound where the frame has one (the
// renderer makes it whenever the exact fill runs; else the ids target stands in, unread).
@group(0) @binding(8) var uv_tex: texture_2d<u32>;
// Per entry, the seeds (cracks/layout.wgsl's `CRACK_SEED_VEC4S`).
@group(0) @binding(9) var<storage, read_write> crack_seeds: array<vec4<u32>>;


// The crack buffers' capacity in entries (`passes::cracks` sets it).
override CRACK_ENTRY_CAPACITY: u32 = 1024u;

// A face is seen at a grazing angle where |n · v| is below this (its normal more than 45°
// from the view ray).
const GRAZING_COS: f32 = 0.7;

struct Texel {
    ids: vec4<u32>,
    distance: f32,
    // Reverse-Z depth (0: background).
    depth: f32,
    // A face (not the background, not a section cap).
    face: bool,
}

fn texel_at(p: vec2<i32>) -> Texel {
    var t: Texel;
    let depth = textureLoad(depth_tex, p, 0).x;
    t.ids = textureLoad(ids_tex, p, 0);
    t.distance = eye_distance(vec2<f32>(p) + 0.5, depth);
    t.depth = depth;
    t.face = (depth > 0.0) && (t.ids.y != 0u) && !is_cap(t.ids);
    if depth <= 0.0 {
        t.ids = vec4<u32>(0u);
    }
    return t;
}

fn same_face(a: vec4<u32>, b: vec4<u32>) -> bool {
    return (a.x == b.x) && (a.y == b.y);
}

// The four pairs' offsets.
fn pair_offset(k: u32) -> vec2<i32> {
    switch k {
        case 0u: { return vec2<i32>(1, 0); }
        case 1u: { return vec2<i32>(0, 1); }
        case 2u: { return vec2<i32>(1, 1); }
        default: { return vec2<i32>(1, -1); }
    }
}

// The offset of neighbour `k` (0..8) of a pixel, row by row, the pixel itself skipped.
fn neighbour(k: u32) -> vec2<i32> {
    let m = k + select(0u, 1u, k >= 4u);
    return vec2<i32>(i32(m % 3u) - 1, i32(m / 3u) - 1);
}

// The pair (0..3) that makes the pixel `p` of a target of `dims` a crack, 4 when none does.
fn crack_pair(p: vec2<i32>, dims: vec2<u32>) -> u32 {
    let g = vec2<u32>(p);
    // The image's border has no opposite neighbours.
    if (g.x == 0u) || (g.y == 0u) || (g.x + 1u >= dims.x) || (g.y + 1u >= dims.y) {
        return 4u;
    }
    // First on the depth target alone (reverse Z: nearer is greater), which turns away
    // nearly every pixel: on a surface the depth grows one way or the other across a pixel,
    // so one neighbour of each pair is farther.
    let depth = textureLoad(depth_tex, p, 0).x;
    var nearer_pair = false;
    var nearer_one = false;
    for (var k = 0u; k < 4u; k++) {
        let o = pair_offset(k);
        let a = textureLoad(depth_tex, p + o, 0).x;
        let b = textureLoad(depth_tex, p - o, 0).x;
        nearer_pair = nearer_pair | ((a > depth) & (b > depth));
        nearer_one = nearer_one | ((k < 2u) & ((a > depth) | (b > depth)));
    }
    // The silhouette rule, when asked for, needs a face at p and one edge neighbour nearer.
    let silhouettes = frame.forward.w > 0.5;
    if !nearer_pair & !(silhouettes & nearer_one & (depth > 0.0)) {
        return 4u;
    }
    let own = texel_at(p);
    if (own.ids.y != 0u) && is_cap(own.ids) {
        return 4u;
    }
    let d_min = frame.tolerances.z;
    var pair = 4u;
    for (var k = 0u; k < 4u; k++) {
        let o = pair_offset(k);
        let a = texel_at(p + o);
        let b = texel_at(p - o);
        let nearer = (a.distance + d_min <= own.distance) && (b.distance + d_min <= own.distance);
        let other = !same_face(a.ids, own.ids) && !same_face(b.ids, own.ids);
        if a.face && b.face && nearer && other && (pair == 4u) {
            pair = k;
        }
    }
    if (pair == 4u) && silhouettes && own.face && (silhouette_neighbour(p, own) < 4u) {
        pair = CRACK_PAIR_SILHOUETTE;
    }
    return pair;
}

// The offset of edge neighbour `k` (0..3: right, down, left, up).
fn edge_offset(k: u32) -> vec2<i32> {
    return select(-1, 1, k < 2u) * pair_offset(k % 2u);
}

// The first edge neighbour (`edge_offset`) of `p` (showing `own`) that shows another face
// nearer by d_min, seen there at a grazing angle (`GRAZING_COS`); 4 when none does.
fn silhouette_neighbour(p: vec2<i32>, own: Texel) -> u32 {
    let d_min = frame.tolerances.z;
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    for (var k = 0u; k < 4u; k++) {
        let q = p + edge_offset(k);
        let t = texel_at(q);
        if !t.face || same_face(t.ids, own.ids) || (t.distance + d_min > own.distance) {
            continue;
        }
        // The view ray at q, as the shade pass finds it.
        let pos = vec2<f32>(q) + 0.5;
        let ndc = vec2<f32>(pos.x / frame.viewport.x * 2.0 - 1.0, 1.0 - pos.y / frame.viewport.y * 2.0);
        let view_h = frame.inv_proj * vec4<f32>(ndc, t.depth, 1.0);
        let v = select(normalize(-view_h.xyz / view_h.w), vec3<f32>(0.0, 0.0, 1.0), ortho);
        let n = from_octahedral(textureLoad(normal_tex, q, 0).xy);
        if abs(dot(n, v)) < GRAZING_COS {
            return k;
        }
    }
    return 4u;
}

// One triangle over the target, at depth ½ (the entries' pass tests it against the flags).
@vertex
fn vs_detect(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.5, 1.0);
}

// The flags: the crack pixels at depth 0 in the crack mask, every other pixel at 1. Free of
// side effects, so a CPU rasterizer shades it 4 × 4 pixels at a time (a shader that writes
// storage runs pixel by pixel there: lavapipe, 1920 × 1080, PRO10363, 131 ms with the
// entries written here, 91 ms for an empty shader that merely could write).
@fragment
fn fs_flag(@builtin(position) pos: vec4<f32>) -> @builtin(frag_depth) f32 {
    return select(1.0, 0.0, crack_pair(vec2<i32>(pos.xy), textureDimensions(ids_tex)) != 4u);
}

// The entries: run where the flags pass (`Greater` than the mask: the cracks alone, where
// the adapter tests depth before a shader that writes storage, `@early_depth_test`;
// elsewhere every pixel, which finds no pair).
@fragment
fn fs_detect(@builtin(position) pos: vec4<f32>) {
    let dims = textureDimensions(ids_tex);
    let p = vec2<i32>(pos.xy);
    let index = u32(p.y) * dims.x + u32(p.x);
    let pair = crack_pair(p, dims);
    if pair == 4u {
        return;
    }
    let own = texel_at(p);
    let d_min = frame.tolerances.z;
    // The fast fill: of the eight neighbours nearer than p, the face most of them show, its
    // first texel, at their mean depth.
    var best = vec2<i32>(0);
    var best_count = 0u;
    for (var k = 0u; k < 8u; k++) {
        let o = neighbour(k);
        let t = texel_at(p + o);
        if !t.face || (t.distance + d_min > own.distance) {
            continue;
        }
        var count = 0u;
        for (var j = 0u; j < 8u; j++) {
            let oj = neighbour(j);
            let u = textureLoad(ids_tex, p + oj, 0);
            count += select(0u, 1u, same_face(u, t.ids) && (textureLoad(depth_tex, p + oj, 0).x > 0.0));
        }
        if count > best_count {
            best_count = count;
            best = o;
        }
    }
    let fill = texel_at(p + best);
    var depth_sum = 0.0;
    var depth_count = 0.0;
    for (var j = 0u; j < 8u; j++) {
        let oj = neighbour(j);
        let depth = textureLoad(depth_tex, p + oj, 0).x;
        if (depth > 0.0) && same_face(textureLoad(ids_tex, p + oj, 0), fill.ids) {
            depth_sum += depth;
            depth_count += 1.0;
        }
    }
    let entry = atomicAdd(&crack_state[CRACK_COUNT_ENTRIES], 1u);
    if pair == CRACK_PAIR_SILHOUETTE {
        atomicAdd(&crack_state[CRACK_COUNT_SILHOUETTES], 1u);
    }
    if entry >= CRACK_ENTRY_CAPACITY {
        atomicAdd(&crack_state[CRACK_COUNT_OVERFLOW], 1u);
        return;
    }
    crack_map[index] = entry + 1u;
    let normal = textureLoad(normal_tex, p + best, 0);
    crack_entries[3u * entry] = vec4<u32>(index, pair, bitcast<u32>(own.depth), 0u);
    crack_entries[3u * entry + 1u] = vec4<u32>(fill.ids.xyz, bitcast<u32>(depth_sum / max(depth_count, 1.0)));
    crack_entries[3u * entry + 2u] = bitcast<vec4<u32>>(vec4<f32>(normal.xy, 1.0, 1.0));
    // The seeds: the pair's two neighbours, or the grazing one beside a silhouette.
    var seeds = array<vec2<i32>, 2>(p + pair_offset(pair % 4u), p - pair_offset(pair % 4u));
    var present = vec2<bool>(true, true);
    if pair == CRACK_PAIR_SILHOUETTE {
        seeds[0] = p + edge_offset(silhouette_neighbour(p, own));
        present.y = false;
    }
    for (var k = 0u; k < CRACK_SEEDS; k++) {
        let q = seeds[k];
        let t = texel_at(q);
        let instance = select(0u, t.ids.y, present[k] & t.face);
        let at = CRACK_SEED_VEC4S * entry + 2u * k;
        crack_seeds[at] = vec4<u32>(t.ids.x, instance, textureLoad(uv_tex, q, 0).xy);
        crack_seeds[at + 1u] = vec4<u32>(0u);
    }
    let words = CRACK_HEADER + entry * CRACK_ENTRY_WORDS;
    for (var slot = 0u; slot < CRACK_MAILBOX_SLOTS; slot++) {
        atomicStore(&crack_state[words + slot], 0u);
    }
    atomicStore(&crack_state[words + CRACK_WORD_HEAD], 0u);
    // +∞: no solution off a face seen yet.
    atomicStore(&crack_state[words + CRACK_WORD_MISS], 0x7f800000u);
    atomicStore(&crack_state[words + CRACK_WORD_MISS_NEXT], 0x7f800000u);
}

// The indirect draw of the crack quads: 6 vertices, as many instances as cracks were kept;
// then the seeded solves' dispatch, a workgroup of 64 for every 64 of them.
@compute @workgroup_size(1)
fn cs_args() {
    let kept = min(atomicLoad(&crack_state[CRACK_COUNT_ENTRIES]), CRACK_ENTRY_CAPACITY);
    crack_args[0] = 6u;
    crack_args[1] = kept;
    crack_args[2] = 0u;
    crack_args[3] = 0u;
    crack_args[4] = (kept + 63u) / 64u;
    crack_args[5] = 1u;
    crack_args[6] = 1u;
    crack_args[7] = 0u;
}
