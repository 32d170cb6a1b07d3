// Trim back-end, B-spline surfaces (render shader only): the point and normal of a packed
// (rational) B-spline (`TrimScene::bspline_data`: degrees and net size as u32 bits, knots,
// homogeneous control points row by row along u), by its basis functions and their first
// derivatives (*The NURBS Book* A2.2, and eq. 2.9 from the degree below).
// `trim_surfaces::packed_bspline_point` is the CPU twin.

const SURFACE_BSPLINE: u32 = 5u;
// Basis functions per direction: degrees up to 15 (`trim_surfaces::MAX_BSPLINE_DEGREE`).
const BSPLINE_WIDTH: u32 = 16u;

// The non-zero basis functions at a parameter and their first derivatives.
struct Basis {
    n: array<f32, 16>,
    d: array<f32, 16>,
}

fn knot(at: u32) -> f32 {
    return trim_bspline[at];
}

// The knot span of `t` among the `n` control points' knots at `at` (degree `p`): the largest
// i in [p, n − 1] with knots[i] ≤ t, moved off empty spans (a parameter past either end
// extends the end piece).
fn bspline_span(at: u32, n: u32, p: u32, t: f32) -> u32 {
    var lo = p;
    var hi = n;
    // knots[lo] ≤ t < knots[hi] (clamped), halved: at most 32 steps.
    for (var k = 0u; k < 32u; k++) {
        if hi - lo <= 1u {
            break;
        }
        let mid = (lo + hi) / 2u;
        let below = knot(at + mid) <= t;
        lo = select(lo, mid, below);
        hi = select(mid, hi, below);
    }
    var span = lo;
    for (var k = 0u; k < n; k++) {
        if (span >= n - 1u) | (knot(at + span) < knot(at + span + 1u)) {
            break;
        }
        span += 1u;
    }
    for (var k = 0u; k < n; k++) {
        if (span <= p) | (knot(at + span) < knot(at + span + 1u)) {
            break;
        }
        span -= 1u;
    }
    return span;
}

// `a / b`, 0 where `b` is 0 (a repeated knot), without forming the infinity: a CPU
// rasterizer's fast-math code may not keep a `select` from an infinite operand.
fn ratio(a: f32, b: f32) -> f32 {
    let zero = b == 0.0;
    return select(a, 0.0, zero) / select(b, 1.0, zero);
}

// The degree-`p` basis functions non-zero on `span` at `t`, and their derivatives.
fn bspline_basis(at: u32, span: u32, p: u32, t: f32) -> Basis {
    var left: array<f32, 16>;
    var right: array<f32, 16>;
    var out: Basis;
    // The degree-(p − 1) functions, for the derivatives.
    var below: array<f32, 16>;
    out.n[0] = 1.0;
    for (var j = 1u; j <= min(p, BSPLINE_WIDTH - 1u); j++) {
        left[j] = t - knot(at + span + 1u - j);
        right[j] = knot(at + span + j) - t;
        if j == p {
            for (var k = 0u; k < j; k++) {
                below[k] = out.n[k];
            }
        }
        var saved = 0.0;
        for (var r = 0u; r < j; r++) {
            let den = right[r + 1u] + left[j - r];
            let temp = ratio(out.n[r], den);
            out.n[r] = saved + right[r + 1u] * temp;
            saved = left[j - r] * temp;
        }
        out.n[j] = saved;
    }
    // N'_{i,p} = p (N_{i,p−1} / (u_{i+p} − u_i) − N_{i+1,p−1} / (u_{i+p+1} − u_{i+1})),
    // i = span − p + r; below[k] is N_{span−p+1+k, p−1}.
    for (var r = 0u; r <= min(p, BSPLINE_WIDTH - 1u); r++) {
        let i = span - p + r;
        var d = 0.0;
        if r >= 1u {
            let den = knot(at + i + p) - knot(at + i);
            d += ratio(below[r - 1u], den);
        }
        if r < p {
            let den = knot(at + i + p + 1u) - knot(at + i + 1u);
            d -= ratio(below[r], den);
        }
        out.d[r] = f32(p) * d;
    }
    return out;
}

// The point of the packed B-spline at `at` and its S_u × S_v.
fn bspline_point(at: u32, uv: vec2<f32>) -> SurfacePoint {
    let p = bitcast<u32>(trim_bspline[at]);
    let q = bitcast<u32>(trim_bspline[at + 1u]);
    let nu = bitcast<u32>(trim_bspline[at + 2u]);
    let nv = bitcast<u32>(trim_bspline[at + 3u]);
    let ku = at + 4u;
    let kv = ku + nu + p + 1u;
    let cp = kv + nv + q + 1u;
    let su = bspline_span(ku, nu, p, uv.x);
    let sv = bspline_span(kv, nv, q, uv.y);
    let bu = bspline_basis(ku, su, p, uv.x);
    let bv = bspline_basis(kv, sv, q, uv.y);
    var s = vec4<f32>(0.0);
    var s_u = vec4<f32>(0.0);
    var s_v = vec4<f32>(0.0);
    for (var r = 0u; r <= min(p, BSPLINE_WIDTH - 1u); r++) {
        for (var t = 0u; t <= min(q, BSPLINE_WIDTH - 1u); t++) {
            let k = cp + 4u * ((su - p + r) * nv + sv - q + t);
            let c = vec4<f32>(trim_bspline[k], trim_bspline[k + 1u], trim_bspline[k + 2u], trim_bspline[k + 3u]);
            s += (bu.n[r] * bv.n[t]) * c;
            s_u += (bu.d[r] * bv.n[t]) * c;
            s_v += (bu.n[r] * bv.d[t]) * c;
        }
    }
    var out: SurfacePoint;
    let w = select(s.w, 1e-30, s.w == 0.0);
    out.position = s.xyz / w;
    // The quotient rule: (A' − w' S) / w.
    let du = (s_u.xyz - s_u.w * out.position) / w;
    let dv = (s_v.xyz - s_v.w * out.position) / w;
    out.normal = cross(du, dv);
    return out;
}

// The point of face record `s`'s surface at `local`, its parameters from the lower corner of
// the record's (u, v) box: its closed form, its B-spline or its sweep.
fn face_point(s: TrimSurface, local: vec2<f32>) -> SurfacePoint {
    let uv = s.uv.xy + local;
    if s.ids.x == SURFACE_BSPLINE {
        // The control points are packed relative to the record's origin (`pack_bspline`),
        // so that a face far from its mesh's origin keeps f32's precision.
        var point = bspline_point(s.ids.w, uv);
        point.position += s.origin.xyz;
        return point;
    }
    if (s.ids.x == SURFACE_EXTRUSION) | (s.ids.x == SURFACE_REVOLUTION) {
        return sweep_point(s, uv);
    }
    return surface_point(s, local);
}
