// The colour of a see-through surface, shared by every back-end's see-through phases so that
// a ray-cast sphere and a meshed part look alike. `normal` is in view space (any length).

// How squarely the surface faces the eye: 1 face-on, 0 edge-on.
fn facing_eye(normal: vec3<f32>) -> f32 {
    let len = length(normal);
    return select(1.0, abs(normal.z) / len, len > 0.0);
}

// X-ray mode: more opaque where the surface is seen edge-on (a Fresnel-like rim), so the
// inside of an assembly shows through its shell.
fn xray_colour(base: vec4<f32>, normal: vec3<f32>) -> vec4<f32> {
    let facing = facing_eye(normal);
    let rim = (1.0 - facing) * (1.0 - facing);
    let alpha = mix(0.06, 0.45, rim);
    return vec4<f32>(base.rgb * (0.55 + 0.45 * facing), alpha);
}

// A see-through part of an opaque view: its colour lit by a headlight, with its opacity.
fn transparent_colour(base: vec4<f32>, normal: vec3<f32>) -> vec4<f32> {
    let facing = facing_eye(normal);
    return vec4<f32>(base.rgb * (0.35 + 0.65 * facing), base.a);
}
