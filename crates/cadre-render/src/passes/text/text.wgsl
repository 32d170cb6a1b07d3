// Text pass: every glyph (and label box) of a frame as one instanced quad, in one draw. The
// quad's corners are the glyph's box in em around its label's anchor; the anchor is placed
// by the label's kind (screen pixels, a scene point facing the viewer, a plane of the scene).
// Coverage comes from the atlas's multi-channel signed distance: the median of the three
// channels, scaled to screen pixels by the texture's footprint (`fwidth`), so edges stay one
// pixel wide from 8 px to 300 px.

@group(0) @binding(1) var<uniform> tf: TextFrame;
@group(0) @binding(2) var<storage, read> quads: array<TextGlyph>;
@group(0) @binding(3) var<storage, read> labels: array<TextLabel>;
@group(0) @binding(4) var atlas: texture_2d<f32>;
@group(0) @binding(5) var atlas_sampler: sampler;
@group(0) @binding(6) var depth_tex: texture_2d<f32>;

struct TextOut {
    @builtin(position) position: vec4<f32>,
    // Atlas coordinates (0–1).
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) label: u32,
    @location(2) @interpolate(flat) kind: u32,
    // Reverse-Z depth of the quad at this corner.
    @location(3) depth: f32,
}

// Output pixels (x right, y down) to clip space at depth `z`, `w` 1.
fn pixels_to_clip(px: vec2<f32>, z: f32) -> vec4<f32> {
    let ndc = vec2<f32>(px.x / tf.viewport.x * 2.0 - 1.0, 1.0 - px.y / tf.viewport.y * 2.0);
    return vec4<f32>(ndc, z, 1.0);
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> TextOut {
    let q = quads[ii];
    let l = labels[q.label];
    var corner = vec2<f32>(f32(vi & 1u), f32(vi >> 1u));
    if (q.kind == TEXT_QUAD_FILL) && (vi == 3u) {
        // A triangle: the strip's last corner falls on the one before.
        corner = vec2<f32>(0.0, 1.0);
    }
    let em = mix(q.plane.xy, q.plane.zw, corner);
    var out: TextOut;
    out.label = q.label;
    out.kind = q.kind;
    // The atlas's rows run down; the quad's em y runs up.
    out.uv = vec2<f32>(mix(q.texels.x, q.texels.z, corner.x), mix(q.texels.w, q.texels.y, corner.y))
        / tf.atlas.xy;
    let scale = tf.viewport.z;
    let kind = l.flags.x;
    if q.kind == TEXT_QUAD_LEADER {
        return leader_corner(l, vi, out);
    }
    var clip: vec4<f32>;
    if kind == TEXT_ANCHOR_SCREEN {
        let px = (l.origin.xy + vec2<f32>(em.x, -em.y) * l.params.x) * scale;
        clip = pixels_to_clip(px, 1.0);
    } else if kind == TEXT_ANCHOR_BILLBOARD {
        let c = tf.to_clip * vec4<f32>(l.origin.xyz, 1.0);
        if c.w <= 0.0 {
            // Behind the eye: nothing.
            out.position = vec4<f32>(0.0, 0.0, -1.0, 1.0);
            return out;
        }
        let px = (l.params.yz + vec2<f32>(em.x, -em.y) * l.params.x) * scale;
        let ndc = px * vec2<f32>(2.0 / tf.viewport.x, -2.0 / tf.viewport.y);
        clip = vec4<f32>(c.xy + ndc * c.w, c.z, c.w);
    } else {
        let world = l.origin.xyz + l.x_axis.xyz * em.x + l.y_axis.xyz * em.y;
        clip = tf.to_clip * vec4<f32>(world, 1.0);
    }
    out.position = clip;
    out.depth = clip.z / clip.w;
    return out;
}

// Half the leader line's width plus the anti-aliasing fringe, target pixels.
const LEADER_HALF: f32 = 0.5;

// Corner `vi` of a billboard label's leader: a quad around the screen segment from the
// leader's start to the label's anchor, a pixel of fringe around it; `uv.x` carries the
// signed distance across, in target pixels.
fn leader_corner(l: TextLabel, vi: u32, base: TextOut) -> TextOut {
    var out = base;
    let a = tf.to_clip * vec4<f32>(l.leader.xyz, 1.0);
    let b = tf.to_clip * vec4<f32>(l.origin.xyz, 1.0);
    if (a.w <= 0.0) || (b.w <= 0.0) {
        out.position = vec4<f32>(0.0, 0.0, -1.0, 1.0);
        return out;
    }
    let half_size = 0.5 * tf.viewport.xy;
    let pa = a.xy / a.w * half_size;
    // The label's screen offset moves its end (pixels, y down).
    let pb = b.xy / b.w * half_size + vec2<f32>(l.params.y, -l.params.z) * tf.viewport.z;
    let d = pb - pa;
    let len = length(d);
    let dir = select(vec2<f32>(1.0, 0.0), d / len, len > 1e-6);
    let side = vec2<f32>(-dir.y, dir.x);
    let reach = LEADER_HALF * tf.viewport.z + 1.0;
    let at_b = (vi & 1u) == 1u;
    let across = select(-1.0, 1.0, (vi & 2u) != 0u) * reach;
    let p = select(pa - dir, pb + dir, at_b) + side * across;
    out.position = vec4<f32>(p / half_size, 1.0, 1.0);
    out.uv = vec2<f32>(across, 0.0);
    out.depth = 1.0;
    return out;
}

fn median3(c: vec3<f32>) -> f32 {
    return max(min(c.r, c.g), min(max(c.r, c.g), c.b));
}

@fragment
fn fs_main(in: TextOut) -> @location(0) vec4<f32> {
    // Sampled before any branch: `fwidth` needs the whole quad.
    let field = textureSample(atlas, atlas_sampler, in.uv).rgb;
    let texels_per_pixel = fwidth(in.uv) * tf.atlas.xy;
    let l = labels[in.label];
    if l.flags.y == 1u {
        let scene = textureLoad(depth_tex, vec2<i32>(in.position.xy), 0).x;
        if in.depth < scene * (1.0 - frame.tolerances.x) {
            discard;
        }
    }
    if in.kind == TEXT_QUAD_BOX {
        return l.background;
    }
    if in.kind == TEXT_QUAD_FILL {
        return l.colour;
    }
    if in.kind == TEXT_QUAD_LEADER {
        let cover = clamp(LEADER_HALF * tf.viewport.z + 0.5 - abs(in.uv.x), 0.0, 1.0);
        return vec4<f32>(l.colour.rgb, l.colour.a * cover);
    }
    // Distance range in screen pixels: the atlas range over the texels a pixel spans.
    let range_px = max(tf.atlas.z / max(0.5 * (texels_per_pixel.x + texels_per_pixel.y), 1e-6), 1.0);
    let distance = median3(field) - 0.5;
    let coverage = clamp(distance * range_px + 0.5, 0.0, 1.0);
    if coverage <= 0.0 {
        discard;
    }
    return vec4<f32>(l.colour.rgb, l.colour.a * coverage);
}
