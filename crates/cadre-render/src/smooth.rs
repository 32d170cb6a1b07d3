//! Edge smoothing of a rendered image (FXAA-style morphological anti-aliasing, on the CPU):
//! the anti-aliasing of images drawn on a CPU adapter, where 2 × 2 supersampling costs four
//! times every pass. B-Rep edges and wires are already drawn with analytic coverage; what is
//! left jagged in a 1× image is where a face meets the background or a face of another
//! colour and the one-pixel silhouette outlines. Those are found here from the image's
//! luma: at each pixel whose neighbourhood has enough contrast, the edge's direction is taken
//! from the 3 × 3 gradients, the edge is followed both ways to its ends, and the pixel is
//! blended towards its neighbour across the edge by how far it lies from the edge's
//! midpoint: a staircase becomes the ramp that its area coverage would give.
//!
//! It runs after the readback, rows in parallel (an 800 × 600 image is a few milliseconds on
//! two cores), where a GPU pass on llvmpipe would pay its per-pixel cost for every pixel of
//! the image, flat ones included.

use crate::renderer::{SRGB_TO_LINEAR, linear_to_srgb, unit_to_byte};
use image::RgbaImage;
use rayon::prelude::*;

/// Contrast below which a pixel is left as it is, relative to its neighbourhood's brightest
/// luma (FXAA's "quality" threshold)...
const RELATIVE_THRESHOLD: f32 = 0.125;
/// ...and in absolute luma (dark regions).
const ABSOLUTE_THRESHOLD: f32 = 0.0312;
/// Weight of the sub-pixel term (a pixel unlike all its neighbours, which no edge search can
/// place). FXAA's default is 0.75; CAD images are mostly thin lines already drawn with
/// their coverage, which that much would blur, so only a quarter of it is kept.
const SUBPIXEL: f32 = 0.25;
/// Steps of the search along an edge, in pixels from the pixel: one by one near it, then
/// coarser (an edge longer than the last step is treated as reaching it).
const STEPS: [i32; 8] = [1, 2, 3, 4, 6, 8, 12, 16];

/// The image with its jagged edges smoothed; pixels whose neighbourhood is flat are copied.
/// Colour is blended in linear light, alpha linearly.
pub fn smooth_edges(image: &RgbaImage) -> RgbaImage {
    let (w, h) = (image.width() as i32, image.height() as i32);
    if w < 3 || h < 3 {
        return image.clone();
    }
    let src = image.as_raw();
    // Whole pixels as words, for the flat test below.
    let words: Vec<u32> = src
        .chunks_exact(4)
        .map(|p| u32::from_ne_bytes([p[0], p[1], p[2], p[3]]))
        .collect();
    let luma: Vec<f32> = src
        .par_chunks_exact(4)
        .map(|p| {
            (0.299 * f32::from(p[0]) + 0.587 * f32::from(p[1]) + 0.114 * f32::from(p[2])) / 255.0
        })
        .collect();
    let frame = Luma {
        values: &luma,
        w,
        h,
    };
    let mut out = src.clone();
    out.par_chunks_mut(4 * w as usize)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as i32;
            for x in 0..w {
                // A pixel equal to its four neighbours (most of an image) has no edge: the
                // test on whole words keeps the flat pixels to a few loads.
                if x > 0 && x < w - 1 && y > 0 && y < h - 1 {
                    let i = (y * w + x) as usize;
                    let c = words[i];
                    if words[i - 1] == c
                        && words[i + 1] == c
                        && words[i - w as usize] == c
                        && words[i + w as usize] == c
                    {
                        continue;
                    }
                }
                if let Some((dx, dy, t)) = frame.blend_at(x, y) {
                    let i = 4 * (y * w + x) as usize;
                    let j = 4 * ((y + dy) * w + x + dx) as usize;
                    let px = &mut row[4 * x as usize..4 * x as usize + 4];
                    blend(px, &src[i..i + 4], &src[j..j + 4], t);
                }
            }
        });
    RgbaImage::from_raw(image.width(), image.height(), out).expect("same size as the input")
}

/// `px` = `a` moved by `t` towards `b`: colour in linear light, alpha linearly.
fn blend(px: &mut [u8], a: &[u8], b: &[u8], t: f32) {
    let lut = &*SRGB_TO_LINEAR;
    for c in 0..3 {
        let (la, lb) = (lut[usize::from(a[c])], lut[usize::from(b[c])]);
        px[c] = unit_to_byte(linear_to_srgb(la + (lb - la) * t));
    }
    let (aa, ab) = (f32::from(a[3]), f32::from(b[3]));
    px[3] = (aa + (ab - aa) * t).round().clamp(0.0, 255.0) as u8;
}

/// The image's luma, read with coordinates clamped to its border.
struct Luma<'a> {
    values: &'a [f32],
    w: i32,
    h: i32,
}

impl Luma<'_> {
    fn at(&self, x: i32, y: i32) -> f32 {
        let (x, y) = (x.clamp(0, self.w - 1), y.clamp(0, self.h - 1));
        self.values[(y * self.w + x) as usize]
    }

    /// Where pixel (x, y) blends to, if anywhere: the neighbour's offset (one of the four
    /// axis neighbours) and the fraction in (0, 1].
    fn blend_at(&self, x: i32, y: i32) -> Option<(i32, i32, f32)> {
        let m = self.at(x, y);
        let (n, s, e, w) = (
            self.at(x, y - 1),
            self.at(x, y + 1),
            self.at(x + 1, y),
            self.at(x - 1, y),
        );
        let hi = m.max(n).max(s).max(e).max(w);
        let lo = m.min(n).min(s).min(e).min(w);
        let range = hi - lo;
        if range < ABSOLUTE_THRESHOLD.max(hi * RELATIVE_THRESHOLD) {
            return None;
        }
        let (nw, ne, sw, se) = (
            self.at(x - 1, y - 1),
            self.at(x + 1, y - 1),
            self.at(x - 1, y + 1),
            self.at(x + 1, y + 1),
        );
        // Second differences across each axis: a horizontal edge (luma changing along y)
        // has a large vertical one.
        let across_y = (0.25 * nw - 0.5 * w + 0.25 * sw).abs()
            + (0.5 * n - m + 0.5 * s).abs()
            + (0.25 * ne - 0.5 * e + 0.25 * se).abs();
        let across_x = (0.25 * nw - 0.5 * n + 0.25 * ne).abs()
            + (0.5 * w - m + 0.5 * e).abs()
            + (0.25 * sw - 0.5 * s + 0.25 * se).abs();
        let horizontal = across_y >= across_x;
        // The blend axis (perpendicular to the edge) and the two neighbours on it.
        let (ax, ay) = if horizontal { (0, 1) } else { (1, 0) };
        let (before, after) = if horizontal { (n, s) } else { (w, e) };
        let (g_before, g_after) = ((before - m).abs(), (after - m).abs());
        // The steeper side is the edge's.
        let (side, side_luma, gradient) = if g_before >= g_after {
            (-1, before, g_before)
        } else {
            (1, after, g_after)
        };
        let (sx, sy) = (ax * side, ay * side);
        let edge_offset = self.edge_offset((x, y), (sx, sy), m, side_luma, gradient);
        // The sub-pixel term: the pixel against the mean of its neighbourhood.
        let mean = (2.0 * (n + s + e + w) + nw + ne + sw + se) / 12.0;
        let sub = ((mean - m).abs() / range).clamp(0.0, 1.0);
        let sub = (-2.0 * sub + 3.0) * sub * sub;
        let t = edge_offset.max(sub * sub * SUBPIXEL);
        (t > 1.0 / 512.0).then_some((sx, sy, t))
    }

    /// How far pixel `p` blends towards its neighbour at `p + side` across the edge between
    /// them: the edge is followed both ways along the line between the two pixels until the
    /// luma there leaves the edge's, and the pixel blends by how far it is from the edge
    /// segment's midpoint (0 at the middle, ½ at an end), only when the nearer end is where
    /// the edge turns towards this pixel (FXAA's end test).
    fn edge_offset(
        &self,
        (x, y): (i32, i32),
        (sx, sy): (i32, i32),
        m: f32,
        side_luma: f32,
        gradient: f32,
    ) -> f32 {
        // Along the edge: perpendicular to the blend axis.
        let (tx, ty) = (sy.abs(), sx.abs());
        let local = 0.5 * (m + side_luma);
        let threshold = 0.25 * gradient;
        // The luma of the line between the pixel row and the side row at `k` steps, minus
        // the edge's local mean.
        let line = |k: i32| {
            let (px, py) = (x + k * tx, y + k * ty);
            0.5 * (self.at(px, py) + self.at(px + sx, py + sy)) - local
        };
        let search = |dir: i32| {
            let mut last = STEPS[STEPS.len() - 1];
            let mut end = line(dir * last);
            for k in STEPS {
                let l = line(dir * k);
                if l.abs() >= threshold {
                    last = k;
                    end = l;
                    break;
                }
            }
            (last, end)
        };
        let (d_neg, end_neg) = search(-1);
        let (d_pos, end_pos) = search(1);
        let (d, end) = if d_neg < d_pos {
            (d_neg, end_neg)
        } else {
            (d_pos, end_pos)
        };
        let length = (d_neg + d_pos) as f32;
        // The edge ends on this pixel's side when the luma there moves the way this pixel
        // differs from the local mean; otherwise the staircase step is on the other row.
        if (end < 0.0) == (m - local < 0.0) {
            return 0.0;
        }
        (0.5 - d as f32 / length).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A white image with a black half-plane below the line y = y0 + slope · x, drawn aliased
    /// (pixel centres) or with each pixel's exact area coverage.
    fn half_plane(w: u32, h: u32, slope: f32, y0: f32, exact: bool) -> RgbaImage {
        RgbaImage::from_fn(w, h, |x, y| {
            let coverage = if exact {
                // Area of the pixel under the line, by 16 × 16 samples.
                let mut inside = 0;
                for i in 0..16 {
                    for j in 0..16 {
                        let (px, py) = (
                            x as f32 + (i as f32 + 0.5) / 16.0,
                            y as f32 + (j as f32 + 0.5) / 16.0,
                        );
                        inside += u32::from(py > y0 + slope * px);
                    }
                }
                inside as f32 / 256.0
            } else {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                f32::from(u8::from(py > y0 + slope * px))
            };
            // Black covering `coverage` of white, in linear light.
            let v = (linear_to_srgb(1.0 - coverage) * 255.0).round() as u8;
            image::Rgba([v, v, v, 255])
        })
    }

    /// Mean absolute difference in linear light of the colour channels.
    fn error(a: &RgbaImage, b: &RgbaImage) -> f32 {
        let lut = &*SRGB_TO_LINEAR;
        let sum: f32 = a
            .pixels()
            .zip(b.pixels())
            .map(|(p, q)| (lut[usize::from(p[0])] - lut[usize::from(q[0])]).abs())
            .sum();
        sum / (a.width() * a.height()) as f32
    }

    #[test]
    fn a_jagged_edge_comes_closer_to_its_area_coverage() {
        // (slope, bound on the error left): long staircases (slopes far from 45°) are where
        // the edge search places the ramp; near 45° the steps are one pixel and only the
        // sub-pixel term helps.
        for (slope, bound) in [
            (0.2f32, 0.5),
            (-0.35, 0.5),
            (0.3333, 0.75),
            (3.0, 0.8),
            (5.0, 0.5),
            (0.9, 0.85),
        ] {
            let exact = half_plane(64, 64, slope, 20.0, true);
            let jagged = half_plane(64, 64, slope, 20.0, false);
            let smoothed = smooth_edges(&jagged);
            let (before, after) = (error(&jagged, &exact), error(&smoothed, &exact));
            // The negative control is `before`: the aliased image itself is far from the
            // exact coverage.
            assert!(
                before > 0.002,
                "slope {slope}: the aliased image differs ({before})"
            );
            assert!(
                after < bound * before,
                "slope {slope}: smoothing should bring the edge closer to its coverage ({before} → {after})"
            );
        }
    }

    #[test]
    fn flat_regions_and_an_already_smooth_ramp_are_kept() {
        let flat = RgbaImage::from_pixel(32, 24, image::Rgba([40, 90, 200, 255]));
        assert_eq!(smooth_edges(&flat), flat);
        // A gentle horizontal ramp has no contrast above the threshold anywhere.
        let ramp = RgbaImage::from_fn(64, 8, |x, _| {
            let v = (x * 2) as u8 + 60;
            image::Rgba([v, v, v, 255])
        });
        assert_eq!(smooth_edges(&ramp), ramp);
    }

    #[test]
    fn tiny_images_are_returned_as_they_are() {
        let tiny = RgbaImage::from_pixel(2, 5, image::Rgba([0, 0, 0, 255]));
        assert_eq!(smooth_edges(&tiny), tiny);
    }
}
