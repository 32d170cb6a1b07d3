// Crack resolve (seed 000, Part IV, steps 3a and the composite of 3b): a quad over each
// crack pixel the detection kept (an indirect instanced draw: the cost follows the cracks,
// not the image) gives it a texel of the visibility buffer (normal, ids, (u, v), and its
// depth through `frag_depth`); every other pixel is left as it is. With the exact fill, the nearest of the pixel's hits (crack.wgsl) — the exact
// surface seen there, trimmed exactly — where it is nearer than what the pixel shows;
// without one, a real gap in the model: closed by the fast fill when narrower than the gap
// tolerance (the two least distances from the pixel's ray to a face's trim), else left. With the fast fill alone,
// the face most of the neighbours show. Marked (ids' material bits 30 and 29) for the
// inspection view when `HIGHLIGHT` is set.

@group(0) @binding(1) var<storage, read> crack_entries: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> crack_state: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read> crack_hits: array<vec4<u32>>;
// Per entry, its seeds (layout.wgsl): the mask reads whether the seeded solves settled it.
@group(0) @binding(4) var<storage, read> crack_seeds: array<vec4<u32>>;


// The exact fill ran (else the fast fill only).
override EXACT: bool = true;
// Mark filled cracks and closed gaps for the inspection view.
override HIGHLIGHT: bool = false;
// Hits a pixel's list is walked for, at most (the mailbox keeps lists short).
const CRACK_LIST_MAX: u32 = 64u;

struct ResolveOut {
    @location(0) normal: vec4<f32>,
    @location(1) ids: vec4<u32>,
    @location(2) uv: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

// Corner `corner` (0..6, two triangles) of the square of `radius` pixels about the centre of
// crack `entry`'s pixel, at reverse-Z depth `z`.
fn crack_quad(entry: u32, corner: u32, radius: f32, z: f32) -> vec4<f32> {
    let width = u32(frame.viewport.x);
    let pixel = crack_entries[3u * entry].x;
    let centre = vec2<f32>(f32(pixel % width), f32(pixel / width)) + 0.5;
    // Corners (0, 0), (1, 0), (1, 1), (0, 0), (1, 1), (0, 1), as bit masks.
    let step = vec2<f32>(f32((22u >> corner) & 1u), f32((52u >> corner) & 1u));
    let q = centre + (2.0 * step - 1.0) * radius;
    return vec4<f32>(q.x / frame.viewport.x * 2.0 - 1.0, 1.0 - q.y / frame.viewport.y * 2.0, z, 1.0);
}

struct ResolveVertex {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) entry: u32,
}

// One quad a crack (instanced: the detection's count), over its pixel.
@vertex
fn vs_resolve(@builtin(vertex_index) corner: u32, @builtin(instance_index) entry: u32) -> ResolveVertex {
    var out: ResolveVertex;
    out.position = crack_quad(entry, corner, 0.5, 0.0);
    out.entry = entry;
    return out;
}

// The exact fill's depth mask: the 3 × 3 pixels about each crack at depth 0, so that the
// fill's fragments pass (`Greater`) only there, everywhere else turned away before their
// shader runs (the mask is cleared to 1). A pixel the seeded solves settled
// (visibility/trim/crack.wgsl's `cs_seeded`), and one beside a silhouette, which only they
// solve, get no square: no face is drawn again for them.
@vertex
fn vs_mask(@builtin(vertex_index) corner: u32, @builtin(instance_index) entry: u32) -> @builtin(position) vec4<f32> {
    let seeded = (crack_entries[3u * entry].y == CRACK_PAIR_SILHOUETTE)
        | (crack_seeds[CRACK_SEED_VEC4S * entry + 1u].w != 0u);
    return crack_quad(entry, corner, select(1.5, 0.0, seeded), 0.0);
}

@fragment
fn fs_resolve(in: ResolveVertex) -> ResolveOut {
    let pos = in.position;
    let entry = in.entry;
    let words = CRACK_HEADER + entry * CRACK_ENTRY_WORDS;
    var out: ResolveOut;
    // The nearest hit (reverse Z: the largest depth).
    var best = 0u;
    var best_depth = -1.0;
    var next = atomicLoad(&crack_state[words + CRACK_WORD_HEAD]);
    for (var k = 0u; (k < CRACK_LIST_MAX) && (next != 0u); k++) {
        let hit = next - 1u;
        let depth = bitcast<f32>(crack_hits[2u * hit].w);
        if depth > best_depth {
            best_depth = depth;
            best = next;
        }
        next = crack_hits[2u * hit + 1u].w;
    }
    // A hit closes the crack only if it is nearer than what the pixel shows by d_min: the
    // surface the pixel already shows (a floor seen through a real gap) is hit too.
    let own = bitcast<f32>(crack_entries[3u * entry].z);
    let closes = eye_distance(pos.xy, best_depth) + frame.tolerances.z <= eye_distance(pos.xy, own);
    if EXACT && (best != 0u) && closes {
        let a = crack_hits[2u * (best - 1u)];
        let b = crack_hits[2u * (best - 1u) + 1u];
        out.ids = vec4<u32>(a.x, a.y, a.z | select(0u, CRACK_FILLED, HIGHLIGHT), a.w);
        out.normal = vec4<f32>(unpack2x16unorm(b.x), 1.0, 1.0);
        out.uv = b.yz;
        out.depth = best_depth;
        atomicAdd(&crack_state[CRACK_COUNT_EXACT], 1u);
        return out;
    }
    var mark = select(0u, CRACK_FILLED, HIGHLIGHT);
    // A pixel beside a silhouette that no exact surface covers: the silhouette passes before
    // it, as drawn (not a crack left open; never the fast fill's).
    if crack_entries[3u * entry].y == CRACK_PAIR_SILHOUETTE {
        discard;
    }
    if EXACT {
        // No face's exact surface closes it: a gap in the model itself, as wide as the
        // ray's two least misses of a face's trim (a face each side; unknown, so left open,
        // where only one face told). Closed when narrower than the tolerance.
        let least = bitcast<f32>(atomicLoad(&crack_state[words + CRACK_WORD_MISS]));
        let next = bitcast<f32>(atomicLoad(&crack_state[words + CRACK_WORD_MISS_NEXT]));
        let width = least + next;
        if !(width <= frame.tolerances.w) {
            atomicAdd(&crack_state[CRACK_COUNT_OPEN], 1u);
            discard;
        }
        mark = select(0u, GAP_CLOSED, HIGHLIGHT);
        atomicAdd(&crack_state[CRACK_COUNT_GAPS], 1u);
    } else {
        atomicAdd(&crack_state[CRACK_COUNT_FAST], 1u);
    }
    let fill = crack_entries[3u * entry + 1u];
    out.ids = vec4<u32>(fill.x, fill.y, fill.z | mark, fill.w);
    out.normal = bitcast<vec4<f32>>(crack_entries[3u * entry + 2u]);
    out.uv = vec2<u32>(0u);
    out.depth = bitcast<f32>(fill.w);
    return out;
}
