// Trim back-end, tessellation (compute, before the visibility pass): for each face of each
// mesh call (a `TrimTask`), the grid its surface is drawn with this frame, written as an
// indirect draw (`args`, four words a task) and its levels (`levels`, two words a task: cells
// per span along u in the low 16 bits, along v in the high ones, then where its grid points
// start in `grid_points`; a B-spline's spans are its knot spans within the face, so that
// every knot line is a grid line, a closed form has one each way). `cs_main` chooses the
// grids and takes room for their points from `points_used`; `cs_points` then evaluates the
// points, once each (the draw's six corners a cell read them): a face whose points found no
// room (`NO_POINTS`) is evaluated by the vertex shader instead.
//
// The grid's error: a cell of size (h_u, h_v) departs from the surface by at most
// (h_u² |S_uu| + 2 h_u h_v |S_uv| + h_v² |S_vv|) / 8 (the interpolation error of a function of
// bounded second derivatives), which must stay within `TOLERANCE_PX` pixels at the face's
// nearest point: a pixel's world size there is its distance times the projection's slope
// (perspective), or the view's constant one (orthographic) — and within `TOLERANCE_REL` of
// the face's bounding radius: the pixel bound alone lets a small or distant curved face sag
// through whatever lies just behind it (a pipe's bore through its 2 mm wall at 20 mm a pixel),
// since it bounds the error across the screen, not in depth — down to the model's depth bound
// (`TrimScene::depth_tolerance`, a quarter of the static mesh's deflection), below which that
// share over-tessellated small faces. Faces outside the view frustum
// in all the call's instances get no cells.

@group(0) @binding(1) var<storage, read> surfaces: array<TrimSurface>;
@group(0) @binding(2) var<storage, read> tasks: array<TrimTask>;
@group(0) @binding(3) var<storage, read_write> args: array<u32>;
@group(0) @binding(4) var<storage, read_write> levels: array<u32>;
@group(0) @binding(5) var<storage, read> trim_bspline: array<f32>;
@group(0) @binding(6) var<storage, read_write> points_used: array<atomic<u32>>;
@group(0) @binding(7) var<storage, read_write> grid_points: array<vec4<f32>>;
// The trim trees (`cadre_trim::TRIM_WGSL`, appended): the cells' verdicts.
@group(0) @binding(8) var<storage, read> trim_faces: array<TrimFace>;
@group(0) @binding(9) var<storage, read> trim_nodes: array<u32>;
@group(0) @binding(10) var<storage, read> trim_floats: array<f32>;
@group(0) @binding(11) var<storage, read> trim_piece_offsets: array<u32>;
@group(0) @binding(12) var<storage, read> trim_lists: array<u32>;

// The tessellation's tolerance, in pixels.
override TOLERANCE_PX: f32 = 0.5;
// The tessellation's tolerance relative to the face's bounding radius.
override TOLERANCE_REL: f32 = 0.002;
// Grid lines a face may have each way (at most 256: `TRIM_VERTICES`); lower only for the
// benchmarks that separate the costs of the geometry from the others.
override MAX_LEVEL: f32 = 256.0;
// Grid lines a face has each way at least: cells wholly on the face skip the per-fragment
// trim test, so even a plane is cut into a few (its 2 triangles would all be crossed).
override MIN_LEVEL: f32 = 4.0;
// Workgroups sharing a task's grid points (`trim::POINT_CHUNKS`: a CPU rasterizer ends long
// shader loops, so no invocation evaluates many).
const POINT_CHUNKS: u32 = 16u;
// Calls with more instances than this are not walked one by one: their nearest distance is
// the task's `near` (from the runs' bounding spheres), and they are not culled here.
const WALK: u32 = 64u;

// Whether the sphere (camera-relative centre `c`, radius `r`) meets the view frustum's four
// side planes (which also put it in front of a perspective eye).
fn in_frustum(c: vec3<f32>, r: f32) -> bool {
    let m = frame.view_proj;
    let row0 = vec4<f32>(m[0].x, m[1].x, m[2].x, m[3].x);
    let row1 = vec4<f32>(m[0].y, m[1].y, m[2].y, m[3].y);
    let row3 = vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w);
    let p = vec4<f32>(c, 1.0);
    var inside = true;
    for (var k = 0u; k < 4u; k++) {
        let side = select(1.0, -1.0, (k & 1u) != 0u);
        let plane = row3 + side * select(row0, row1, k >= 2u);
        inside = inside & (dot(plane, p) >= -4.0 * r * length(plane.xyz));
    }
    return inside;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let t = id.x;
    if t >= arrayLength(&tasks) {
        return;
    }
    let task = tasks[t];
    let s = surfaces[task.surface];
    let walk = task.instances <= WALK;
    var near = select(3.4e38, task.near, !walk);
    var scale = select(0.0, 1.0, !walk);
    var visible = !walk;
    let count = max(task.locals_count, 1u);
    for (var i = 0u; i < min(task.instances, WALK); i++) {
        let d = draws[task.record + i / count];
        let l = locals[task.locals_first + i % count];
        let m = d.model * l.model;
        let c = (m * vec4<f32>(s.sphere.xyz, 1.0)).xyz;
        let k = max(length(m[0].xyz), max(length(m[1].xyz), length(m[2].xyz)));
        let r = s.sphere.w * k;
        visible = visible | in_frustum(c, r);
        near = min(near, length(c) - r);
        scale = max(scale, k);
    }
    // A ray-cast face: its box's 36 vertices, no grid (raycast.wgsl).
    if is_ray_cast(s) {
        args[4u * t] = select(0u, 36u, visible);
        args[4u * t + 1u] = task.instances;
        args[4u * t + 2u] = task.slot * TRIM_VERTICES;
        args[4u * t + 3u] = 0u;
        levels[2u * t] = 1u | (1u << 16u);
        levels[2u * t + 1u] = NO_POINTS;
        return;
    }
    // The near plane's distance (reverse Z: depth 1), below which nothing is drawn.
    let near_h = frame.inv_proj * vec4<f32>(0.0, 0.0, 1.0, 1.0);
    let z_near = abs(near_h.z / near_h.w);
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let distance = select(max(near, z_near), 1.0, ortho);
    let pixel = distance * 2.0 * frame.inv_proj[1][1] / frame.viewport.y;
    // Half a pixel, and in depth a share of the face's radius, but no finer than the model's
    // depth bound (`TrimScene::depth_tolerance`, the record's axis_z.w).
    let depth = max(TOLERANCE_REL * s.sphere.w, s.axis_z.w) * scale;
    let eps = max(min(TOLERANCE_PX * pixel, depth), 1e-30);
    let m = s.curvature.xyz * scale;
    let spans = grid_spans(s);
    // The widest span each way: every span gets the cells the widest needs.
    var size = vec2<f32>(0.0);
    for (var axis = 0u; axis < 2u; axis++) {
        for (var k = 0u; k < spans[axis]; k++) {
            let w = grid_break(s, spans, axis, k + 1u) - grid_break(s, spans, axis, k);
            size[axis] = max(size[axis], w);
        }
    }
    // Cells a span may hold so that the grid stays within MAX_LEVEL lines.
    let most = max(floor(vec2<f32>(MAX_LEVEL) / vec2<f32>(spans)), vec2<f32>(1.0));
    // Half the error for each pure term, then both levels raised together until the whole
    // bound, the mixed term's included, fits.
    // Faces over 16 pixels across at their nearest are cut into MIN_LEVEL cells each way at
    // least (smaller ones have few pixels to test).
    let across = s.sphere.w * scale / pixel;
    let least_lines = select(1.0, MIN_LEVEL, across > 16.0);
    let least = max(ceil(vec2<f32>(least_lines) / vec2<f32>(spans)), vec2<f32>(1.0));
    var n = max(ceil(size * sqrt(m.xz / (4.0 * eps))), least);
    n = min(n, most);
    let h = size / n;
    let e = (h.x * h.x * m.x + 2.0 * h.x * h.y * m.y + h.y * h.y * m.z) / 8.0;
    n = clamp(ceil(n * sqrt(max(e / eps, 1.0))), vec2<f32>(1.0), most);
    let per = vec2<u32>(n);
    let lines = per * spans;
    let cells = select(0u, lines.x * lines.y, visible);
    args[4u * t] = 6u * cells;
    args[4u * t + 1u] = task.instances;
    args[4u * t + 2u] = task.slot * TRIM_VERTICES;
    args[4u * t + 3u] = 0u;
    // Room for the grid's points (two vec4 each) and its cells' trim verdicts (eight a
    // point's room, `verdict_slot`), or none: the vertex shader evaluates them.
    let points = select(0u, (lines.x + 1u) * (lines.y + 1u) + (cells + 7u) / 8u, visible);
    var base = NO_POINTS;
    if points > 0u {
        let at = atomicAdd(&points_used[0], points);
        if at + points <= arrayLength(&grid_points) / 2u {
            base = at;
        }
    }
    levels[2u * t] = per.x | (per.y << 16u);
    levels[2u * t + 1u] = base;
}

// The grid points of task `wg.x + 65535 wg.y`, POINT_CHUNKS workgroups of 64 invocations
// each (chunk `wg.z`): position and (u, v) from the box's corner, as (x, y, z, u) then
// (normal, v).
@compute @workgroup_size(64)
fn cs_points(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let t = wg.x + 65535u * wg.y;
    if t >= arrayLength(&tasks) {
        return;
    }
    let base = levels[2u * t + 1u];
    if base == NO_POINTS {
        return;
    }
    let s = surfaces[tasks[t].surface];
    let level = levels[2u * t];
    let per = vec2<u32>(max(level & 0xffffu, 1u), max(level >> 16u, 1u));
    let spans = grid_spans(s);
    let row = per.x * spans.x + 1u;
    let count = row * (per.y * spans.y + 1u);
    for (var i = lane + 64u * wg.z; i < count; i += 64u * POINT_CHUNKS) {
        let g = vec2<u32>(i % row, i / row);
        let local = vec2<f32>(grid_param(s, spans, 0u, g.x, per.x), grid_param(s, spans, 1u, g.y, per.y));
        let p = face_point(s, local);
        grid_points[2u * (base + i)] = vec4<f32>(p.position, local.x);
        grid_points[2u * (base + i) + 1u] = vec4<f32>(p.normal, local.y);
    }
    // Each cell against the face's trim tree, once (the vertex shader reads the verdict at
    // each of the cell's six corners): out — not drawn, in — not tested per pixel, crossed.
    let lines = per * spans;
    let cells = lines.x * lines.y;
    for (var c = lane + 64u * wg.z; c < cells; c += 64u * POINT_CHUNKS) {
        let first = vec2<u32>(c % lines.x, c / lines.x);
        let lo = vec2<f32>(grid_param(s, spans, 0u, first.x, per.x), grid_param(s, spans, 1u, first.y, per.y));
        let hi = vec2<f32>(
            grid_param(s, spans, 0u, first.x + 1u, per.x),
            grid_param(s, spans, 1u, first.y + 1u, per.y),
        );
        let slot = verdict_slot(base, lines, c);
        grid_points[slot.x][slot.y] = f32(trim_cell(s.ids.z, lo, hi));
    }
}
