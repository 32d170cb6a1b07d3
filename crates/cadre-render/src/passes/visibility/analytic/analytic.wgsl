// Analytic back-end of the visibility pass: spheres and rectangles ray cast per pixel. Each
// primitive draws a proxy that covers it on screen (a sphere's bounding cube, both sides; a
// rectangle itself), and each proxy fragment casts the pixel's view ray in the primitive's
// own frame, keeps the nearest hit in front of the near plane and outside every section
// plane, writes that hit's depth (not the proxy's) and goes through `visibility_texel`
// (texel.wgsl, before this file) like a mesh fragment.

@group(0) @binding(1) var<storage, read> primitives: array<Primitive>;

// `Primitive.kind` (analytic::PRIMITIVE_*).
const PRIMITIVE_SPHERE: u32 = 0u;
const PRIMITIVE_RECTANGLE: u32 = 1u;

// The hit's depth is written (false only for the tests' negative control: the proxy's
// depth, which is wrong wherever the proxy is not the surface).
override EXACT_DEPTH: bool = true;

struct ProxyOut {
    @builtin(position) clip: vec4<f32>,
    // Camera-relative world position on the proxy: with the eye it gives the pixel's ray.
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) index: u32,
}

struct AnalyticOut {
    @location(0) normal: vec4<f32>,
    @location(1) ids: vec4<u32>,
    @location(2) uv: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

// Corner `vi` (0..36) of the cube [−1, 1]³ as 12 triangles: face `vi / 6` (axis, sign),
// corner `vi % 6` of its two triangles.
fn cube_corner(vi: u32) -> vec3<f32> {
    let face = vi / 6u;
    let quad = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vi % 6u];
    let axis = face / 2u;
    let sign = select(-1.0, 1.0, (face & 1u) == 1u);
    let a = select(-1.0, 1.0, quad == 1u || quad == 2u);
    let b = select(-1.0, 1.0, quad >= 2u);
    var p = vec3<f32>(0.0);
    p[axis] = sign;
    p[(axis + 1u) % 3u] = a;
    p[(axis + 2u) % 3u] = b;
    return p;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) index: u32) -> ProxyOut {
    let p = primitives[index];
    var local: vec3<f32>;
    if p.kind == PRIMITIVE_SPHERE {
        local = cube_corner(vi) * p.size.x;
    } else if vi < 6u {
        // The rectangle's two triangles; the other corners collapse onto its centre.
        local = vec3<f32>(cube_corner(vi).yz * p.size.xy, 0.0);
    } else {
        local = vec3<f32>(0.0);
    }
    let world = p.model * vec4<f32>(local, 1.0);
    var out: ProxyOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.index = index;
    return out;
}

// Ray parameters where `o + t d` meets the primitive (shape-local), nearest first; t = −1e30
// for no hit.
fn primitive_hits(p: Primitive, o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let none = -1e30;
    if p.kind == PRIMITIVE_SPHERE {
        let r = p.size.x;
        let a = dot(d, d);
        let b = 2.0 * dot(o, d);
        let c = dot(o, o) - r * r;
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 || a <= 0.0 {
            return vec2<f32>(none);
        }
        // The stable form: no cancellation between b and the root.
        let q = -0.5 * (b + select(-1.0, 1.0, b >= 0.0) * sqrt(disc));
        let t0 = q / a;
        let t1 = select(t0, c / q, q != 0.0);
        return vec2<f32>(min(t0, t1), max(t0, t1));
    }
    if abs(d.z) < 1e-30 {
        return vec2<f32>(none);
    }
    let t = -o.z / d.z;
    let h = o + t * d;
    if abs(h.x) > p.size.x || abs(h.y) > p.size.y {
        return vec2<f32>(none);
    }
    return vec2<f32>(t, none);
}

@fragment
fn fs_main(in: ProxyOut) -> AnalyticOut {
    let p = primitives[in.index];
    // The pixel's ray, camera-relative: from the eye (perspective) or along the view
    // direction through the proxy point (orthographic; t may then be negative).
    var origin = vec3<f32>(0.0);
    var dir = in.world;
    if frame.modes.x == PROJECTION_ORTHOGRAPHIC {
        origin = in.world;
        dir = frame.forward.xyz;
    }
    let o = (p.to_local * vec4<f32>(origin, 1.0)).xyz;
    let d = (p.to_local * vec4<f32>(dir, 0.0)).xyz;
    let ts = primitive_hits(p, o, d);
    var found = false;
    var t = 0.0;
    var depth = 0.0;
    for (var k = 0; k < 2; k++) {
        let tk = ts[k];
        if tk < -1e29 {
            continue;
        }
        let hit = origin + tk * dir;
        let clip = frame.view_proj * vec4<f32>(hit, 1.0);
        let z = clip.z / clip.w;
        // In front of the near plane (reverse Z: depth ≤ 1) and not behind the eye.
        if clip.w <= 0.0 || z > 1.0 || z < 0.0 || section_cut(hit) {
            continue;
        }
        found = true;
        t = tk;
        depth = z;
        break;
    }
    if !found {
        discard;
    }
    let local = o + t * d;
    var n = vec3<f32>(0.0, 0.0, 1.0);
    var uv = local.xy;
    if p.kind == PRIMITIVE_SPHERE {
        n = local / p.size.x;
        let tau = 6.283185307179586;
        let u = atan2(local.y, local.x);
        uv = vec2<f32>(select(u, u + tau, u < 0.0), asin(clamp(local.z / p.size.x, -1.0, 1.0)));
    }
    // Seen from the side the normal points to, unless the ray leaves the sphere (inside).
    let front = dot(n, d) < 0.0;
    let normal = mat3x3<f32>(p.normal[0].xyz, p.normal[1].xyz, p.normal[2].xyz) * n;
    let ids = InstanceIds(p.material, p.instance, p.flags);
    let texel = visibility_texel(origin + t * dir, normal, p.face, ids, depth, uv, front);
    var out: AnalyticOut;
    out.normal = texel.normal;
    out.ids = texel.ids;
    out.uv = texel.uv;
    out.depth = select(in.clip.z, depth, EXACT_DEPTH);
    if !EXACT_DEPTH {
        out.ids.w = bitcast<u32>(in.clip.z);
    }
    return out;
}
