// Exact crack fill, which faces it draws (seed 000, Part IV: "the faces near the flagged
// pixels"): after the detection, each tessellation task's indirect draw is copied for the
// fill where its face's bounding sphere, placed by one of its call's instances, projects
// within `CRACK_FACE_MARGIN` pixels of a crack pixel, and emptied elsewhere, so that the
// fill's vertex stage runs on the faces about the cracks, not on every trimmed face again
// (trj3_s1-ec-214 at 1080p on lavapipe: 405 ms for 79 cracks). Conservative: a call with
// more instances than the pass walks, a sphere that reaches behind the near plane, or more
// work than `CRACK_FACE_WORK` keeps its draw.

@group(0) @binding(1) var<storage, read> surfaces: array<TrimSurface>;
@group(0) @binding(2) var<storage, read> tasks: array<TrimTask>;
// The tessellation's indirect draws (four words a task), and the fill's, written here.
@group(0) @binding(3) var<storage, read> args: array<u32>;
@group(0) @binding(4) var<storage, read_write> crack_args: array<u32>;
// The crack entries and state (`passes::cracks`: cracks/layout.wgsl): the count of cracks
// read, the faces drawn counted (`CrackCounts::fill_faces`).
@group(0) @binding(5) var<storage, read> crack_entries: array<vec4<u32>>;
@group(0) @binding(6) var<storage, read_write> crack_state: array<atomic<u32>>;
// The packed B-splines (surface.wgsl's grid breaks read them; not this pass).
@group(0) @binding(7) var<storage, read> trim_bspline: array<f32>;
// Per entry, its seeds (cracks/layout.wgsl): whether the seeded solves settled it.
@group(0) @binding(8) var<storage, read> crack_seeds: array<vec4<u32>>;

// The crack buffers' capacity in entries (`passes::cracks` sets it).
override CRACK_ENTRY_CAPACITY: u32 = 1024u;
// Instances walked one by one (tessellate.wgsl's `WALK`).
const CRACK_FACE_WALK: u32 = 64u;
// Pixels a crack may lie outside a face's projected sphere and still be reached: the fill's
// fragments solve for the cracks of their 3 × 3 neighbourhood.
const CRACK_FACE_MARGIN: f32 = 2.0;
// Instances × cracks a task may test (llvmpipe ends a shader's loops after 65,535
// iterations); past it the task is drawn.
const CRACK_FACE_WORK: u32 = 32768u;

// The pixel rectangle (x0, y0, x1, y1) that the sphere (camera-relative centre `c`, radius
// `r`) projects into: the bounds of its box's eight corners; the whole plane where a corner
// lies behind the near plane.
fn sphere_rect(c: vec3<f32>, r: f32) -> vec4<f32> {
    var lo = vec2<f32>(3.4e38);
    var hi = vec2<f32>(-3.4e38);
    for (var k = 0u; k < 8u; k++) {
        let corner = c + r * vec3<f32>(
            select(-1.0, 1.0, (k & 1u) != 0u),
            select(-1.0, 1.0, (k & 2u) != 0u),
            select(-1.0, 1.0, (k & 4u) != 0u),
        );
        let clip = frame.view_proj * vec4<f32>(corner, 1.0);
        // Reverse Z: in front of the near plane where z ≤ w (and w > 0).
        if (clip.w <= 0.0) | (clip.z > clip.w) {
            return vec4<f32>(-3.4e38, -3.4e38, 3.4e38, 3.4e38);
        }
        let ndc = clip.xy / clip.w;
        let p = vec2<f32>((0.5 + 0.5 * ndc.x) * frame.viewport.x, (0.5 - 0.5 * ndc.y) * frame.viewport.y);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    return vec4<f32>(lo - CRACK_FACE_MARGIN, hi + CRACK_FACE_MARGIN);
}

@compute @workgroup_size(64)
fn cs_crack_faces(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = id.x;
    if t >= arrayLength(&tasks) {
        return;
    }
    let task = tasks[t];
    let s = surfaces[task.surface];
    let cracks = min(atomicLoad(&crack_state[CRACK_COUNT_ENTRIES]), CRACK_ENTRY_CAPACITY);
    let walked = min(task.instances, CRACK_FACE_WALK);
    var near = (task.instances > CRACK_FACE_WALK) | (walked * cracks > CRACK_FACE_WORK);
    let width = u32(frame.viewport.x);
    let count = max(task.locals_count, 1u);
    for (var i = 0u; (i < walked) & !near; i++) {
        let d = draws[task.record + i / count];
        let l = locals[task.locals_first + i % count];
        let m = d.model * l.model;
        let c = (m * vec4<f32>(s.sphere.xyz, 1.0)).xyz;
        let k = max(length(m[0].xyz), max(length(m[1].xyz), length(m[2].xyz)));
        let rect = sphere_rect(c, s.sphere.w * k);
        for (var e = 0u; (e < cracks) & !near; e++) {
            let head = crack_entries[3u * e];
            let p = vec2<f32>(f32(head.x % width), f32(head.x / width)) + 0.5;
            // A pixel beside a silhouette is solved from its seed alone (`cs_seeded`), and
            // one its seeds settled needs no face drawn again.
            let seeded = (head.y == CRACK_PAIR_SILHOUETTE) | (crack_seeds[CRACK_SEED_VEC4S * e + 1u].w != 0u);
            near = all(p >= rect.xy) & all(p <= rect.zw) & !seeded;
        }
    }
    if near {
        atomicAdd(&crack_state[CRACK_COUNT_FILL_FACES], 1u);
    }
    crack_args[4u * t] = select(0u, args[4u * t], near);
    crack_args[4u * t + 1u] = args[4u * t + 1u];
    crack_args[4u * t + 2u] = args[4u * t + 2u];
    crack_args[4u * t + 3u] = args[4u * t + 3u];
}
