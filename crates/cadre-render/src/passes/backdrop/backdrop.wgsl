// Backdrop pass: the background (solid, gradient, image) where the shade pass left the
// background (no surface, or surfaces drawn as the background in hidden-line and wireframe
// modes; not section caps, which keep their hatching), then the ground grid: the pixel's
// ray hits the ground plane exactly, and the grid shows where that hit is nearer than the
// scene (reverse Z) or there is no scene. Lines are anti-aliased by their distance in
// pixels (the plane coordinates' screen derivatives); the spacing is a power of ten that
// follows the pixel's footprint, the finest level fading out as its lines close up.

@group(0) @binding(1) var<uniform> bd: BackdropUniform;
@group(0) @binding(2) var depth_tex: texture_2d<f32>;
@group(0) @binding(3) var ids_tex: texture_2d<u32>;
@group(0) @binding(4) var image_tex: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return screen_triangle(i);
}

fn srgb_to_linear3(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

// The image stretched over the view, bilinear (texels read with `textureLoad`).
fn image_at(uv: vec2<f32>) -> vec4<f32> {
    let size = vec2<f32>(textureDimensions(image_tex));
    let p = clamp(uv * size - 0.5, vec2<f32>(0.0), size - 1.0);
    let i = vec2<i32>(floor(p));
    let f = p - floor(p);
    let m = vec2<i32>(size) - 1;
    let a = textureLoad(image_tex, i, 0);
    let b = textureLoad(image_tex, min(i + vec2<i32>(1, 0), m), 0);
    let c = textureLoad(image_tex, min(i + vec2<i32>(0, 1), m), 0);
    let d = textureLoad(image_tex, min(i + vec2<i32>(1, 1), m), 0);
    let texel = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
    return vec4<f32>(srgb_to_linear3(texel.rgb), texel.a);
}

// The background's colour at `uv` (0 at the top-left, 1 at the bottom-right), chosen by
// `select`: an `if` on a uniform alone is one lavapipe recompiles the shader for at every
// bind (see `section_cut`, common.wgsl).
fn background_at(uv: vec2<f32>) -> vec4<f32> {
    let gradient = mix(bd.top, bd.bottom, uv.y);
    let image = image_at(uv);
    return select(select(frame.background, image, bd.modes.x == 2u), gradient, bd.modes.x == 1u);
}

// How much of a pixel the lines of spacing `s` cover, `w` pixels wide: `g` the plane
// coordinates, `dg` their change per pixel.
fn lines_coverage(g: vec2<f32>, dg: vec2<f32>, s: f32, w: f32) -> f32 {
    let q = g / s;
    let d = abs(fract(q + 0.5) - 0.5) * s / max(dg, vec2<f32>(1e-30));
    let c = clamp(0.5 * w + 0.5 - d, vec2<f32>(0.0), vec2<f32>(1.0));
    return max(c.x, c.y);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let uv = pos.xy / frame.viewport.xy;
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    // The pixel's ray, camera-relative (two points of it: the near plane and halfway).
    let a = bd.inv_view_proj * vec4<f32>(ndc, 1.0, 1.0);
    let b = bd.inv_view_proj * vec4<f32>(ndc, 0.5, 1.0);
    let o = a.xyz / a.w;
    let dir = b.xyz / b.w - o;
    let n = bd.plane.xyz;
    let along = dot(n, dir);
    let t = (bd.plane.w - dot(n, o)) / select(along, 1e-30, abs(along) < 1e-30);
    let hit = o + t * dir;
    // Plane coordinates relative to the grid's origin, and their derivatives: taken before
    // any branch (derivatives need every pixel of the quad).
    let g = (hit + bd.origin.xyz).xy;
    let dg = fwidth(g);
    let pixel = vec2<i32>(pos.xy);
    let scene_depth = textureLoad(depth_tex, pixel, 0).x;
    // (The ids count only where the depth is not 0: they are or'ed after the depth test.)
    let ids = textureLoad(ids_tex, pixel, 0);
    let background = (scene_depth <= 0.0) | ((frame.modes.y != FILL_SHADED) & !is_cap(ids));
    var out = vec4<f32>(0.0);
    if background & (bd.modes.x != 0u) {
        out = background_at(uv);
        out.a = 1.0;
    }
    if (bd.modes.y != 0u) & (t > 0.0) {
        let clip = frame.view_proj * vec4<f32>(hit, 1.0);
        let depth = clip.z / clip.w;
        // Wireframe draws no faces: nothing hides the grid.
        let occluder = select(scene_depth, 0.0, frame.modes.y == FILL_NONE);
        if (depth > occluder) && (depth <= 1.0) {
            let footprint = max(dg.x, dg.y);
            // A fixed spacing, faded where its lines come closer than 3 pixels.
            let spacing = max(bd.params.x, 1e-30);
            let gap = spacing / max(footprint, 1e-30);
            let fixed = max(
                lines_coverage(g, dg, spacing, 1.0) * clamp((gap - 3.0) / 3.0, 0.0, 1.0),
                lines_coverage(g, dg, 10.0 * spacing, 1.5),
            );
            // Powers of ten: the finest whose lines are ≥ 1 pixel apart fades in as they
            // open from 2 to 10 pixels apart; the next ones full, every tenth stronger.
            let level = log2(max(footprint, 1e-30)) / log2(10.0);
            let fine = pow(10.0, floor(level) + 1.0);
            let fade = smoothstep(2.0, 10.0, fine / max(footprint, 1e-30));
            let adaptive = max(
                lines_coverage(g, dg, fine, 1.0) * fade * 0.6,
                max(
                    lines_coverage(g, dg, 10.0 * fine, 1.0) * 0.85,
                    lines_coverage(g, dg, 100.0 * fine, 1.5),
                ),
            );
            // Near the horizon the lines crowd into moiré: faded out.
            let grazing = abs(along) / max(length(dir), 1e-30);
            // And towards the far plane, over its last third, rather than cut there.
            let distance = dot(hit, frame.forward.xyz);
            let cover = select(adaptive, fixed, bd.params.x > 0.0)
                * clamp((grazing - 0.02) / 0.08, 0.0, 1.0)
                * clamp((bd.params.y - distance) / (0.33 * bd.params.y), 0.0, 1.0);
            var colour = bd.grid_colour.rgb;
            var alpha = bd.grid_colour.a * cover;
            // The world axes through the origin: X red (y = 0), Y green (x = 0).
            let axis = (g - bd.axes.xy) / max(dg, vec2<f32>(1e-30));
            let on_x = clamp(1.5 - abs(axis.y), 0.0, 1.0);
            let on_y = clamp(1.5 - abs(axis.x), 0.0, 1.0);
            if (bd.params.w != 0.0) & (max(on_x, on_y) > cover) {
                colour = select(vec3<f32>(0.1, 0.6, 0.15), vec3<f32>(0.8, 0.1, 0.1), on_x >= on_y);
                alpha = max(on_x, on_y) * max(bd.grid_colour.a, 0.8);
            }
            if out.a > 0.0 {
                out = vec4<f32>(mix(out.rgb, colour, alpha), 1.0);
            } else {
                out = vec4<f32>(colour, alpha);
            }
        }
    }
    if out.a <= 0.0 {
        discard;
    }
    return out;
}
