// Analytic faces ray cast (seed 001 for B-Rep faces, `--method raycast`): a plane, cylinder,
// cone or sphere face is not tessellated; its proxy is the box of the face in its surface's
// frame (36 vertices, `ray_cast_vertex`), and each proxy fragment casts the pixel's ray
// against the support quadric in closed form, takes the hit's (u, v) and keeps the nearest
// hit that the face's trim tree keeps (`cast_face`, then trim.wgsl's `fs_raycast`): exact
// silhouettes and trimmed edges at any zoom, and a few bytes a face instead of its mesh.
// Coordinates here are the surface frame's: along `axis_x`, `axis_y`, `axis_z` from
// `origin` (the frame moved to the (u, v) box's corner for the linear parameters, as
// `surface_point` reads them).

// A face's box in its frame's coordinates: low and high corners.
struct FaceBox {
    lo: vec3<f32>,
    hi: vec3<f32>,
}

// The box of the unit circle's arc from angle `u0` over `span` (≤ 2π): its endpoints and
// the axis extremes it passes.
fn arc_box(u0: f32, span: f32) -> vec4<f32> {
    let quarter = 1.5707963267948966;
    var lo = min(vec2<f32>(cos(u0), sin(u0)), vec2<f32>(cos(u0 + span), sin(u0 + span)));
    var hi = max(vec2<f32>(cos(u0), sin(u0)), vec2<f32>(cos(u0 + span), sin(u0 + span)));
    let first = ceil(u0 / quarter);
    for (var k = 0u; k < 5u; k++) {
        let a = (first + f32(k)) * quarter;
        if a > u0 + span {
            break;
        }
        let p = vec2<f32>(cos(a), sin(a));
        // Exactly on an axis: the extremes are ±1, 0.
        let q = round(p);
        lo = min(lo, q);
        hi = max(hi, q);
    }
    return vec4<f32>(lo, hi);
}

// The face's box (its (u, v) box mapped to the frame), a hair wider than the surface.
fn face_box(s: TrimSurface) -> FaceBox {
    let a = s.origin.w;
    let b = s.axis_x.w;
    let size = s.uv.zw;
    var lo = vec3<f32>(0.0);
    var hi = vec3<f32>(0.0);
    switch s.ids.x {
        case SURFACE_PLANE: {
            lo = vec3<f32>(0.0, 0.0, 0.0);
            hi = vec3<f32>(size, 0.0);
        }
        case SURFACE_CYLINDER: {
            let arc = arc_box(s.uv.x, size.x) * abs(a);
            lo = vec3<f32>(arc.xy, 0.0);
            hi = vec3<f32>(arc.zw, size.y);
        }
        case SURFACE_CONE: {
            // The arc at both ends' (signed) radii; the axis too where the apex is within.
            let arc = arc_box(s.uv.x, size.x);
            let r0 = a;
            let r1 = a + b * size.y;
            let ends = array<vec2<f32>, 4>(arc.xy * r0, arc.zw * r0, arc.xy * r1, arc.zw * r1);
            var l = min(min(ends[0], ends[1]), min(ends[2], ends[3]));
            var h = max(max(ends[0], ends[1]), max(ends[2], ends[3]));
            if r0 * r1 <= 0.0 {
                l = min(l, vec2<f32>(0.0));
                h = max(h, vec2<f32>(0.0));
            }
            lo = vec3<f32>(l, 0.0);
            hi = vec3<f32>(h, size.y);
        }
        case SURFACE_TORUS: {
            // The arc's box at the least and greatest distance from the axis over the
            // latitudes (ρ = R + r cos v), and the heights r sin v.
            let arc = arc_box(s.uv.x, size.x);
            let meridian = arc_box(s.uv.y, size.y);
            let rho = vec2<f32>(a + b * meridian.x, a + b * meridian.z);
            let r_lo = min(rho.x, rho.y);
            let r_hi = max(rho.x, rho.y);
            let ends = array<vec2<f32>, 4>(arc.xy * r_lo, arc.zw * r_lo, arc.xy * r_hi, arc.zw * r_hi);
            let heights = vec2<f32>(b * meridian.y, b * meridian.w);
            lo = vec3<f32>(min(min(ends[0], ends[1]), min(ends[2], ends[3])), min(heights.x, heights.y));
            hi = vec3<f32>(max(max(ends[0], ends[1]), max(ends[2], ends[3])), max(heights.x, heights.y));
        }
        default: {
            // Sphere: the arc's box scaled by the cosine's range over the latitudes, and
            // the sines' range along the axis.
            let r = abs(a);
            let arc = arc_box(s.uv.x, size.x);
            let v0 = s.uv.y;
            let v1 = s.uv.y + size.y;
            let c_lo = min(cos(v0), cos(v1));
            let c_hi = select(max(cos(v0), cos(v1)), 1.0, v0 <= 0.0 && v1 >= 0.0);
            let ends = array<vec2<f32>, 4>(arc.xy * c_lo, arc.zw * c_lo, arc.xy * c_hi, arc.zw * c_hi);
            lo = vec3<f32>(min(min(ends[0], ends[1]), min(ends[2], ends[3])) * r, r * sin(v0));
            hi = vec3<f32>(max(max(ends[0], ends[1]), max(ends[2], ends[3])) * r, r * sin(v1));
        }
    }
    let margin = 1e-4 * max(length(hi - lo), abs(a) + abs(b) * f32(s.ids.x == SURFACE_TORUS)) + 1e-6;
    return FaceBox(lo - margin, hi + margin);
}

// The inverse of an invertible 3×3 matrix (cofactors; WGSL has no inverse).
fn inverse3(m: mat3x3<f32>) -> mat3x3<f32> {
    let c0 = cross(m[1], m[2]);
    let c1 = cross(m[2], m[0]);
    let c2 = cross(m[0], m[1]);
    let det = dot(m[0], c0);
    return transpose(mat3x3<f32>(c0, c1, c2)) * (1.0 / det);
}

// What the proxy's vertices hand the fragments: the proxy point and the eye (w = 1) or the
// view direction (w = 0, orthographic) in the frame's coordinates, and the view-space images
// of the frame's axes (for the normals).
struct RayFrame {
    point: vec3<f32>,
    eye: vec4<f32>,
    normal_x: vec3<f32>,
    normal_y: vec3<f32>,
    normal_z: vec3<f32>,
}

// Corner `corner` (0..36) of face `s`'s box as placed by `d`, and its ray frame.
fn ray_cast_corner(s: TrimSurface, d: Draw, corner: u32) -> RayFrame {
    let b = face_box(s);
    let c = mix(b.lo, b.hi, cube_corner(corner) * 0.5 + 0.5);
    let x = s.axis_x.xyz;
    let y = s.axis_y.xyz;
    let z = s.axis_z.xyz;
    let inv = inverse3(mat3x3<f32>(d.model[0].xyz, d.model[1].xyz, d.model[2].xyz));
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    // The eye (the camera-relative origin) or the view direction, in the mesh's frame.
    let mesh = select(inv * (-d.model[3].xyz) - s.origin.xyz, inv * frame.forward.xyz, ortho);
    let normals = mat3x3<f32>(d.normal[0].xyz, d.normal[1].xyz, d.normal[2].xyz);
    var out: RayFrame;
    out.point = c;
    out.eye = vec4<f32>(dot(mesh, x), dot(mesh, y), dot(mesh, z), select(1.0, 0.0, ortho));
    out.normal_x = normals * x;
    out.normal_y = normals * y;
    out.normal_z = normals * z;
    return out;
}

// The hits of a ray on a face's support surface, nearest first: ray parameter, (u, v) from
// the box's corner, and the surface's normal (frame coordinates, any length, oriented as
// `surface_point`'s).
struct FaceCast {
    count: u32,
    t: array<f32, TORUS_HITS>,
    local: array<vec2<f32>, TORUS_HITS>,
    n: array<vec3<f32>, TORUS_HITS>,
}

// Hits a ray can have on a face's support surface: two on a quadric, four on a torus.
const TORUS_HITS: u32 = 4u;

// The angle of (x, y) from the box's first angle, in [−(2π − span) / 2, span + (2π − span) / 2):
// within the box on the face, just outside it (negative or past the span) near its ends.
fn box_angle(s: TrimSurface, p: vec2<f32>) -> f32 {
    let tau = 6.283185307179586;
    var w = atan2(p.y, p.x) - s.uv.x;
    w -= floor(w / tau) * tau;
    return select(w, w - tau, w > 0.5 * (s.uv.z + tau));
}

// The ray o + t d (frame coordinates; perspective: t = 1 at the proxy point) against face
// `s`'s support surface.
fn cast_face(s: TrimSurface, o_in: vec3<f32>, d: vec3<f32>) -> FaceCast {
    var out: FaceCast;
    out.count = 0u;
    let a = s.origin.w;
    let b = s.axis_x.w;
    let kind = s.ids.x;
    // From the ray's point nearest the frame's origin (by the box's corner): no large
    // cancelling terms in C when the eye is far.
    let shift = -dot(o_in, d) / max(dot(d, d), 1e-30);
    let o = o_in + shift * d;
    if kind == SURFACE_TORUS {
        return cast_torus(s, o, d, shift);
    }
    var roots = vec2<f32>(0.0);
    var count = 0u;
    if kind == SURFACE_PLANE {
        if d.z != 0.0 {
            roots = vec2<f32>(-o.z / d.z);
            count = 1u;
        }
    } else {
        var qa = 0.0;
        var qb = 0.0;
        var qc = 0.0;
        if kind == SURFACE_CYLINDER {
            qa = dot(d.xy, d.xy);
            qb = dot(o.xy, d.xy);
            qc = dot(o.xy, o.xy) - a * a;
        } else if kind == SURFACE_CONE {
            // x² + y² = (a + b z)².
            let rho = a + b * o.z;
            qa = dot(d.xy, d.xy) - b * b * d.z * d.z;
            qb = dot(o.xy, d.xy) - b * d.z * rho;
            qc = dot(o.xy, o.xy) - rho * rho;
        } else {
            qa = dot(d, d);
            qb = dot(o, d);
            qc = dot(o, o) - a * a;
        }
        if qa == 0.0 {
            if qb != 0.0 {
                roots = vec2<f32>(-qc / (2.0 * qb));
                count = 1u;
            }
        } else {
            let disc = qb * qb - qa * qc;
            if disc >= 0.0 {
                let q = -(qb + select(-1.0, 1.0, qb >= 0.0) * sqrt(disc));
                if q != 0.0 {
                    let t0 = q / qa;
                    let t1 = qc / q;
                    roots = vec2<f32>(min(t0, t1), max(t0, t1));
                    count = 2u;
                }
            }
        }
    }
    for (var i = 0u; i < count; i++) {
        let p = o + roots[i] * d;
        var local = p.xy;
        var n = vec3<f32>(0.0, 0.0, 1.0);
        // A negative radius (a cylinder's or sphere's, or a cone's past its apex) puts the
        // point on the far side of the axis from its angle.
        if kind == SURFACE_CYLINDER {
            local = vec2<f32>(box_angle(s, p.xy * sign(a)), p.z);
            n = vec3<f32>(p.xy, 0.0);
        } else if kind == SURFACE_CONE {
            let rho = a + b * p.z;
            local = vec2<f32>(box_angle(s, p.xy * sign(rho)), p.z);
            n = vec3<f32>(p.xy, -b * rho);
        } else if kind == SURFACE_SPHERE {
            let q = p * sign(a);
            local = vec2<f32>(box_angle(s, q.xy), asin(clamp(q.z / abs(a), -1.0, 1.0)) - s.uv.y);
            n = p / abs(a);
        }
        out.t[i] = shift + roots[i];
        out.local[i] = local;
        out.n[i] = n;
    }
    out.count = count;
    return out;
}

// Most steps of the march along a ray through a torus face's box, and the distance to the
// surface, in pixels, at which a step has reached it.
const TORUS_STEPS: u32 = 192u;
const TORUS_REACHED_PX: f32 = 0.01;

// The exact distance from `p` (frame coordinates) to the torus of radii `a` (major) and `b`
// (minor): to its core circle, less the tube's radius; negative inside the tube.
fn torus_distance(p: vec3<f32>, a: f32, b: f32) -> f32 {
    return length(vec2<f32>(length(p.xy) - a, p.z)) - abs(b);
}

// The distance's gradient at `p` (a unit vector: the tube's outward normal).
fn torus_gradient(p: vec3<f32>, a: f32) -> vec3<f32> {
    let rho = max(length(p.xy), 1e-30);
    return normalize(vec3<f32>(p.xy * ((rho - a) / rho), p.z));
}

// An angle's offset from `start` in [−(2π − span) / 2, span + (2π − span) / 2): within the
// face's box on it, just outside near its ends (as `box_angle` does for u).
fn wrapped_angle(angle: f32, start: f32, span: f32) -> f32 {
    let tau = 6.283185307179586;
    var w = angle - start;
    w -= floor(w / tau) * tau;
    return select(w, w - tau, w > 0.5 * (span + tau));
}

// Hit `sigma` (distance along `dn` from `o`) of torus `s` appended to `out`: its parameter
// on the fragment's ray, (u, v) from the box's corner and the normal S_u × S_v's direction.
fn torus_hit(s: TrimSurface, o: vec3<f32>, dn: vec3<f32>, shift: f32, length_d: f32, sigma: f32, out: ptr<function, FaceCast>) {
    let a = s.origin.w;
    let b = s.axis_x.w;
    let p = o + sigma * dn;
    let rho = max(length(p.xy), 1e-30);
    let cv = (rho - a) / b;
    let sv = p.z / b;
    let i = (*out).count;
    (*out).t[i] = shift + sigma / length_d;
    (*out).local[i] = vec2<f32>(box_angle(s, p.xy), wrapped_angle(atan2(sv, cv), s.uv.y, s.uv.w));
    // surface.wgsl's torus: sign(r) (cos v radial + sin v z) where R + r cos v > 0.
    (*out).n[i] = sign(b) * vec3<f32>(p.xy * (cv / rho), sv);
    (*out).count = i + 1u;
}

// The hits of the ray `o` + t `d` (`o` its point nearest the frame's origin, `shift` the
// parameter of that point on the fragment's ray) on a ring torus (R > |r|) within the face's
// box, nearest first. A torus is of degree four, whose roots `f32` cannot take in closed
// form near a silhouette (a double root), so the ray marches by the exact distance f to the
// surface, which `f32` holds to 10⁻⁷ of the torus, from the box's entry to its exit; each
// approach within `TORUS_REACHED_PX` of a pixel is a hit (the silhouette exact to a
// hundredth of a pixel at any zoom). Outside the tube a step is the longest the distance's
// curvature bound allows: along a line f'' ≥ −1/ρ (ρ the distance to the axis; the
// curvature of the level tori), so f stays positive for x up to the root of
// f + f'·x − x²/(2ρ_min) — Newton's step where the ray meets the surface at an angle,
// √(2ρf) where it grazes it (sphere tracing's safe step, f, would fall by sin θ a step and
// take thousands), and never past the surface. Inside the tube the safe steps lead to the
// exit (the distance to the entry doubles a step).
fn cast_torus(s: TrimSurface, o: vec3<f32>, d: vec3<f32>, shift: f32) -> FaceCast {
    var out: FaceCast;
    out.count = 0u;
    let a = s.origin.w;
    let b = s.axis_x.w;
    let length_d = length(d);
    if length_d == 0.0 {
        return out;
    }
    let dn = d / length_d;
    // The box's entry and exit along the ray (distances from `o`).
    let box = face_box(s);
    let safe = select(vec3<f32>(1e-30), dn, abs(dn) > vec3<f32>(1e-30));
    let t_lo = (box.lo - o) / safe;
    let t_hi = (box.hi - o) / safe;
    let entry = max(max(min(t_lo.x, t_hi.x), min(t_lo.y, t_hi.y)), min(t_lo.z, t_hi.z));
    let exit = min(min(max(t_lo.x, t_hi.x), max(t_lo.y, t_hi.y)), max(t_lo.z, t_hi.z));
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    // Not behind the eye (perspective: the eye is at distance −shift·|d|).
    let eye_at = -shift * length_d;
    var sigma = select(max(entry, eye_at), entry, ortho);
    if exit < sigma {
        return out;
    }
    // A pixel's size in frame units: at a distance from the eye (perspective), or anywhere.
    let angle = 2.0 * frame.inv_proj[1][1] / frame.viewport.y;
    let floor_reach = 1e-7 * (abs(a) + abs(b));
    var armed = true;
    for (var step = 0u; step < TORUS_STEPS; step++) {
        if sigma > exit || out.count == TORUS_HITS {
            break;
        }
        let pixel = angle * select(max(sigma - eye_at, 0.0), length_d, ortho);
        let reach = TORUS_REACHED_PX * pixel + floor_reach;
        let p = o + sigma * dn;
        let f = torus_distance(p, a, b);
        if abs(f) < reach {
            if armed {
                torus_hit(s, o, dn, shift, length_d, sigma, &out);
                armed = false;
            }
            // On past the surface: at least a reach a step.
            sigma += max(abs(f), reach);
            continue;
        }
        // Off the surface by more than a reach: the next approach is a new hit.
        armed = armed || abs(f) > 2.0 * reach;
        var stride = abs(f);
        if f > 0.0 {
            // Within half the distance to the axis, ρ ≥ ρ_min = ρ / 2.
            let rho_min = 0.5 * length(p.xy);
            let slope = dot(torus_gradient(p, a), dn);
            let bound = rho_min * (slope + sqrt(slope * slope + 2.0 * f / max(rho_min, 1e-30)));
            stride = max(f, 0.99 * min(bound, rho_min));
        }
        sigma += stride;
    }
    return out;
}

// The ray of a proxy fragment: origin and direction in frame coordinates.
struct FrameRay {
    o: vec3<f32>,
    d: vec3<f32>,
}

fn frame_ray(point: vec3<f32>, eye: vec4<f32>) -> FrameRay {
    let ortho = eye.w == 0.0;
    return FrameRay(select(eye.xyz, point, ortho), select(point - eye.xyz, eye.xyz, ortho));
}

// The camera-relative point at parameter `t` of the ray through proxy point `world`.
fn ray_world(world: vec3<f32>, eye: vec4<f32>, t: f32) -> vec3<f32> {
    return select(t * world, world + t * frame.forward.xyz, eye.w == 0.0);
}

// A change of (u, v) between neighbouring pixels with the angles taken the short way (a
// full-turn face's parameters jump by 2π across its seam).
fn short_way(s: TrimSurface, j: vec2<f32>) -> vec2<f32> {
    let tau = 6.283185307179586;
    var out = j;
    if s.ids.x != SURFACE_PLANE && abs(out.x) > 0.5 * tau {
        out.x -= sign(out.x) * tau;
    }
    if s.ids.x == SURFACE_TORUS && abs(out.y) > 0.5 * tau {
        out.y -= sign(out.y) * tau;
    }
    return out;
}

// The pixel's footprint in (u, v) at the hit `p` (frame coordinates) of the ray of direction
// `d` through the proxy point `world`: half a pixel over the surface's speeds there (the trim
// test's stop rule, as a tessellated face's derivatives give it). Worked out, not taken from
// the derivatives of (u, v), which jump where a neighbouring pixel misses the surface or
// takes its other root.
fn cast_footprint(s: TrimSurface, p: vec3<f32>, d: vec3<f32>, world: vec3<f32>, eye: vec4<f32>) -> vec2<f32> {
    let ortho = eye.w == 0.0;
    // Frame units per world unit (an instance may scale), and the pixel's world size there.
    let per_world = select(length(d) / max(length(world), 1e-30), length(d), ortho);
    let t_world = select(length(world) * length(p - eye.xyz) / max(length(d), 1e-30), 1.0, ortho);
    let pixel = t_world * 2.0 * frame.inv_proj[1][1] / frame.viewport.y * per_world;
    let a = abs(s.origin.w);
    let b = s.axis_x.w;
    var speed = vec2<f32>(1.0);
    switch s.ids.x {
        case SURFACE_CYLINDER: {
            speed = vec2<f32>(a, 1.0);
        }
        case SURFACE_CONE: {
            speed = vec2<f32>(abs(s.origin.w + b * p.z), sqrt(1.0 + b * b));
        }
        case SURFACE_SPHERE: {
            speed = vec2<f32>(length(p.xy), a);
        }
        case SURFACE_TORUS: {
            speed = vec2<f32>(length(p.xy), abs(b));
        }
        default: {}
    }
    return 0.5 * pixel / max(speed, vec2<f32>(1e-30));
}
