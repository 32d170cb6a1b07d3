// Trim back-end, swept surfaces (render shader only): surfaces of linear extrusion
// S = c + C(u) + v d (d: the record's axis_z) and of revolution S = c + R_a(u) C(v) (a: its
// unit axis_z), c the record's origin (a point near the face; on a revolution's axis), from
// their profile C, relative to c, packed at the record's data offset in `trim_bspline`
// behind a kind word: a (rational) B-spline curve (degree, control points, knots,
// homogeneous control points), a line o + t X or an ellipse o + cos t X + sin t Y (nine
// numbers o, X, Y). `trim_sweeps::sweep_point` is the CPU twin.

const SURFACE_EXTRUSION: u32 = 6u;
const SURFACE_REVOLUTION: u32 = 7u;
const PROFILE_BSPLINE: u32 = 0u;
const PROFILE_LINE: u32 = 1u;

// A profile's point and first derivative.
struct ProfilePoint {
    position: vec3<f32>,
    tangent: vec3<f32>,
}

fn packed_vector(at: u32) -> vec3<f32> {
    return vec3<f32>(trim_bspline[at], trim_bspline[at + 1u], trim_bspline[at + 2u]);
}

fn profile_point(at: u32, t: f32) -> ProfilePoint {
    let kind = bitcast<u32>(trim_bspline[at]);
    var out: ProfilePoint;
    if kind == PROFILE_BSPLINE {
        let p = bitcast<u32>(trim_bspline[at + 1u]);
        let n = bitcast<u32>(trim_bspline[at + 2u]);
        let knots = at + 3u;
        let cp = knots + n + p + 1u;
        let span = bspline_span(knots, n, p, t);
        let b = bspline_basis(knots, span, p, t);
        var c = vec4<f32>(0.0);
        var d = vec4<f32>(0.0);
        for (var r = 0u; r <= min(p, BSPLINE_WIDTH - 1u); r++) {
            let k = cp + 4u * (span - p + r);
            let h = vec4<f32>(trim_bspline[k], trim_bspline[k + 1u], trim_bspline[k + 2u], trim_bspline[k + 3u]);
            c += b.n[r] * h;
            d += b.d[r] * h;
        }
        let w = select(c.w, 1e-30, c.w == 0.0);
        out.position = c.xyz / w;
        // The quotient rule: (A' − w' C) / w.
        out.tangent = (d.xyz - d.w * out.position) / w;
        return out;
    }
    let o = packed_vector(at + 1u);
    let x = packed_vector(at + 4u);
    if kind == PROFILE_LINE {
        out.position = o + t * x;
        out.tangent = x;
        return out;
    }
    let y = packed_vector(at + 7u);
    out.position = o + cos(t) * x + sin(t) * y;
    out.tangent = cos(t) * y - sin(t) * x;
    return out;
}

// `q` turned by `angle` about the unit axis `a` (Rodrigues).
fn rotate_about(q: vec3<f32>, a: vec3<f32>, angle: f32) -> vec3<f32> {
    let c = cos(angle);
    return q * c + cross(a, q) * sin(angle) + a * (dot(a, q) * (1.0 - c));
}

// The point of swept face `s` at `uv` and its S_u × S_v. On a revolution's axis (a profile
// meeting it: a dome's pole), where S_u vanishes, the direction is taken a ten-thousandth
// of the box towards its middle: the limit of the normals about the pole.
fn sweep_point(s: TrimSurface, uv: vec2<f32>) -> SurfacePoint {
    var out: SurfacePoint;
    let axis = s.axis_z.xyz;
    let centre = s.origin.xyz;
    if s.ids.x == SURFACE_EXTRUSION {
        let c = profile_point(s.ids.w, uv.x);
        out.position = centre + c.position + uv.y * axis;
        out.normal = cross(c.tangent, axis);
        return out;
    }
    let c = profile_point(s.ids.w, uv.y);
    let q = rotate_about(c.position, axis, uv.x);
    var su = cross(axis, q);
    var sv = rotate_about(c.tangent, axis, uv.x);
    out.position = centre + q;
    if length(su) <= 1e-5 * length(q) {
        let middle = s.uv.y + 0.5 * s.uv.w;
        let v = uv.y + 1e-4 * s.uv.w * select(1.0, -1.0, middle < uv.y);
        let near = profile_point(s.ids.w, v);
        su = cross(axis, rotate_about(near.position, axis, uv.x));
        sv = rotate_about(near.tangent, axis, uv.x);
    }
    out.normal = cross(su, sv);
    return out;
}
