// Shade pass, lighting: Cook–Torrance terms, the lights, the procedural environment
// and ACES tone mapping (see shade.wgsl).

const SKY: vec3<f32> = vec3<f32>(0.46, 0.50, 0.56);
const HORIZON: vec3<f32> = vec3<f32>(0.34, 0.34, 0.34);
const GROUND: vec3<f32> = vec3<f32>(0.15, 0.14, 0.13);

const PI: f32 = 3.14159265;

// What every light's term shares at one pixel: the surface, the view, and the parts of the
// BRDF that depend on them alone.
struct Surface {
    n: vec3<f32>,
    v: vec3<f32>,
    base: vec3<f32>,
    metallic: f32,
    // GGX's alpha² (alpha = roughness²).
    a2: f32,
    // Schlick-GGX's k, (roughness + 1)² / 8.
    k: f32,
    f0: vec3<f32>,
    // n·v, and clamped away from 0.
    nv: f32,
    nv_clamped: f32,
    // Smith's view term without its n·v numerator: n·v (1 − k) + k.
    gv: f32,
    // The Lambert term's colour: (1 − metallic) base / π.
    diffuse: vec3<f32>,
    roughness: f32,
}

fn surface(n: vec3<f32>, v: vec3<f32>, base: vec3<f32>, metallic: f32, roughness: f32) -> Surface {
    let alpha = roughness * roughness;
    let k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    let nv = dot(n, v);
    let nv_clamped = max(nv, 1e-4);
    return Surface(n, v, base, metallic, alpha * alpha, k, mix(vec3<f32>(0.04), base, metallic),
        nv, nv_clamped, nv_clamped * (1.0 - k) + k, (1.0 - metallic) * base / PI, roughness);
}

// The fifth power by products: a CPU rasterizer (llvmpipe) may lower `pow` to a log2 and an
// exp2 approximation.
fn fresnel_schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let x = clamp(1.0 - cos_theta, 0.0, 1.0);
    let x2 = x * x;
    return f0 + (vec3<f32>(1.0) - f0) * (x2 * x2 * x);
}

// One light's Cook–Torrance term: GGX distribution D, Smith Schlick-GGX geometry G,
// Fresnel–Schlick F; the specular D G F / (4 n·v n·l) with G's n·v and n·l numerators
// cancelled against the denominator, so that one division remains, and no branch: a CPU
// rasterizer runs both sides of a branch for every pixel anyway. `l` is a unit vector.
fn light(s: Surface, l: vec3<f32>, radiance: vec3<f32>) -> vec3<f32> {
    let nl_raw = dot(s.n, l);
    let nl = max(nl_raw, 0.0);
    // The half vector h = (v + l) / |v + l| is not formed: for unit v and l,
    // |v + l|² = 2 + 2 v·l, so n·h and v·h follow from n·v, n·l and v·l (two dot products
    // a light where normalising h took four).
    let vl = dot(s.v, l);
    let inv = inverseSqrt(max(2.0 + 2.0 * vl, 1e-12));
    let nh = max((s.nv + nl_raw) * inv, 0.0);
    let f = fresnel_schlick(s.f0, max((1.0 + vl) * inv, 0.0));
    let d = nh * nh * (s.a2 - 1.0) + 1.0;
    let gl = nl * (1.0 - s.k) + s.k;
    let spec = f * (s.a2 / (4.0 * PI * d * d * s.gv * gl));
    let diffuse = (vec3<f32>(1.0) - f) * s.diffuse;
    return (diffuse + spec) * radiance * nl;
}

// The environment's radiance seen along `dir` (view space): ground below the horizon, sky
// above, blurred over an angular width `w` around the horizon. `frame.sky_up` is a unit
// vector (a rotation of +Z).
fn environment(dir: vec3<f32>, w: f32) -> vec3<f32> {
    let t = dot(dir, frame.sky_up.xyz);
    let above = mix(HORIZON, SKY, clamp(t, 0.0, 1.0));
    return mix(GROUND, above, smoothstep(-w, w, t));
}

// Image-based ambient light from the procedural environment.
fn ambient(s: Surface) -> vec3<f32> {
    let n = s.n;
    let v = s.v;
    let nv = s.nv_clamped;
    let f0 = s.f0;
    let roughness = s.roughness;
    // Irradiance of a uniform sky (its mean) over a uniform ground: the cosine-weighted mix.
    let up = dot(n, frame.sky_up.xyz);
    let irradiance = mix(GROUND, 0.5 * (SKY + HORIZON), 0.5 + 0.5 * up);
    // Split-sum: prefiltered radiance along the reflection × Karis' analytic BRDF term.
    let r = reflect(-v, n);
    let prefiltered = environment(r, 0.02 + roughness * roughness);
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let q = roughness * c0 + c1;
    let a004 = min(q.x * q.x, exp2(-9.28 * nv)) * q.x + q.y;
    let ab = vec2<f32>(-1.04, 1.04) * a004 + q.zw;
    let specular = prefiltered * (f0 * ab.x + ab.y);
    // The light the environment's reflection takes from the diffuse term: Fresnel–Schlick
    // with its grazing limit lowered to 1 − roughness (Fdez-Agüera 2019's roughness-aware
    // form, as Filament and most engines weigh image-based diffuse light). A rough surface
    // does not turn into a mirror at grazing view: with the plain form, the pixels along
    // every silhouette (n·v near 0) lost their diffuse light and showed the ground's
    // reflection, near-black specks one pixel wide.
    let x = clamp(1.0 - nv, 0.0, 1.0);
    let x2 = x * x;
    let f = f0 + (max(vec3<f32>(1.0 - roughness), f0) - f0) * (x2 * x2 * x);
    let diffuse = (vec3<f32>(1.0) - f) * (1.0 - s.metallic) * s.base * irradiance;
    return diffuse + specular;
}

fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let c = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}
