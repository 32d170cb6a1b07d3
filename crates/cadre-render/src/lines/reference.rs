//! The lines' screen-space arc lengths and dashes computed on the CPU in `f64`, with the GPU
//! scan's conventions (`passes/lines/scan.wgsl`): each segment clipped at the near plane
//! before it is measured, lengths in target pixels, restarting at 0 at every polyline's
//! first point. The oracle of the GPU path, and what the renderer uploads instead where the
//! adapter has no compute shaders.

use super::{LineSet, Stipple};
use crate::Camera;
use glam::{DMat4, DVec2, DVec3, DVec4};

/// World → clip space of `camera` for a target of `aspect` (width / height).
pub fn world_to_clip(camera: &Camera, aspect: f64) -> DMat4 {
    camera.projection_matrix(aspect) * camera.view_rotation() * DMat4::from_translation(-camera.eye)
}

/// A clip-space point's position on a `size` target, pixels (x right, y down; pixel
/// `(i, j)` covers `[i, i + 1) × [j, j + 1)`).
pub fn to_pixels(clip: DVec4, (w, h): (f64, f64)) -> DVec2 {
    let ndc = clip.truncate().truncate() / clip.w;
    DVec2::new((0.5 * ndc.x + 0.5) * w, (0.5 - 0.5 * ndc.y) * h)
}

/// The part of the clip-space segment `a`–`b` in front of the near plane (reverse depth:
/// kept where `z ≤ w`), as parameters `(t0, t1)` along it; `None` when it is wholly behind.
pub fn near_clip(a: DVec4, b: DVec4) -> Option<(f64, f64)> {
    let (da, db) = (a.w - a.z, b.w - b.z);
    if da < 0.0 && db < 0.0 {
        return None;
    }
    let cut = da / (da - db);
    Some(if da < 0.0 {
        (cut, 1.0)
    } else if db < 0.0 {
        (0.0, cut)
    } else {
        (0.0, 1.0)
    })
}

/// The screen length in pixels of the part of `a`–`b` (world) in front of the near plane.
pub fn screen_length(to_clip: DMat4, a: DVec3, b: DVec3, size: (f64, f64)) -> f64 {
    let (ca, cb) = (to_clip * a.extend(1.0), to_clip * b.extend(1.0));
    match near_clip(ca, cb) {
        Some((t0, t1)) => {
            to_pixels(ca.lerp(cb, t0), size).distance(to_pixels(ca.lerp(cb, t1), size))
        }
        None => 0.0,
    }
}

/// Every point's screen arc length from its polyline's start (pixels of a `size` target),
/// polylines in order, points in order: what the GPU scan writes.
pub fn arc_lengths(set: &LineSet, camera: &Camera, (w, h): (u32, u32)) -> Vec<f64> {
    let size = (f64::from(w), f64::from(h));
    let to_clip = world_to_clip(camera, size.0 / size.1);
    let mut out = Vec::with_capacity(set.point_count());
    for polyline in &set.polylines {
        let mut s = 0.0;
        for (k, p) in polyline.points.iter().enumerate() {
            if k > 0 {
                s += screen_length(to_clip, polyline.points[k - 1], *p, size);
            }
            out.push(s);
        }
    }
    out
}

/// The arc lengths where `stipple` switches between drawn and not drawn on `[0, length]`
/// (its dash ends), in order.
pub fn dash_ends(stipple: Stipple, length: f64) -> Vec<f64> {
    let factor = f64::from(stipple.factor.max(1));
    let mut ends = Vec::new();
    let mut k = 1u64;
    while (k as f64) * factor < length {
        let s = k as f64 * factor;
        if stipple.drawn_at(s - 0.5 * factor) != stipple.drawn_at(s + 0.5 * factor) {
            ends.push(s);
        }
        k += 1;
    }
    ends
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lines::Polyline;
    use crate::{Camera, ViewPreset};

    fn camera() -> Camera {
        Camera::fit(
            DVec3::new(-1.0, -1.0, -1.0),
            DVec3::ONE,
            ViewPreset::Front,
            false,
            1.0,
        )
    }

    #[test]
    fn arc_length_restarts_at_each_polyline_and_adds_up_along_one() {
        let line = |x: f64| Polyline {
            points: vec![
                DVec3::new(x, 0.0, 0.0),
                DVec3::new(x + 0.5, 0.0, 0.0),
                DVec3::new(x + 0.5, 0.0, 0.5),
            ],
            ..Polyline::default()
        };
        let set = LineSet {
            polylines: vec![line(-1.0), line(0.0)],
            styles: vec![],
        };
        let s = arc_lengths(&set, &camera(), (200, 200));
        assert_eq!(s.len(), 6);
        assert_eq!(s[0], 0.0);
        assert_eq!(s[3], 0.0);
        assert!(
            s[1] > 10.0 && (s[2] - 2.0 * s[1]).abs() < 1e-6 * s[2],
            "{s:?}"
        );
        // Seen from the front (perspective) the second copy's legs are as long as each
        // other too.
        assert!((s[5] - 2.0 * s[4]).abs() < 1e-3 * s[5], "{s:?}");
    }

    #[test]
    fn a_segment_through_the_eye_counts_only_its_part_in_front() {
        let cam = camera();
        let to_clip = world_to_clip(&cam, 1.0);
        let ahead = cam.target;
        let behind = cam.eye - (cam.target - cam.eye);
        let side = DVec3::new(0.0, 0.0, 0.3);
        let through = screen_length(to_clip, ahead + side, behind + side, (100.0, 100.0));
        assert!(through.is_finite() && through > 0.0, "{through}");
        assert_eq!(
            screen_length(to_clip, behind, behind + side, (100.0, 100.0)),
            0.0
        );
    }

    #[test]
    fn dash_ends_follow_the_pattern_bits() {
        let dashed = Stipple::parse("dashed", 2).unwrap();
        // 0x00FF: bits 0–7 drawn, 8–15 not: ends every 16 pixels at factor 2.
        assert_eq!(dash_ends(dashed, 70.0), vec![16.0, 32.0, 48.0, 64.0]);
        assert!(dashed.drawn_at(0.0) && !dashed.drawn_at(16.5) && dashed.drawn_at(32.0));
        assert!(dash_ends(Stipple::SOLID, 100.0).is_empty());
        assert_eq!(Stipple::parse("0x0C0F", 1).unwrap().pattern, 0x0C0F);
        assert!(Stipple::parse("wavy", 1).is_none());
    }
}
