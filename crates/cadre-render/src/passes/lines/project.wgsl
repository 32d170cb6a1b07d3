// What the lines' scan and draw share: the set's points and per-frame constants, and a
// segment's clip-space ends clipped at the near plane (`lines::reference` is the f64 twin).

@group(0) @binding(1) var<uniform> lf: LineFrame;
@group(0) @binding(2) var<storage, read> points: array<LinePoint>;

// Whether point `i` starts a polyline (the first point, or another polyline than the one
// before).
fn starts_polyline(i: u32) -> bool {
    return (i == 0u) || (points[i].polyline != points[max(i, 1u) - 1u].polyline);
}

// A clip-space position's place on the target, pixels (x right, y down).
fn to_pixels(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((0.5 * ndc.x + 0.5) * lf.viewport.x, (0.5 - 0.5 * ndc.y) * lf.viewport.y);
}

// The parameters (t0, t1) of the part of clip-space segment a–b in front of the near plane
// (reverse depth: z ≤ w); t0 > t1 when it is wholly behind.
fn near_range(a: vec4<f32>, b: vec4<f32>) -> vec2<f32> {
    let da = a.w - a.z;
    let db = b.w - b.z;
    if (da < 0.0) & (db < 0.0) {
        return vec2<f32>(1.0, 0.0);
    }
    let cut = da / (da - db);
    if da < 0.0 {
        return vec2<f32>(cut, 1.0);
    }
    if db < 0.0 {
        return vec2<f32>(0.0, cut);
    }
    return vec2<f32>(0.0, 1.0);
}

// The screen length (pixels) of the part in front of the near plane of the segment that ends
// at point `i` (0 where `i` starts a polyline).
fn length_into(i: u32) -> f32 {
    if starts_polyline(i) {
        return 0.0;
    }
    let a = lf.to_clip * vec4<f32>(points[i - 1u].position, 1.0);
    let b = lf.to_clip * vec4<f32>(points[i].position, 1.0);
    let r = near_range(a, b);
    if r.x >= r.y {
        return 0.0;
    }
    return distance(to_pixels(mix(a, b, r.x)), to_pixels(mix(a, b, r.y)));
}
