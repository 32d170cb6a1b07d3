// Shading pass: Cook–Torrance lighting (GGX distribution, Smith Schlick-GGX geometry,
// Fresnel–Schlick) of the visibility buffer under a CAD key/fill/rim rig of directional
// lights fixed to the camera plus a sky/ground ambient, then ACES tone mapping. The target is
// an sRGB texture, so the output here is linear.

struct Frame {
    view_proj: mat4x4<f32>,
    inv_proj: mat4x4<f32>,
    background: vec4<f32>,
    viewport: vec4<f32>,
    edges: vec4<f32>,
    edge_colour: vec4<f32>,
    hidden_colour: vec4<f32>,
    outline: vec4<f32>,
}

struct Material {
    base_color: vec4<f32>,
    params: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> materials: array<Material>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var ids_tex: texture_2d<u32>;

const PI: f32 = 3.14159265;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the screen.
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

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

fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let c = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Reverse-Z depth of the visibility buffer at `p` (0 for background or outside the image).
fn depth_at(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return 0.0;
    }
    let ids = textureLoad(ids_tex, p, 0);
    return select(0.0, bitcast<f32>(ids.w), ids.y != 0u);
}

// Whether `p` lies on a silhouette: a neighbour farther away by more than the relative jump
// (another part, the background, or the same part behind a fold). Only the nearer side of a
// jump is marked, so outlines stay one pixel wide and on the object.
fn on_silhouette(p: vec2<i32>, depth: f32) -> bool {
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    for (var k = 0; k < 4; k++) {
        let d = depth_at(p + offsets[k]);
        // Reverse Z: depth ∝ 1/distance, so a relative gap in depth is one in distance.
        if d < depth * (1.0 - frame.outline.y) {
            return true;
        }
    }
    return false;
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let ids = textureLoad(ids_tex, p, 0);
    if ids.y != 0u && frame.outline.x > 0.5 && on_silhouette(p, bitcast<f32>(ids.w)) {
        return frame.edge_colour;
    }
    // No face (background), or faces drawn as the background (hidden-line, wireframe).
    if ids.y == 0u || frame.viewport.w > 0.5 {
        return frame.background;
    }
    let m = materials[ids.z];
    let base = m.base_color.rgb;
    let metallic = clamp(m.params.x, 0.0, 1.0);
    let roughness = clamp(m.params.y, 0.04, 1.0);
    // View direction from the depth: towards the eye (perspective) or along +z (orthographic).
    let depth = bitcast<f32>(ids.w);
    let ndc = vec2<f32>(pos.x / frame.viewport.x * 2.0 - 1.0, 1.0 - pos.y / frame.viewport.y * 2.0);
    let view_h = frame.inv_proj * vec4<f32>(ndc, depth, 1.0);
    let view_pos = view_h.xyz / view_h.w;
    var v = normalize(-view_pos);
    if frame.viewport.z > 0.5 {
        v = vec3<f32>(0.0, 0.0, 1.0);
    }
    var n = normalize(textureLoad(normal_tex, p, 0).xyz);
    // Both sides of a face are lit alike (open shells, views from inside).
    if dot(n, v) < 0.0 {
        n = -n;
    }
    var colour = vec3<f32>(0.0);
    colour += light(n, v, normalize(vec3<f32>(-0.45, 0.55, 0.70)), vec3<f32>(2.6), base, metallic, roughness);
    colour += light(n, v, normalize(vec3<f32>(0.70, 0.10, 0.50)), vec3<f32>(0.9), base, metallic, roughness);
    colour += light(n, v, normalize(vec3<f32>(0.05, 0.60, -0.80)), vec3<f32>(1.1), base, metallic, roughness);
    // Ambient: a sky above (view up) and a darker ground below.
    let sky = vec3<f32>(0.42, 0.45, 0.50);
    let ground = vec3<f32>(0.16, 0.15, 0.14);
    let hemi = mix(ground, sky, 0.5 + 0.5 * n.y);
    let f0 = mix(vec3<f32>(0.04), base, metallic);
    let f_amb = fresnel_schlick(f0, max(dot(n, v), 0.0)) * (1.0 - 0.5 * roughness);
    colour += hemi * ((1.0 - metallic) * base * (vec3<f32>(1.0) - f_amb) + f_amb);
    return vec4<f32>(aces(colour), 1.0);
}
