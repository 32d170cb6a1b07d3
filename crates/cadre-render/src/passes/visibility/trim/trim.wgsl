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
    // Whether the fragment must be tested against the tree: its cell is crossed by the trim
    // (cells wholly on the face are not tested, those wholly off it are not drawn).
    @location(6) @interpolate(flat) crossed: u32,
    // A ray-cast face's proxy (raycast.wgsl's `RayFrame`; zeros for a tessellated face).
    @location(7) ray_point: vec3<f32>,
    @location(8) @interpolate(flat) ray_eye: vec4<f32>,
    @location(9) @interpolate(flat) normal_x: vec3<f32>,
    @location(10) @interpolate(flat) normal_y: vec3<f32>,
    @location(11) @interpolate(flat) normal_z: vec3<f32>,
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
    if is_ray_cast(s) {
        return ray_cast_vertex(index, s, local_vertex, instance);
    }
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
    out.instance = trim_instance(d);
    out.world = placed.world;
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
    let point = fragment_view_point(in.clip);
    return trim_fragment(in, jx, jy, cross(dpdx(point), dpdy(point)));
}

// A tessellated face's fragment, (u, v) changing by `jx`, `jy` to the next pixels, on a
// triangle of view-space normal `plane` (either sense): trimmed (discarded off the face)
// and written, its normal kept on the side of the triangle seen (`surface_facing`).
fn trim_fragment(in: TrimOut, jx: vec2<f32>, jy: vec2<f32>, plane: vec3<f32>) -> VisibilityOut {
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
    let closed = (ids.flags & DRAW_CLOSED) != 0u;
    let facing = surface_facing(in.normal, plane, in.clip, closed);
    let front = winding_front(facing.front, ids);
    if hidden_inside(front, ids) {
        discard;
    }
    var out = visibility_texel(in.world, facing.normal, s.ids.y, ids, in.clip.z, uv, front);
    // Analytic coverage of a pixel on a trimmed edge (kept: its centre is on the face): ½ at
    // the boundary, whole from half a pixel in (F / |∇F| in pixels; caps keep theirs).
    if COVERAGE && TRIM_TEST && (in.crossed != 0u) && ((out.ids.z & SECTION_CAP) == 0u) {
        out.normal.z = clamp(0.5 + trim_edge_pixels(s.ids.z, in.local, jx, jy), 0.5, 1.0);
    }
    return out;
}

// The least |cos| between a ray-cast hit's normal and its ray (`fs_raycast`).
const GRAZING_HIT: f32 = 1e-4;

// The draw's ids for the fragments, with `DRAW_MIRRORED` where its placement mirrors.
fn trim_instance(d: Draw) -> vec3<u32> {
    let linear = mat3x3<f32>(d.model[0].xyz, d.model[1].xyz, d.model[2].xyz);
    return vec3<u32>(d.material, d.instance, d.flags | select(0u, DRAW_MIRRORED, determinant(linear) < 0.0));
}

// The side of a face's point seen, `front` by its exact normal, as `visibility_texel`
// reads it: the triangles' winding's, which `DRAW_INSIDE_OUT` turns over for a mirroring
// placement. The exact normals stay outward under a mirror (their inverse transpose), so
// a mirror turns their side over against the winding's.
fn winding_front(front: bool, ids: InstanceIds) -> bool {
    return front != ((ids.flags & DRAW_MIRRORED) != 0u);
}

// Whether a point of a closed solid seen from inside (`front` as `winding_front` gives it)
// is left out: without section planes (whose caps need it) it shows only where the grids
// of the faces in front end short of their true silhouette (within their half-pixel
// tolerance) while a face behind reaches its exact trim — a plane end cap seen from
// inside past a cylinder's rim, lit as facing the eye — or ties with them at an apex.
// Left out, the pixel shows what lies behind, as past any tessellated silhouette.
// `frame.sky_up.w` at 1 keeps them (the tests' negative control).
fn hidden_inside(front: bool, ids: InstanceIds) -> bool {
    let inside = front == ((ids.flags & DRAW_INSIDE_OUT) != 0u);
    let closed = (ids.flags & DRAW_CLOSED) != 0u;
    return closed && (frame.counts.z == 0u) && inside && (frame.sky_up.w == 0.0);
}

// A ray-cast face's proxy vertex: corner `corner` of its box, placed by instance `instance`.
fn ray_cast_vertex(index: u32, s: TrimSurface, corner: u32, instance: u32) -> TrimOut {
    let d = instance_draw(instance);
    let ray = ray_cast_corner(s, d, min(corner, 35u));
    let position = s.origin.xyz + ray.point.x * s.axis_x.xyz + ray.point.y * s.axis_y.xyz
        + ray.point.z * s.axis_z.xyz;
    let placed = place_vertex(d, position, s.axis_z.xyz);
    var out: TrimOut;
    out.clip = placed.clip;
    // Vertices past the box's 36 (a draw reserves TRIM_VERTICES) are out of the view.
    if corner >= 36u {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    }
    out.normal = placed.normal;
    out.local = vec2<f32>(0.0);
    out.surface = index;
    out.instance = trim_instance(d);
    out.world = placed.world;
    out.crossed = 1u;
    out.ray_point = ray.point;
    out.ray_eye = ray.eye;
    out.normal_x = ray.normal_x;
    out.normal_y = ray.normal_y;
    out.normal_z = ray.normal_z;
    return out;
}

struct RayCastOut {
    @location(0) normal: vec4<f32>,
    @location(1) ids: vec4<u32>,
    @location(2) uv: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

// The fragment of the ray-cast variant (`--method raycast`): a ray-cast face's nearest hit
// that its trim tree keeps, at the hit's own depth; a tessellated face's as `fs_main` writes
// it, at its own depth.
@fragment
fn fs_raycast(in: TrimOut) -> RayCastOut {
    let s = surfaces[in.surface];
    let analytic = is_ray_cast(s);
    // A tessellated face's derivatives, taken first, as `fs_main` takes them.
    let tx = dpdx(in.local);
    let ty = dpdy(in.local);
    let point = fragment_view_point(in.clip);
    let plane = cross(dpdx(point), dpdy(point));
    var hits: FaceCast;
    var local = vec2<f32>(0.0);
    let ray = frame_ray(in.ray_point, in.ray_eye);
    var first = 0.0;
    if analytic {
        hits = cast_face(s, ray.o, ray.d);
        local = hits.local[0];
        first = f32(hits.count > 0u);
    }
    // Derivatives before any discard (every lane of the quad takes part); a ray-cast
    // face's are of its first hit's (u, v), and hold only where the neighbours have one too.
    var jx = dpdx(local);
    var jy = dpdy(local);
    let steady = (dpdx(first) == 0.0) && (dpdy(first) == 0.0);
    var out: RayCastOut;
    if !analytic {
        let texel = trim_fragment(in, tx, ty, plane);
        out.normal = texel.normal;
        out.ids = texel.ids;
        out.uv = texel.uv;
        out.depth = in.clip.z;
        return out;
    }
    jx = short_way(s, jx);
    jy = short_way(s, jy);
    for (var i = 0u; i < hits.count; i++) {
        let t = hits.t[i];
        let local = hits.local[i];
        let world = ray_world(in.world, in.ray_eye, t);
        let footprint = cast_footprint(s, ray.o + t * ray.d, ray.d, in.world, in.ray_eye);
        let clip = frame.view_proj * vec4<f32>(world, 1.0);
        let depth = clip.z / clip.w;
        // In front of the near plane (reverse Z) and not behind the eye.
        if clip.w <= 0.0 || depth > 1.0 || depth < 0.0 {
            continue;
        }
        let in_box = all(local >= vec2<f32>(0.0)) && all(local <= s.uv.zw);
        if !in_box || (TRIM_TEST && !trim_classify_within(s.ids.z, local, footprint)) {
            continue;
        }
        if SECTIONS && section_cut(world) {
            continue;
        }
        let n = hits.n[i] * s.axis_y.w;
        // A hit this grazing is f32's, not the surface's: a face seen exactly edge-on
        // (its plane through the eye, the eye on its cylinder) covers no pixel, yet the
        // rounded roots put a dotted line of it over the faces behind. Past the limit a
        // plane 10⁴ pixels long is under a pixel wide, a cylinder's silhouette band 10⁻⁸ of
        // its radius.
        if abs(dot(n, ray.d)) < GRAZING_HIT * length(n) * length(ray.d) {
            continue;
        }
        let normal = n.x * in.normal_x + n.y * in.normal_y + n.z * in.normal_z;
        let ids = unpack_instance(in.instance);
        let front = winding_front(dot(n, ray.d) < 0.0, ids);
        if hidden_inside(front, ids) {
            continue;
        }
        let texel = visibility_texel(world, normal, s.ids.y, ids, depth, s.uv.xy + local, front);
        out.normal = texel.normal;
        out.ids = texel.ids;
        out.uv = texel.uv;
        out.depth = depth;
        // Analytic coverage of a pixel on a trimmed edge, as `trim_fragment` gives it (where
        // the derivatives are this hit's).
        if COVERAGE && TRIM_TEST && steady && (i == 0u) && ((out.ids.z & SECTION_CAP) == 0u) {
            out.normal.z = clamp(0.5 + trim_edge_pixels(s.ids.z, local, jx, jy), 0.5, 1.0);
        }
        return out;
    }
    discard;
}
