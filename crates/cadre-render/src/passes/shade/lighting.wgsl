// Shade pass, lighting: Cook–Torrance terms, the lights, the procedural environment
// and ACES tone mapping (see shade.wgsl).

const SKY: vec3<f32> = vec3<f32>(0.46, 0.50, 0.56);
const HORIZON: vec3<f32> = vec3<f32>(0.34, 0.34, 0.34);
const GROUND: vec3<f32> = vec3<f32>(0.15, 0.14, 0.13);

const PI: f32 = 3.14159265;

fn distribution_ggx(nh: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

fn geometry_smith(nv: f32, nl: f32, roughness: f32) -> f32 {
    let k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    let gv = nv / (nv * (1.0 - k) + k);
    let gl = nl / (nl * (1.0 - k) + k);
    return gv * gl;
}

fn fresnel_schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow(clamp(1.0 - cos_theta, 0.0, 1.0), 5.0);
}

fn light(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, radiance: vec3<f32>, base: vec3<f32>,
         metallic: f32, roughness: f32) -> vec3<f32> {
    let nl = max(dot(n, l), 0.0);
    if nl <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = normalize(v + l);
    let nv = max(dot(n, v), 1e-4);
    let f0 = mix(vec3<f32>(0.04), base, metallic);
    let f = fresnel_schlick(f0, max(dot(h, v), 0.0));
    let alpha = roughness * roughness;
    let spec = distribution_ggx(max(dot(n, h), 0.0), alpha) * geometry_smith(nv, nl, roughness)
        * f / (4.0 * nv * nl + 1e-4);
    let diffuse = (vec3<f32>(1.0) - f) * (1.0 - metallic) * base / PI;
    return (diffuse + spec) * radiance * nl;
}

// The environment's radiance seen along `dir` (view space): ground below the horizon, sky
// above, blurred over an angular width `w` around the horizon.
fn environment(dir: vec3<f32>, w: f32) -> vec3<f32> {
    let t = dot(dir, normalize(frame.sky_up.xyz));
    let above = mix(HORIZON, SKY, clamp(t, 0.0, 1.0));
    return mix(GROUND, above, smoothstep(-w, w, t));
}

// Image-based ambient light from the procedural environment.
fn ambient(n: vec3<f32>, v: vec3<f32>, base: vec3<f32>, metallic: f32, roughness: f32) -> vec3<f32> {
    let nv = max(dot(n, v), 1e-4);
    let f0 = mix(vec3<f32>(0.04), base, metallic);
    // Irradiance of a uniform sky (its mean) over a uniform ground: the cosine-weighted mix.
    let up = dot(n, normalize(frame.sky_up.xyz));
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
    let f = fresnel_schlick(f0, nv);
    let diffuse = (vec3<f32>(1.0) - f) * (1.0 - metallic) * base * irradiance;
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
