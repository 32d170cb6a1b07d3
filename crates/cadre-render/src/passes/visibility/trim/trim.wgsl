// Trim back-end of the visibility pass: each face's support surface evaluated over its trim
// tree's (u, v) box on the grid the tessellation pass chose (tessellate.wgsl), placed by its
// call's instances (instances.wgsl), and trimmed per fragment by its tree (cadre_trim's
// trim.wgsl, after this file); each kept fragment is written by `visibility_texel`
// (texel.wgsl), as the mesh back-end's are.

@group(0) @binding(1) var<storage, read> surfaces: array<TrimSurface>;
@group(0) @binding(2) var<storage, read> levels: array<u32>;
@group(0) @binding(3) var<storage, read> trim_faces: array<TrimFace>;
@group(0) @binding(4) var<storage, read> trim_nodes: array<u32>;
@group(0) @binding(5) var<storage, read> trim_floats: array<f32>;
@group(0) @binding(6) var<storage, read> trim_piece_offsets: array<u32>;
@group(0) @binding(7) var<storage, read> trim_lists: array<u32>;
@group(0) @binding(8) var<storage, read> trim_bspline: array<f32>;
@group(0) @binding(9) var<storage, read> grid_points: array<vec4<f32>>;

// The trim test, off only for the tests' negative control (the surfaces' whole boxes).
override TRIM_TEST: bool = true;
// Trimmed edges' pixels carry their analytic coverage (the frame's shade pass blends them).
override COVERAGE: bool = true;

struct TrimOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    // (u, v) from the tree's lower corner: what the trim test reads.
    @location(1) local: vec2<f32>,
    @location(2) @interpolate(flat) surface: u32,
    @location(3) @interpolate(flat) instance: vec3<u32>,
    // Camera-relative world position, for the section planes.
    @location(4) world: vec3<f32>,
    // The face's outward normal against the view ray: negative where it faces the eye.
    @location(5) facing: f32,
    // Whether the fragment must be tested against the tree: its cell is crossed by the trim
    // (cells wholly on the face are not tested, those wholly off it are not drawn).
    @location(6) @interpolate(flat) crossed: u32,
}

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> TrimOut {
    return trim_vertex(vertex, instance);
}

// Vertex `vertex` of instance `instance` of a draw: the grid point it stands for, placed
// (also the crack pass's vertex, crack.wgsl).
fn trim_vertex(vertex: u32, instance: u32) -> TrimOut {
    // The face is the draw's `vertex / TRIM_VERTICES`-th (its first vertex, set by the
    // tessellation pass), the cell and corner its `vertex % TRIM_VERTICES`-th.
    let k = vertex / TRIM_VERTICES;
    let local_vertex = vertex % TRIM_VERTICES;
    let index = call.range.x + k;
    let s = surfaces[index];
    let task = call.range.y + k;
    let level = levels[2u * task];
    let base = levels[2u * task + 1u];
    let per = vec2<u32>(max(level & 0xffffu, 1u), max(level >> 16u, 1u));
    let spans = grid_spans(s);
    let lines = per * spans;
    let cell = local_vertex / 6u;
    // Corners (0, 0), (1, 0), (1, 1), (0, 0), (1, 1), (0, 1) of the cell, as bit masks.
    let corner = local_vertex % 6u;
    let step = vec2<u32>((22u >> corner) & 1u, (52u >> corner) & 1u);
    let first = vec2<u32>(cell % lines.x, cell / lines.x);
    let grid = first + step;
    // The point the tessellation pass evaluated, or (no room there) evaluated here.
    var local: vec2<f32>;
    var point: SurfacePoint;
    if base != NO_POINTS {
        let i = base + grid.y * (lines.x + 1u) + grid.x;
        let a = grid_points[2u * i];
        let b = grid_points[2u * i + 1u];
        local = vec2<f32>(a.w, b.w);
        point = SurfacePoint(a.xyz, b.xyz);
    } else {
        local = vec2<f32>(grid_param(s, spans, 0u, grid.x, per.x), grid_param(s, spans, 1u, grid.y, per.y));
        point = face_point(s, local);
    }
    // The cell against the tree, the same at its six corners: the tessellation pass's
    // verdict, or (no room there) worked out here.
    var verdict = TRIM_CELL_CROSSED;
    if TRIM_TEST && (base != NO_POINTS) {
        let slot = verdict_slot(base, lines, cell);
        verdict = u32(grid_points[slot.x][slot.y] + 0.5);
    } else if TRIM_TEST {
        let cell_lo = vec2<f32>(grid_param(s, spans, 0u, first.x, per.x), grid_param(s, spans, 1u, first.y, per.y));
        let cell_hi = vec2<f32>(
            grid_param(s, spans, 0u, first.x + 1u, per.x),
            grid_param(s, spans, 1u, first.y + 1u, per.y),
        );
        verdict = trim_cell(s.ids.z, cell_lo, cell_hi);
    }
    let d = instance_draw(instance);
    let normal = point.normal * s.axis_y.w;
    let placed = place_vertex(d, point.position, normal);
    var out: TrimOut;
    out.clip = placed.clip;
    out.normal = placed.normal;
    out.local = local;
    out.surface = index;
    out.instance = pack_instance(d);
    out.world = placed.world;
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let world_normal = (d.model * vec4<f32>(normal, 0.0)).xyz;
    out.facing = dot(world_normal, select(placed.world, frame.forward.xyz, ortho));
    out.crossed = select(0u, 1u, verdict == TRIM_CELL_CROSSED);
    // A cell wholly off the face: every corner at the same point, out of the view.
    if verdict == TRIM_CELL_OUT {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    }
    return out;
}

@fragment
fn fs_main(in: TrimOut) -> VisibilityOut {
    // The pixel's footprint in (u, v), before any discard (derivatives need every lane).
    // A cell answered by its coverage bit misplaces the trim boundary by up to the cell's
    // size on screen; fwidth sums the (u, v) change over a step in x and one in y, so a
    // quarter of it keeps that within half a pixel where the face is not seen edge-on
    // (with the whole fwidth, pixels two away from a face were drawn on it), while the
    // cells of a distant perforated face still merge into their majority (no moiré).
    let jx = dpdx(in.local);
    let jy = dpdy(in.local);
    let footprint = 0.25 * (abs(jx) + abs(jy));
    let s = surfaces[in.surface];
    if TRIM_TEST && (in.crossed != 0u) && !trim_classify_within(s.ids.z, in.local, footprint) {
        discard;
    }
    if SECTIONS && section_cut(in.world) {
        discard;
    }
    let ids = unpack_instance(in.instance);
    let uv = s.uv.xy + in.local;
    var out = visibility_texel(in.world, in.normal, s.ids.y, ids, in.clip.z, uv, in.facing < 0.0);
    // Analytic coverage of a pixel on a trimmed edge (kept: its centre is on the face): ½ at
    // the boundary, whole from half a pixel in (F / |∇F| in pixels; caps keep theirs).
    if COVERAGE && TRIM_TEST && (in.crossed != 0u) && ((out.ids.z & SECTION_CAP) == 0u) {
        out.normal.z = clamp(0.5 + trim_edge_pixels(s.ids.z, in.local, jx, jy), 0.5, 1.0);
    }
    return out;
}
