// Analytic back-end: spheres, rectangles and quadrics cut by planes ray cast per pixel. Each
// primitive draws a proxy that covers it on screen (a sphere's bounding cube, both sides; a
// rectangle itself; a quadric's screen rectangle, quadric.wgsl), and each proxy fragment
// casts the pixel's view ray in the primitive's own frame. Into the
// visibility buffer (`fs_main`) it keeps the nearest hit in front of the near plane and
// outside every section plane, writes that hit's depth (not the proxy's) and goes through
// `visibility_texel` (texel.wgsl, before this file) like a mesh fragment. In the see-through
// phases (`fs_xray`, `fs_transparent`) it draws hit `LAYER` (0 the nearer, 1 the farther:
// a pipeline per layer, the farther drawn first) in the colours of see_through.wgsl.

@group(0) @binding(1) var<storage, read> primitives: array<Primitive>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;

// `Primitive.kind` (analytic::PRIMITIVE_*).
const PRIMITIVE_SPHERE: u32 = 0u;
const PRIMITIVE_RECTANGLE: u32 = 1u;

// The hit's depth is written (false only for the tests' negative control: the proxy's
// depth, which is wrong wherever the proxy is not the surface).
override EXACT_DEPTH: bool = true;

// The hit a see-through pipeline draws: 0 the nearer, 1 the farther.
override LAYER: u32 = 0u;
// Quadrics' silhouettes and cut edges carry their analytic coverage (the frame blends them).
override COVERAGE: bool = true;

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

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) index: u32) -> ProxyOut {
    let p = primitives[index];
    var out: ProxyOut;
    out.index = index;
    if is_quadric(p) {
        out.clip = quadric_proxy(p, vi);
        out.world = vec3<f32>(0.0);
        return out;
    }
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
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
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

// A pixel's view ray, camera-relative (`origin`, `dir`) and in the primitive's frame
// (`o`, `d`): from the eye (perspective) or along the view direction through the proxy point
// (orthographic; t may then be negative).
struct PixelRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
    o: vec3<f32>,
    d: vec3<f32>,
}

fn pixel_ray(p: Primitive, world: vec3<f32>) -> PixelRay {
    // By `select`, not `if` (see `section_cut`, common.wgsl).
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let origin = select(vec3<f32>(0.0), world, ortho);
    let dir = select(world, frame.forward.xyz, ortho);
    let o = (p.to_local * vec4<f32>(origin, 1.0)).xyz;
    let d = (p.to_local * vec4<f32>(dir, 0.0)).xyz;
    return PixelRay(origin, dir, o, d);
}

// A hit of the ray: its parameter and depth; `found` false for none.
struct RayHit {
    found: bool,
    t: f32,
    depth: f32,
}

// The ray's hit number `layer` (0 the nearest) among those in front of the near plane,
// not behind the eye and not cut away by a section plane.
fn layer_hit(p: Primitive, ray: PixelRay, layer: u32) -> RayHit {
    let ts = primitive_hits(p, ray.o, ray.d);
    var seen = 0u;
    for (var k = 0; k < 2; k++) {
        let tk = ts[k];
        if tk < -1e29 {
            continue;
        }
        let hit = ray.origin + tk * ray.dir;
        let clip = frame.view_proj * vec4<f32>(hit, 1.0);
        let z = clip.z / clip.w;
        // In front of the near plane (reverse Z: depth ≤ 1) and not behind the eye.
        if clip.w <= 0.0 || z > 1.0 || z < 0.0 || section_cut(hit) {
            continue;
        }
        if seen == layer {
            return RayHit(true, tk, z);
        }
        seen += 1u;
    }
    return RayHit(false, 0.0, 0.0);
}

// The hit's unit normal in the primitive's frame and its (u, v) on the exact surface.
struct SurfacePoint {
    n: vec3<f32>,
    uv: vec2<f32>,
}

fn surface_point(p: Primitive, local: vec3<f32>) -> SurfacePoint {
    var n = vec3<f32>(0.0, 0.0, 1.0);
    var uv = local.xy;
    if p.kind == PRIMITIVE_SPHERE {
        n = local / p.size.x;
        let tau = 6.283185307179586;
        let u = atan2(local.y, local.x);
        uv = vec2<f32>(select(u, u + tau, u < 0.0), asin(clamp(local.z / p.size.x, -1.0, 1.0)));
    }
    return SurfacePoint(n, uv);
}

// The primitive's normal map (shape frame → view space) applied to `n`.
fn view_normal(p: Primitive, n: vec3<f32>) -> vec3<f32> {
    return mat3x3<f32>(p.normal[0].xyz, p.normal[1].xyz, p.normal[2].xyz) * n;
}

// The surface point a fragment shows: camera-relative position, view-space normal, (u, v),
// whether it is seen from the side its normal points to, and its depth; `found` false for
// none.
struct ShownPoint {
    found: bool,
    world: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    front: bool,
    depth: f32,
    // A quadric's boundary functions and boundary point (`QuadricHit::edge`); large for the
    // other kinds.
    edge: vec3<f32>,
}

// The point hit number `layer` (0 the nearest) of the proxy fragment at `pixel` (its
// position) and `world` (its camera-relative point).
fn shown_point(p: Primitive, pixel: vec2<f32>, world: vec3<f32>, layer: u32) -> ShownPoint {
    var out = ShownPoint(false, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec2<f32>(0.0), true, 0.0, vec3<f32>(QUADRIC_FAR));
    if is_quadric(p) {
        let ray = quadric_ray(p, pixel);
        let hit = quadric_hit(p, ray, layer);
        out.edge = hit.edge;
        if hit.found {
            let local = ray.o + hit.s * ray.d;
            out = ShownPoint(
                true,
                (p.model * vec4<f32>(local, 1.0)).xyz,
                view_normal(p, hit.n),
                local.xy,
                dot(hit.n, ray.d) < 0.0,
                hit.depth,
                hit.edge,
            );
        }
        return out;
    }
    let ray = pixel_ray(p, world);
    let hit = layer_hit(p, ray, layer);
    if hit.found {
        let local = ray.o + hit.t * ray.d;
        let surface = surface_point(p, local);
        // Seen from the side the normal points to, unless the ray leaves the sphere (inside).
        out = ShownPoint(
            true,
            ray.origin + hit.t * ray.dir,
            view_normal(p, surface.n),
            surface.uv,
            dot(surface.n, ray.d) < 0.0,
            hit.depth,
            vec3<f32>(QUADRIC_FAR),
        );
    }
    return out;
}

@fragment
fn fs_main(in: ProxyOut) -> AnalyticOut {
    let p = primitives[in.index];
    let shown = shown_point(p, in.clip.xy, in.world, 0u);
    // The boundary functions' screen derivatives, before any discard (every lane takes part).
    let ex = dpdx(shown.edge);
    let ey = dpdy(shown.edge);
    if !shown.found {
        discard;
    }
    let ids = InstanceIds(p.material, p.instance, p.flags);
    let texel = visibility_texel(
        shown.world,
        shown.normal,
        p.face,
        ids,
        shown.depth,
        shown.uv,
        shown.front,
    );
    var out: AnalyticOut;
    out.normal = texel.normal;
    out.ids = texel.ids;
    out.uv = texel.uv;
    out.depth = select(in.clip.z, shown.depth, EXACT_DEPTH);
    // Analytic coverage (F / |∇F| in pixels from each boundary, ½ on it): the shade pass
    // blends the rest of the pixel with what its neighbours across the boundary show.
    if COVERAGE && is_quadric(p) && ((out.ids.z & SECTION_CAP) == 0u) {
        // The silhouette's function is one polynomial across it; a cut edge's margin is
        // the neighbours' only where they show the same boundary point.
        let steady = (ex.z == 0.0) && (ey.z == 0.0);
        var covered = 1.0;
        for (var k = 0u; k < 2u; k++) {
            let g = length(vec2<f32>(ex[k], ey[k]));
            if g > 0.0 && shown.edge[k] < 0.5 * QUADRIC_FAR && (k == 0u || steady) {
                covered = min(covered, 0.5 + shown.edge[k] / g);
            }
        }
        out.normal.z = clamp(covered, 0.5, 1.0);
    }
    if !EXACT_DEPTH {
        out.ids.w = bitcast<u32>(in.clip.z);
    }
    return out;
}

// Whether this proxy fragment draws its pixel in a see-through phase, where no depth test
// keeps one of a sphere's cube's two sides: the one on the cube's far side along the ray
// (whose face's outward normal the ray runs along), seen once from outside and from inside.
fn draws_pixel(p: Primitive, world: vec3<f32>) -> bool {
    if p.kind != PRIMITIVE_SPHERE {
        return true;
    }
    let ray = pixel_ray(p, world);
    let q = (p.to_local * vec4<f32>(world, 1.0)).xyz;
    let a = abs(q);
    var axis = 0u;
    if a.y > a[axis] {
        axis = 1u;
    }
    if a.z > a[axis] {
        axis = 2u;
    }
    return q[axis] * ray.d[axis] > 0.0;
}

// A see-through fragment: the hit of layer `LAYER`, its view-space normal and its depth.
struct SeeThroughHit {
    found: bool,
    normal: vec3<f32>,
    depth: f32,
}

fn see_through_hit(p: Primitive, pixel: vec2<f32>, world: vec3<f32>) -> SeeThroughHit {
    var out = SeeThroughHit(false, vec3<f32>(0.0, 0.0, 1.0), 0.0);
    if !draws_pixel(p, world) {
        return out;
    }
    let shown = shown_point(p, pixel, world, LAYER);
    if shown.found {
        out.found = true;
        out.normal = shown.normal;
        out.depth = shown.depth;
    }
    return out;
}

@fragment
fn fs_xray(in: ProxyOut) -> @location(0) vec4<f32> {
    let p = primitives[in.index];
    let hit = see_through_hit(p, in.clip.xy, in.world);
    if !hit.found {
        discard;
    }
    return xray_colour(materials[p.material].base_color, hit.normal);
}

struct TransparentOut {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_transparent(in: ProxyOut) -> TransparentOut {
    let p = primitives[in.index];
    let hit = see_through_hit(p, in.clip.xy, in.world);
    if !hit.found {
        discard;
    }
    // The hit's own depth, tested against the opaque surfaces' (not the proxy's).
    return TransparentOut(transparent_colour(materials[p.material].base_color, hit.normal), hit.depth);
}
