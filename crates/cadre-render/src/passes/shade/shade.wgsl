// Shading pass: Cook–Torrance lighting (GGX distribution, Smith Schlick-GGX geometry,
// Fresnel–Schlick) of the visibility buffer under the frame's lights (directional, point,
// spot; by default a CAD key/fill/rim rig fixed to the camera) and image-based ambient light
// from a procedural sky/ground environment, prefiltered analytically (irradiance of a uniform
// sky over a uniform ground; the specular lobe blurs the horizon by the roughness; Karis'
// analytic split-sum BRDF), then
// ACES tone mapping. The target is an sRGB texture, so the output here is linear.
//
// Section caps (the inside of a closed solid seen through a cut, marked in the ids' material
// channel) get the part's base colour a little darker, lit by the plane's normal, crossed by
// dark 45° hatch lines in screen space (the other diagonal on every other part, as drawings
// tell adjacent parts apart) and outlined where the cap ends.

@group(0) @binding(1) var<storage, read> materials: array<Material>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var ids_tex: texture_2d<u32>;
@group(0) @binding(4) var<storage, read> lights: array<Light>;
@group(0) @binding(5) var<storage, read> selection: array<vec4<u32>>;

const SKY: vec3<f32> = vec3<f32>(0.46, 0.50, 0.56);
const HORIZON: vec3<f32> = vec3<f32>(0.34, 0.34, 0.34);
const GROUND: vec3<f32> = vec3<f32>(0.15, 0.14, 0.13);

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

// A distance beyond any surface: the background's, so it is always farther than a face.
const FAR_AWAY: f32 = 1e30;

// Distance from the eye (along the view axis) of the visibility buffer's surface at `p`;
// `FAR_AWAY` for background or outside the image. The reverse-Z depth is unprojected through
// the inverse projection: with a finite far plane depth is not proportional to 1/distance (it
// reaches 0 at the far plane, not at infinity), and orthographic depth is linear in distance,
// so relative gaps in depth are not relative gaps in distance.
fn distance_at(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return FAR_AWAY;
    }
    let ids = textureLoad(ids_tex, p, 0);
    if ids.y == 0u {
        return FAR_AWAY;
    }
    let centre = vec2<f32>(p) + 0.5;
    let ndc = vec2<f32>(centre.x / frame.viewport.x * 2.0 - 1.0, 1.0 - centre.y / frame.viewport.y * 2.0);
    let view_h = frame.inv_proj * vec4<f32>(ndc, bitcast<f32>(ids.w), 1.0);
    return -view_h.z / view_h.w;
}

// Whether `p` lies on a silhouette: a neighbour farther from the eye by more than the
// relative jump `outline.y` (another part, the background, or the same part behind a fold).
// Only the nearer side of a jump is marked, so outlines stay one pixel wide and on the object.
fn on_silhouette(p: vec2<i32>) -> bool {
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    let limit = distance_at(p) * (1.0 + frame.tolerances.y);
    for (var k = 0; k < 4; k++) {
        if distance_at(p + offsets[k]) > limit {
            return true;
        }
    }
    return false;
}

// The ids at `p`, or `fallback` outside the image.
fn ids_at(p: vec2<i32>, fallback: vec4<u32>) -> vec4<u32> {
    let size = vec2<i32>(frame.viewport.xy);
    if any(p < vec2<i32>(0)) || any(p >= size) {
        return fallback;
    }
    return textureLoad(ids_tex, p, 0);
}

// Whether the cap pixel `p` (ids `ids`) lies within the outline width of where its cap ends:
// a pixel that is not a cap of the same part and plane.
fn on_cap_boundary(p: vec2<i32>, ids: vec4<u32>) -> bool {
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    let reach = max(i32(frame.section.z + 0.5), 1);
    for (var k = 0; k < 4; k++) {
        for (var r = 1; r <= reach; r++) {
            let q = ids_at(p + offsets[k] * r, ids);
            if q.y != ids.y || q.z != ids.z {
                return true;
            }
        }
    }
    return false;
}

// Coverage (0..1, anti-aliased) of the cap hatch lines at pixel centre `pos`: 45° lines every
// `section.x` pixels, `section.y` wide, the other diagonal for every other part and plane.
fn hatch(pos: vec2<f32>, ids: vec4<u32>) -> f32 {
    let plane = (ids.z >> 28u) & 3u;
    let flip = ((ids.y + plane) & 1u) == 1u;
    let u = select(pos.x + pos.y, pos.x - pos.y, flip) * 0.70710678;
    let spacing = max(frame.section.x, 2.0);
    let d = abs(u - spacing * round(u / spacing));
    return clamp(0.5 * frame.section.y + 0.5 - d, 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let ids = textureLoad(ids_tex, p, 0);
    if ids.y != 0u && frame.modes.w != 0u && on_silhouette(p) {
        return frame.edge_colour;
    }
    let cap = is_cap(ids);
    // Caps are outlined whenever faces are filled (shaded or hidden-line).
    if cap && frame.modes.y != FILL_NONE && on_cap_boundary(p, ids) {
        return frame.edge_colour;
    }
    // No face (background), or faces drawn as the background (hidden-line, wireframe);
    // hidden-line drawings keep the caps' hatching.
    if ids.y == 0u || frame.modes.y != FILL_SHADED {
        if cap && frame.modes.y != FILL_NONE {
            let h = hatch(pos.xy, ids);
            return vec4<f32>(mix(frame.background.rgb, frame.edge_colour.rgb, h), frame.background.a);
        }
        return frame.background;
    }
    let m = materials[ids.z & CAP_MATERIAL];
    // The cut material a little darker than the part's surface.
    let base = m.base_color.rgb * select(1.0, 0.8, cap);
    let metallic = clamp(m.params.x, 0.0, 1.0);
    let roughness = clamp(m.params.y, 0.04, 1.0);
    // View direction from the depth: towards the eye (perspective) or along +z (orthographic).
    let depth = bitcast<f32>(ids.w);
    let ndc = vec2<f32>(pos.x / frame.viewport.x * 2.0 - 1.0, 1.0 - pos.y / frame.viewport.y * 2.0);
    let view_h = frame.inv_proj * vec4<f32>(ndc, depth, 1.0);
    let view_pos = view_h.xyz / view_h.w;
    var v = normalize(-view_pos);
    if frame.modes.x == PROJECTION_ORTHOGRAPHIC {
        v = vec3<f32>(0.0, 0.0, 1.0);
    }
    var n = normalize(textureLoad(normal_tex, p, 0).xyz);
    // Both sides of a face are lit alike (open shells, views from inside).
    if dot(n, v) < 0.0 {
        n = -n;
    }
    var colour = vec3<f32>(0.0);
    for (var i = 0u; i < frame.counts.x; i++) {
        let li = lights[i];
        let kind = u32(li.position.w + 0.5);
        var l = normalize(li.direction.xyz);
        var radiance = li.colour.rgb;
        if kind != 0u {
            let to_light = li.position.xyz - view_pos;
            let d = max(length(to_light), 1e-6);
            l = to_light / d;
            var falloff = 1.0 / (d * d);
            let range = li.direction.w;
            if range > 0.0 {
                let x = d / range;
                let w = clamp(1.0 - x * x * x * x, 0.0, 1.0);
                falloff *= w * w;
            }
            radiance *= falloff;
            if kind == 2u {
                radiance *= smoothstep(li.colour.w, li.params.x, dot(-l, normalize(li.direction.xyz)));
            }
        }
        colour += light(n, v, l, radiance, base, metallic, roughness);
    }
    colour += ambient(n, v, base, metallic, roughness);
    var mapped = aces(colour);
    if cap {
        // Dark lines in the cap's own hue.
        mapped = mix(mapped, 0.1 * mapped, hatch(pos.xy, ids));
    }
    return vec4<f32>(highlighted(mapped, ids), 1.0);
}

// `colour` tinted when its face (or part) is selected or hovered.
fn highlighted(colour: vec3<f32>, ids: vec4<u32>) -> vec3<f32> {
    for (var i = 0u; i < frame.counts.y; i++) {
        if is_target(selection[i], 1u, ids.y, ids.x) {
            return mix(colour, frame.selection_colour.rgb, frame.selection_colour.w);
        }
    }
    if is_target(frame.hover, 1u, ids.y, ids.x) {
        return mix(colour, frame.hover_colour.rgb, frame.hover_colour.w);
    }
    return colour;
}
