// Quadrics cut by planes (seed 001), ray cast per pixel: the analytic back-end's third kind
// (before analytic.wgsl, which draws their proxies and writes their texels).
//
// A record holds the quadric Σ λᵢ zᵢ² + 2 bᵀz + c and its planes in its box's frame (z of
// the primitive's size), the screen rectangle that bounds it (computed on the CPU in f64: its
// box's corners, and for an ellipsoid its dual quadric, Sigg et al. 2006) and the pixel's ray
// as an affine function of the pixel's device coordinates (`analytic::pixel_ray`): exact to a
// fraction of a pixel at any magnification, where a ray from the eye in f32 is not.

@group(0) @binding(3) var<storage, read> quadric_planes: array<vec4<f32>>;

// `Primitive.kind` (analytic::PRIMITIVE_QUADRIC_*).
const PRIMITIVE_QUADRIC_PATCH: u32 = 2u;
const PRIMITIVE_QUADRIC_VOLUME: u32 = 3u;

// Stands for ±∞ along a ray.
const QUADRIC_FAR: f32 = 1e30;

fn is_quadric(p: Primitive) -> bool {
    return p.kind == PRIMITIVE_QUADRIC_PATCH || p.kind == PRIMITIVE_QUADRIC_VOLUME;
}

// Corner `vi` (0..6: two triangles) of the quadric's screen rectangle, in clip space; the
// other proxy vertices collapse onto its first corner. Two pixels of margin.
fn quadric_proxy(p: Primitive, vi: u32) -> vec4<f32> {
    let margin = 4.0 / frame.viewport.xy;
    let lo = clamp(p.screen.xy - margin, vec2<f32>(-1.0), vec2<f32>(1.0));
    let hi = clamp(p.screen.zw + margin, vec2<f32>(-1.0), vec2<f32>(1.0));
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0),
        vec2<f32>(1.0, 0.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, 0.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, 1.0),
    )[min(vi, 5u)];
    let xy = select(lo, mix(lo, hi, corner), vi < 6u);
    // Any depth inside the view volume: the hit's depth is written.
    return vec4<f32>(xy, 0.5, 1.0);
}

// The pixel's ray in the quadric's box frame: the point `o` at the view depth of the box's
// centre and the direction `d` (view depth grows by 1 per unit).
struct QuadricRay {
    o: vec3<f32>,
    d: vec3<f32>,
}

fn quadric_ray(p: Primitive, pixel: vec2<f32>) -> QuadricRay {
    let ndc = vec2<f32>(2.0 * pixel.x / frame.viewport.x - 1.0, 1.0 - 2.0 * pixel.y / frame.viewport.y);
    let o = p.ray[0].xyz + ndc.x * p.ray[1].xyz + ndc.y * p.ray[2].xyz;
    let d = p.ray[3].xyz + ndc.x * p.ray[4].xyz + ndc.y * p.ray[5].xyz;
    return QuadricRay(o, d);
}

// The reverse-Z depth at ray parameter `s` (-1 behind the eye).
fn quadric_depth(p: Primitive, s: f32) -> f32 {
    let perspective = frame.modes.x != PROJECTION_ORTHOGRAPHIC;
    let w = select(1.0, p.depth.x + s, perspective);
    return select(-1.0, (p.depth.y - p.depth.z * s) / w, w > 0.0);
}

// A boundary point of the primitive along the ray: its parameter and what it lies on
// (-1 the quadric, k ≥ 0 plane k).
struct QuadricCandidate {
    s: f32,
    on: i32,
}

// The `layer`-th boundary point (0 the nearest) in front of the near plane and not cut away
// by a section plane, as `found`, its ray parameter, its reverse-Z depth and its normal in the
// box frame (the quadric's gradient, or the plane's normal).
struct QuadricHit {
    found: bool,
    s: f32,
    depth: f32,
    n: vec3<f32>,
    // Functions of the pixel whose zeros are the boundaries about the hit, positive on the
    // hit's side: the ray's discriminant (its zeros, the silhouette conic) and, on a patch,
    // the nearest plane's margin at the hit (its zeros, the cut edges); their screen
    // derivatives give the pixel's distance to them (F / |∇F|, the analytic coverage); and
    // which boundary point it is (the margin's derivatives hold only where the neighbours
    // show the same one: the candidate's rank and what it lies on).
    edge: vec3<f32>,
}

// What a quadric of the record keeps of the ray: the boundary points, ascending, of the patch
// (roots within every plane; where the front root is cut away the back one shows) or of the
// volume (ends of the intervals inside Q ≤ 0 and every plane).
fn quadric_hit(p: Primitive, ray: QuadricRay, layer: u32) -> QuadricHit {
    let lambda = p.size.xyz;
    let b = p.linear.xyz;
    let c = p.size.w;
    // From the ray's point nearest the box's centre, so C holds no large cancelling terms.
    let s0 = -dot(ray.o, ray.d) / dot(ray.d, ray.d);
    let o = ray.o + s0 * ray.d;
    let d = ray.d;
    let qa = dot(lambda, d * d);
    let qb = dot(lambda, o * d) + dot(b, d);
    let qc = dot(lambda, o * o) + 2.0 * dot(b, o) + c;
    // A hit's side of the silhouette: the discriminant, scaled so that it does not
    // underflow for tiny quadrics (only its zero and its sign matter).
    let disc_edge = select(QUADRIC_FAR, (qb * qb - qa * qc) / max(qa * qa, 1e-30), p.linear.w > 0.5);
    // Roots, ascending, in the ray's own parameter.
    var roots = vec2<f32>(0.0);
    var count = 0u;
    if qa == 0.0 {
        if qb != 0.0 {
            roots = vec2<f32>(s0 - qc / (2.0 * qb));
            count = 1u;
        }
    } else {
        let disc = qb * qb - qa * qc;
        if disc >= 0.0 {
            let q = -(qb + select(-1.0, 1.0, qb >= 0.0) * sqrt(disc));
            if q == 0.0 {
                roots = vec2<f32>(s0);
                count = 1u;
            } else {
                let t0 = q / qa;
                let t1 = qc / q;
                roots = s0 + vec2<f32>(min(t0, t1), max(t0, t1));
                count = 2u;
            }
        }
    }
    // The interval every plane keeps, and the planes ending it.
    var enter = QuadricCandidate(-QUADRIC_FAR, -1);
    var leave = QuadricCandidate(QUADRIC_FAR, -1);
    for (var k = 0u; k < p.planes.y; k++) {
        let plane = quadric_planes[p.planes.x + k];
        let v = dot(plane.xyz, ray.o) + plane.w;
        let towards = dot(plane.xyz, d);
        if towards == 0.0 {
            if v > 0.0 {
                leave.s = -QUADRIC_FAR;
            }
        } else {
            let t = -v / towards;
            if towards > 0.0 && t < leave.s {
                leave = QuadricCandidate(t, i32(k));
            } else if towards < 0.0 && t > enter.s {
                enter = QuadricCandidate(t, i32(k));
            }
        }
    }
    // Up to four boundary points, ascending.
    var list: array<QuadricCandidate, 4>;
    var n = 0u;
    if enter.s <= leave.s {
        if p.kind == PRIMITIVE_QUADRIC_PATCH {
            for (var i = 0u; i < count; i++) {
                if roots[i] >= enter.s && roots[i] <= leave.s {
                    list[n] = QuadricCandidate(roots[i], -1);
                    n += 1u;
                }
            }
        } else {
            // The intervals inside Q ≤ 0: [r0, r1] when A > 0, outside them when A < 0, all
            // or nothing without roots, a half-line for a linear ray.
            var inside: array<vec2<f32>, 2>;
            var m = 0u;
            let all = vec2<f32>(-QUADRIC_FAR, QUADRIC_FAR);
            if count == 0u {
                if qa < 0.0 || (qa == 0.0 && qc <= 0.0) {
                    inside[0] = all;
                    m = 1u;
                }
            } else if count == 1u && qa == 0.0 {
                inside[0] = select(vec2<f32>(roots.x, QUADRIC_FAR), vec2<f32>(-QUADRIC_FAR, roots.x), qb > 0.0);
                m = 1u;
            } else if count == 1u {
                if qa < 0.0 {
                    inside[0] = all;
                    m = 1u;
                }
            } else if qa > 0.0 {
                inside[0] = roots;
                m = 1u;
            } else {
                inside[0] = vec2<f32>(-QUADRIC_FAR, roots.x);
                inside[1] = vec2<f32>(roots.y, QUADRIC_FAR);
                m = 2u;
            }
            for (var i = 0u; i < m; i++) {
                var start = enter;
                if inside[i].x >= enter.s {
                    start = QuadricCandidate(inside[i].x, -1);
                }
                var end = leave;
                if inside[i].y <= leave.s {
                    end = QuadricCandidate(inside[i].y, -1);
                }
                if start.s <= end.s {
                    list[n] = start;
                    list[n + 1u] = end;
                    n += 2u;
                }
            }
        }
    }
    var seen = 0u;
    for (var i = 0u; i < n; i++) {
        let s = list[i].s;
        if abs(s) >= 0.5 * QUADRIC_FAR {
            continue;
        }
        let depth = quadric_depth(p, s);
        let local = ray.o + s * d;
        let world = (p.model * vec4<f32>(local, 1.0)).xyz;
        // In front of the near plane (reverse Z: depth ≤ 1) and not behind the eye.
        if depth < 0.0 || depth > 1.0 || section_cut(world) {
            continue;
        }
        if seen == layer {
            var normal = 2.0 * (lambda * local + b);
            if list[i].on >= 0 {
                normal = quadric_planes[p.planes.x + u32(list[i].on)].xyz;
            }
            // The nearest cut edge of a patch (a volume's plane faces meet the quadric along
            // edges that are not silhouettes: left to supersampling).
            var margin = QUADRIC_FAR;
            if p.kind == PRIMITIVE_QUADRIC_PATCH {
                for (var k = 0u; k < p.planes.y; k++) {
                    let plane = quadric_planes[p.planes.x + k];
                    margin = min(margin, -(dot(plane.xyz, local) + plane.w));
                }
            }
            let which = f32(i) + 8.0 * f32(list[i].on + 1);
            // A volume's plane face goes on across the quadric's silhouette.
            let silhouette = select(QUADRIC_FAR, disc_edge, list[i].on < 0);
            return QuadricHit(true, s, depth, normal, vec3<f32>(silhouette, margin, which));
        }
        seen += 1u;
    }
    return QuadricHit(false, 0.0, 0.0, vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(disc_edge, 0.0, -1.0));
}
