//! Image comparison for golden-image tests: per-pixel tolerance plus a largest fraction of
//! differing pixels, and a diff image that shows where.

use image::RgbaImage;

/// How two images differ.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Fraction of pixels whose largest channel difference exceeds the tolerance (1 when the
    /// sizes differ).
    pub differing: f64,
    /// Largest channel difference over the image (0–255).
    pub max_delta: u8,
    /// Differing pixels in red over a faded copy of the expected image.
    pub diff: RgbaImage,
}

impl Comparison {
    /// Whether at most `max_fraction` of the pixels differ.
    pub fn passes(&self, max_fraction: f64) -> bool {
        self.differing <= max_fraction
    }
}

/// Compares `actual` with `expected`: a pixel differs when any channel differs by more than
/// `tolerance`.
pub fn compare(actual: &RgbaImage, expected: &RgbaImage, tolerance: u8) -> Comparison {
    if actual.dimensions() != expected.dimensions() {
        return Comparison {
            differing: 1.0,
            max_delta: 255,
            diff: actual.clone(),
        };
    }
    let mut max_delta = 0u8;
    let mut count = 0usize;
    let diff = RgbaImage::from_fn(actual.width(), actual.height(), |x, y| {
        let (a, e) = (actual.get_pixel(x, y).0, expected.get_pixel(x, y).0);
        let d = (0..4).map(|c| a[c].abs_diff(e[c])).max().unwrap_or(0);
        max_delta = max_delta.max(d);
        if d > tolerance {
            count += 1;
            image::Rgba([255, 0, 0, 255])
        } else {
            let fade = |v: u8| 192 + v / 4;
            image::Rgba([fade(e[0]), fade(e[1]), fade(e[2]), 255])
        }
    });
    let pixels = (u64::from(actual.width()) * u64::from(actual.height())).max(1);
    Comparison {
        differing: count as f64 / pixels as f64,
        max_delta,
        diff,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerance_and_fraction_decide() {
        let a = RgbaImage::from_pixel(10, 10, image::Rgba([100, 100, 100, 255]));
        let mut b = a.clone();
        b.put_pixel(3, 3, image::Rgba([110, 100, 100, 255]));
        let c = compare(&b, &a, 16);
        assert_eq!(c.differing, 0.0);
        assert_eq!(c.max_delta, 10);
        b.put_pixel(4, 4, image::Rgba([200, 100, 100, 255]));
        let c = compare(&b, &a, 16);
        assert_eq!(c.differing, 0.01);
        assert!(c.passes(0.01) && !c.passes(0.005));
        assert_eq!(c.diff.get_pixel(4, 4).0, [255, 0, 0, 255]);
        let small = RgbaImage::new(5, 5);
        assert_eq!(compare(&small, &a, 16).differing, 1.0);
    }
}
