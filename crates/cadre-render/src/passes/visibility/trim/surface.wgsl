// Trim back-end, shared by its compute and render shaders: a face's record (`TrimSurface`,
// `layout.rs`), its grid's spans, and its support surface evaluated in closed form
// (`trim_surfaces.rs`'s `closed_form_point` is the CPU twin). The includer declares
// `trim_bspline: array<f32>` (`TrimScene::bspline_data`).

struct TrimSurface {
    origin: vec4<f32>,
    axis_x: vec4<f32>,
    axis_y: vec4<f32>,
    axis_z: vec4<f32>,
    uv: vec4<f32>,
    sphere: vec4<f32>,
    curvature: vec4<f32>,
    ids: vec4<u32>,
}

struct TrimTask {
    surface: u32,
    record: u32,
    locals_first: u32,
    locals_count: u32,
    instances: u32,
    slot: u32,
    near: f32,
    pad: u32,
}

// `layout::TrimCall`: a trim draw's call, for the exact crack fill's seeded solves.
struct TrimCall {
    first_surface: u32,
    faces: u32,
    record: u32,
    locals_first: u32,
    locals_count: u32,
    instances: u32,
    pad: vec2<u32>,
}

// `trim_surfaces::SURFACE_*`.
const SURFACE_PLANE: u32 = 0u;
const SURFACE_CYLINDER: u32 = 1u;
const SURFACE_CONE: u32 = 2u;
const SURFACE_SPHERE: u32 = 3u;
const SURFACE_TORUS: u32 = 4u;

// Vertices reserved for each face of a draw (`trim::TRIM_VERTICES`): 6 per cell of the
// largest grid, 256² cells (tessellate.wgsl's `MAX_LEVEL` at most).
const TRIM_VERTICES: u32 = 393216u;

// Plane, cylinder, cone, sphere and ring torus faces are ray cast, not tessellated
// (raycast.wgsl; `TrimVariant::ray_cast`, `--method raycast`).
override RAYCAST: bool = false;

// Whether face `s` is ray cast: the quadrics, and the tori whose tube does not reach their
// axis (R > |r|; a spindle torus's inner sheet is tessellated).
fn is_ray_cast(s: TrimSurface) -> bool {
    let ring_torus = (s.ids.x == SURFACE_TORUS) && (s.origin.w > abs(s.axis_x.w));
    return RAYCAST && ((s.ids.x <= SURFACE_SPHERE) || ring_torus);
}

// A task whose grid points found no room in `grid_points` (tessellate.wgsl).
const NO_POINTS: u32 = 0xffffffffu;

// `TrimFaceSurface::breaks` of a face drawn as one span each way.
const NO_BREAKS: u32 = 0xffffffffu;

// Where the trim verdict of cell `cell` of a grid of `lines` cells each way lies in the grid
// points' buffer (`grid_points`, vec4s) whose points start at point `base`: after the grid's
// (lines + 1)² points, eight verdicts a point's room (two vec4s), one a component, stored as
// an `f32` value (0, 1, 2: `TRIM_CELL_*`). x: the vec4's index; y: the component.
fn verdict_slot(base: u32, lines: vec2<u32>, cell: u32) -> vec2<u32> {
    let points = (lines.x + 1u) * (lines.y + 1u);
    return vec2<u32>(2u * (base + points) + cell / 4u, cell % 4u);
}

// The spans of face `s`'s grid along u and v (its knot lines within its box; one span each
// way for the closed forms).
fn grid_spans(s: TrimSurface) -> vec2<u32> {
    let at = bitcast<u32>(s.curvature.w);
    if at == NO_BREAKS {
        return vec2<u32>(1u);
    }
    return vec2<u32>(bitcast<u32>(trim_bspline[at]), bitcast<u32>(trim_bspline[at + 1u]));
}

// Breakpoint `k` (0 to the span count) along `axis` (0: u, 1: v) from the box's lower corner.
fn grid_break(s: TrimSurface, spans: vec2<u32>, axis: u32, k: u32) -> f32 {
    let at = bitcast<u32>(s.curvature.w);
    if at == NO_BREAKS {
        return select(0.0, s.uv[2u + axis], k > 0u);
    }
    return trim_bspline[at + 2u + select(0u, spans.x + 1u, axis == 1u) + k];
}

// The face-local parameter of grid line `g` along `axis`, with `per` cells in each span.
fn grid_param(s: TrimSurface, spans: vec2<u32>, axis: u32, g: u32, per: u32) -> f32 {
    let span = min(g / per, spans[axis] - 1u);
    let f = f32(g - span * per) / f32(per);
    return mix(grid_break(s, spans, axis, span), grid_break(s, spans, axis, span + 1u), f);
}

// A point of a surface and the direction of its normal S_u × S_v (any length; the poles of
// spheres and tori and the cone's apex, where S_u × S_v vanishes, get the limit direction).
struct SurfacePoint {
    position: vec3<f32>,
    normal: vec3<f32>,
}

// `local`: the parameters from the lower corner of the record's (u, v) box. The linear ones
// (a plane's u and v, a cylinder's or cone's v) are taken from there, the record's frame
// and a cone's radius being moved to that corner (`trim_surfaces::closed_form`): a plane
// whose frame lies 1,661 mm from its face has parameters in the thousands, which f32 holds
// to 0.12 µm; the angles are absolute.
fn surface_point(s: TrimSurface, local: vec2<f32>) -> SurfacePoint {
    let uv = s.uv.xy + local;
    let x = s.axis_x.xyz;
    let y = s.axis_y.xyz;
    let z = s.axis_z.xyz;
    let a = s.origin.w;
    let b = s.axis_x.w;
    let cu = cos(uv.x);
    let su = sin(uv.x);
    let cv = cos(uv.y);
    let sv = sin(uv.y);
    // The unit radial direction at u, and its derivative (radial × tangent = z).
    let radial = cu * x + su * y;
    var out: SurfacePoint;
    switch s.ids.x {
        case SURFACE_PLANE: {
            out.position = local.x * x + local.y * y;
            out.normal = z;
        }
        case SURFACE_CYLINDER: {
            out.position = a * radial + local.y * z;
            out.normal = a * radial;
        }
        case SURFACE_CONE: {
            let rho = a + local.y * b;
            out.position = rho * radial + local.y * z;
            // The nappe the face lies on, from the middle of its box: at the apex row ρ
            // rounds to either sign, and a per-point sign turned the apex's normals round
            // (the cells about the apex were lit as the cone's inside).
            let side = a + 0.5 * s.uv.w * b;
            out.normal = select(1.0, -1.0, side < 0.0) * (radial - b * z);
        }
        case SURFACE_SPHERE: {
            out.position = a * (cv * radial + sv * z);
            out.normal = select(1.0, -1.0, a < 0.0) * (cv * radial + sv * z);
        }
        default: {
            // Torus: S_u × S_v = (R + r cos v) r (cos v radial + sin v z).
            out.position = (a + b * cv) * radial + b * sv * z;
            out.normal = select(1.0, -1.0, (a + b * cv) * b < 0.0) * (cv * radial + sv * z);
        }
    }
    out.position += s.origin.xyz;
    return out;
}
