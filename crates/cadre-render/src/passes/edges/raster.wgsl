// Edges raster: the visible-edges mode's segments rasterized in compute, one invocation per
// segment and instance, into a coverage buffer that `composite.wgsl` then blends over the
// image. The quads of `edges.wgsl` cost two triangles each through the rasterizer's
// per-primitive work, which is what a scene of many small parts spends its edges on: on
// lavapipe that work runs on the one submitting thread (vertex shading, clipping, setup,
// binning) where compute runs on every core, and on GPUs with little raster hardware (Hopper)
// primitives are the bottleneck where compute is not.
//
// Each pixel gets exactly the coverage the quad's fragment would (the edge's half width plus
// half a pixel, less the distance from the line, clamped to [0, 1]) and the same depth test
// against the visibility depth. The quads blend each fragment over the last, 1 − Π(1 − aᵢ)
// in all for one colour; here each pixel sums −ln(1 − aᵢ) in fixed point with an atomic add
// (in any order, to the same total) and the composite takes 1 − exp(−sum). Highlighted
// segments (another colour and width) are left to the quads (`RASTERED` there), as are the
// hidden-dashed and all-edges modes and frames with section planes.

@group(0) @binding(4) var<storage, read_write> cover: array<atomic<u32>>;

// No section planes here (`behind_its_solid` reads it).
override SECTIONS: bool = false;

// Fixed-point scale of the summed −ln(1 − a): each fragment adds at most −ln(10⁻⁶) ≈ 13.8,
// and a pixel stops taking them once opaque (`SATURATED`), far from the 2³² wrap.
const COVER_SCALE: f32 = 65536.0;
// The sum past which a pixel is opaque (20 in fixed point).
const SATURATED: u32 = 1310720u;
// Invocations per workgroup (`raster.rs` dispatches by it).
const GROUP: u32 = 64u;

@compute @workgroup_size(64)
fn cs_main(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = gid.x + gid.y * groups.x * GROUP;
    let count = call.range.y;
    if i >= count * call.instances {
        return;
    }
    let d = instance_draw(i / count);
    let seg = segments[call.range.x + i % count];
    if behind_its_solid(seg, d) | (highlight_of(seg, d.instance).w > 0.0) {
        return;
    }
    let e = screen_segment(seg, d);
    if e.both_behind {
        return;
    }
    rasterize(e);
}

// Adds segment `e`'s coverage to every pixel its quad covers. The loop runs along the
// segment's major axis (columns, or rows for a steep one), a few pixels across each.
fn rasterize(e: ScreenSegment) {
    let size = frame.viewport.xy;
    let half = 0.5 * frame.viewport.z + 0.5;
    // Past the ends by half a pixel, or by the half width for a point (as `segment_quad`).
    let ext = select(0.5, half, e.len <= 1e-6);
    let side = vec2<f32>(-e.dir.y, e.dir.x);
    // Pixels from the image's bottom-left corner, y up.
    let qa = e.sa + 0.5 * size;
    let za = e.ca.z / e.ca.w;
    let zb = e.cb.z / e.cb.w;
    let alpha = frame.edge_colour.a;
    // Swapped: rows are the major axis (a steep segment), x and y exchanged below.
    let steep = abs(e.dir.y) > abs(e.dir.x);
    let m_dir = select(e.dir.x, e.dir.y, steep);
    let t_dir = select(e.dir.y, e.dir.x, steep);
    let m_a = select(qa.x, qa.y, steep);
    let t_a = select(qa.y, qa.x, steep);
    let m_size = select(size.x, size.y, steep);
    let t_size = select(size.y, size.x, steep);
    // The quad's reach along the major axis (its four corners'), clamped to the image.
    let lo_end = qa - e.dir * ext;
    let hi_end = qa + e.dir * (e.len + ext);
    let reach = abs(select(side.x, side.y, steep)) * half;
    let m_lo = min(select(lo_end.x, lo_end.y, steep), select(hi_end.x, hi_end.y, steep)) - reach;
    let m_hi = max(select(lo_end.x, lo_end.y, steep), select(hi_end.x, hi_end.y, steep)) + reach;
    let first = i32(clamp(floor(m_lo), 0.0, m_size));
    let last = i32(clamp(ceil(m_hi), 0.0, m_size));
    // Across the major axis the band |v| < half spans half / |m_dir| each side of the line
    // (|m_dir| ≥ 1/√2): a few pixels.
    let span = half / max(abs(m_dir), 0.5);
    let across = i32(ceil(2.0 * span)) + 2;
    let width = u32(size.x);
    for (var m = first; m < last; m++) {
        let mc = f32(m) + 0.5;
        // The line's minor coordinate at this column's centre.
        let t_line = t_a + (mc - m_a) * t_dir / m_dir;
        let t_first = i32(floor(t_line - span - 0.5));
        for (var k = 0; k < across; k++) {
            let t = t_first + k;
            let tc = f32(t) + 0.5;
            let p = select(vec2<f32>(mc, tc), vec2<f32>(tc, mc), steep);
            let outside = (t < 0) | (tc >= t_size);
            let u = dot(p - qa, e.dir);
            let v = dot(p - qa, side);
            let coverage = clamp(half - abs(v), 0.0, 1.0);
            let z = mix(za, zb, clamp((u + ext) / (e.len + 2.0 * ext), 0.0, 1.0));
            let col = u32(p.x);
            let row = u32(size.y - p.y);
            let off_quad = outside | (u < -ext) | (u > e.len + ext) | (coverage <= 0.0)
                | (z < 0.0) | (z > 1.0);
            if off_quad {
                continue;
            }
            // Reverse Z: nearer is larger; the tolerance keeps an edge on its own faces
            // visible (as the quads' test).
            let scene = textureLoad(depth_tex, vec2<i32>(i32(col), i32(row)), 0).x;
            if z < scene * (1.0 - frame.tolerances.x) {
                continue;
            }
            let a = min(alpha * coverage, 1.0 - 1e-6);
            // A pixel already opaque (a sum past 20, 1 − e⁻²⁰) takes no more: thousands of
            // segments piled on one pixel (a huge assembly zoomed out to a few pixels) would
            // otherwise wrap the sum around.
            let at = row * width + col;
            if atomicLoad(&cover[at]) < SATURATED {
                atomicAdd(&cover[at], u32(-log(1.0 - a) * COVER_SCALE + 0.5));
            }
        }
    }
}
