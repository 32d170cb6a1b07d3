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

// The optional parts, compiled in or out per pipeline (`ShadeVariant` in mod.rs): a CPU
// rasterizer runs both sides of every branch under lane masks, so code a frame cannot reach
// would still cost its full price at every pixel.
// Section caps (with outlines and hatching): set when the frame has section planes.
override SECTIONS: bool = true;
// Outlines where the depth jumps: set in the modes that draw visible edges.
override SILHOUETTES: bool = true;
// Point and spot lights; unset when every light is directional (the default rig).
override POSITIONAL_LIGHTS: bool = true;
// The number of lights (the frame's `counts.x`): a loop of constant trip count is unrolled,
// where a loop of uniform count costs a CPU rasterizer its mask bookkeeping per iteration
// and one masked iteration even when empty.
override LIGHTS: u32 = 1u;
// Selected entities to tint (`counts.y > 0`).
override SELECTION: bool = true;
// Trimmed edges' pixels blended by their coverage (`counts.w > 0`: the frame draws faces
// trimmed per pixel and asks for analytic anti-aliasing).
override COVERAGE: bool = true;
// The key light (the first) casts shadows from the frame's shadow map (`shadow_params.w > 0`).
override SHADOWS: bool = false;

@group(0) @binding(1) var<storage, read> materials: array<Material>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var ids_tex: texture_2d<u32>;
@group(0) @binding(4) var<uniform> lights: LightRig;
@group(0) @binding(5) var<storage, read> selection: array<vec4<u32>>;
// The visibility depth (also the pass's read-only depth attachment): 0 where nothing is.
@group(0) @binding(6) var depth_tex: texture_2d<f32>;
// The key light's shadow map: the depth every back-end wrote, seen from the light (reverse
// Z); any texture when the frame has no shadows.
@group(0) @binding(7) var shadow_tex: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the screen, on the far plane (reverse-Z depth 0): the pass's depth
    // test (`faces_only` in mod.rs) leaves the background cleared and unshaded.
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let own = shade_pixel(p, pos.xy);
    if COVERAGE {
        // A pixel on a trimmed edge, covered `covered` (≥ ½) by its face: the rest of it is
        // what its neighbours across the edge show (those of the four with another face or
        // part, or nothing), shaded as they are.
        let covered = textureLoad(normal_tex, p, 0).z;
        let ids = textureLoad(ids_tex, p, 0);
        if (covered < 0.999) & (ids.y != 0u) {
            let size = vec2<i32>(textureDimensions(ids_tex));
            var across = vec4<f32>(0.0);
            var count = 0.0;
            for (var k = 0u; k < 4u; k++) {
                let offset = vec2<i32>(select(select(1, -1, k == 1u), 0, k >= 2u), select(0, select(1, -1, k == 3u), k >= 2u));
                let q = p + offset;
                if all(q >= vec2<i32>(0)) && all(q < size) {
                    let other = textureLoad(ids_tex, q, 0);
                    if (other.x != ids.x) || (other.y != ids.y) {
                        across += shade_pixel(q, pos.xy + vec2<f32>(offset));
                        count += 1.0;
                    }
                }
            }
            if count > 0.0 {
                return mix(across / count, own, covered);
            }
        }
    }
    return own;
}

// The colour of the visibility texel at `p` (whose centre is `pos`).
// How much of the key light reaches the view-space point `view_pos` of normal `n`: its
// shadow map looked up 3 × 3 texels about the point (percentage-closer filtering), the point
// first moved 1.5 texels along its normal (no self-shadowing acne on surfaces the light
// grazes). Outside the map: lit.
fn key_light_shadow(view_pos: vec3<f32>, n: vec3<f32>) -> f32 {
    let size = frame.shadow_params.w;
    let at = frame.shadow * vec4<f32>(view_pos, 1.0);
    let texel = max(at.w, 1e-6) * frame.shadow_params.x;
    let c = frame.shadow * vec4<f32>(view_pos + n * (1.5 * texel), 1.0);
    if c.w <= 0.0 {
        return 1.0;
    }
    let ndc = c.xyz / c.w;
    if any(abs(ndc.xy) > vec2<f32>(1.0)) {
        return 1.0;
    }
    let centre = vec2<i32>(floor(vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y) * size));
    let last = i32(size) - 1;
    var lit = 0.0;
    for (var k = 0; k < 9; k++) {
        let q = clamp(centre + vec2<i32>(k % 3 - 1, k / 3 - 1), vec2<i32>(0), vec2<i32>(last));
        let nearest = textureLoad(shadow_tex, q, 0).x;
        // Reverse Z: the point is lit when it is no farther from the light than the map.
        lit += select(0.0, 1.0, ndc.z >= nearest - 1e-6);
    }
    return 1.0 - frame.shadow_params.z * (1.0 - lit / 9.0);
}

fn shade_pixel(p: vec2<i32>, pos: vec2<f32>) -> vec4<f32> {
    let ids = textureLoad(ids_tex, p, 0);
    let depth = bitcast<f32>(ids.w);
    if SILHOUETTES {
        // The depth target's, not the ids' (a cap's ids carry the cut plane's depth, its
        // depth target the back face it was drawn from: its neighbours' kind).
        let surface = textureLoad(depth_tex, p, 0).x;
        if (ids.y != 0u) & (frame.modes.w != 0u) & on_silhouette(p, surface) {
            return frame.edge_colour;
        }
    }
    let cap = SECTIONS && is_cap(ids);
    // Caps are outlined whenever faces are filled (shaded or hidden-line).
    if cap && frame.modes.y != FILL_NONE && on_cap_boundary(p, ids) {
        return frame.edge_colour;
    }
    // No face (background), or faces drawn as the background (hidden-line, wireframe);
    // hidden-line drawings keep the caps' hatching.
    if ids.y == 0u || frame.modes.y != FILL_SHADED {
        if cap && frame.modes.y != FILL_NONE {
            let h = hatch(pos, ids);
            return vec4<f32>(mix(frame.background.rgb, frame.edge_colour.rgb, h), frame.background.a);
        }
        return frame.background;
    }
    // The inspection view: cracks the crack pass filled, magenta; real gaps it closed, orange.
    if !cap && ((ids.z & (CRACK_FILLED | GAP_CLOSED)) != 0u) {
        return select(vec4<f32>(1.0, 0.3, 0.0, 1.0), vec4<f32>(1.0, 0.0, 1.0, 1.0), (ids.z & CRACK_FILLED) != 0u);
    }
    let m = materials[ids.z & CAP_MATERIAL];
    // The cut material a little darker than the part's surface.
    let base = m.base_color.rgb * select(1.0, 0.8, cap);
    let metallic = clamp(m.params.x, 0.0, 1.0);
    let roughness = clamp(m.params.y, 0.04, 1.0);
    // View direction from the depth: towards the eye (perspective) or along +z (orthographic).
    let ndc = vec2<f32>(pos.x / frame.viewport.x * 2.0 - 1.0, 1.0 - pos.y / frame.viewport.y * 2.0);
    let view_h = frame.inv_proj * vec4<f32>(ndc, depth, 1.0);
    let view_pos = view_h.xyz / view_h.w;
    let ortho = frame.modes.x == PROJECTION_ORTHOGRAPHIC;
    let v = select(normalize(-view_pos), vec3<f32>(0.0, 0.0, 1.0), ortho);
    // The normal target holds its octahedral map (`encode_normal`, texel.wgsl).
    var n = from_octahedral(textureLoad(normal_tex, p, 0).xy);
    // Both sides of a face are lit alike (open shells, views from inside).
    if dot(n, v) < 0.0 {
        n = -n;
    }
    let lit = surface(n, v, base, metallic, roughness);
    var colour = vec3<f32>(0.0);
    for (var i = 0u; i < LIGHTS; i++) {
        let li = lights.lights[i];
        let kind = u32(li.position.w + 0.5);
        // Unit already (`Light::to_gpu`).
        var l = li.direction.xyz;
        var radiance = li.colour.rgb;
        if POSITIONAL_LIGHTS {
            // Chosen without branches: the light's values are uniform, and lavapipe compiles a
            // shader again for every new uniform value a branch depends on.
            let positional = kind != 0u;
            let to_light = li.position.xyz - view_pos;
            let d = max(length(to_light), 1e-6);
            l = select(l, to_light / d, positional);
            let range = li.direction.w;
            let x = d / max(range, 1e-30);
            let w = clamp(1.0 - x * x * x * x, 0.0, 1.0);
            let falloff = select(1.0, w * w, range > 0.0) / (d * d);
            let cone = smoothstep(li.colour.w, li.params.x, dot(-l, normalize(li.direction.xyz)));
            radiance *= select(1.0, falloff * select(1.0, cone, kind == 2u), positional);
        }
        if SHADOWS && (i == 0u) {
            radiance *= key_light_shadow(view_pos, n);
        }
        colour += light(lit, l, radiance);
    }
    colour += ambient(lit);
    var mapped = aces(colour);
    if cap {
        // Dark lines in the cap's own hue.
        mapped = mix(mapped, 0.1 * mapped, hatch(pos, ids));
    }
    return vec4<f32>(highlighted(mapped, ids), 1.0);
}

// `colour` tinted when its face (or part) is selected or hovered.
fn highlighted(colour: vec3<f32>, ids: vec4<u32>) -> vec3<f32> {
    if SELECTION {
        // Bounded by the buffer too (see `section_cut`, common.wgsl).
        for (var i = 0u; i < min(frame.counts.y, arrayLength(&selection)); i++) {
            if is_target(selection[i], 1u, ids.y, ids.x) {
                return mix(colour, frame.selection_colour.rgb, frame.selection_colour.w);
            }
        }
    }
    if is_target(frame.hover, 1u, ids.y, ids.x) {
        return mix(colour, frame.hover_colour.rgb, frame.hover_colour.w);
    }
    return colour;
}
