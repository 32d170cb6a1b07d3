//! Glyphs whose contours overlap.
//!
//! `fdsm` measures the distance to every edge of a shape, the parts of a contour that lie
//! inside another contour included: where a symbol font draws ⌖ as a circle crossed by two
//! bars, the field has false edges inside the ink and the drawn glyph gets holes (measured:
//! 224 pixels wrong at 200 px before this). msdfgen resolves this with its overlapping-contour
//! combiner, which `fdsm` lacks (its docs say so); this is that combiner over `fdsm`'s
//! per-contour fields: each contour's distance field generated alone, its sign made
//! "inside this contour", then per texel the inner distance (nearest contour the texel is
//! inside of) or the outer one (nearest hole it is in) is taken as msdfgen does.

use super::RANGE_PX;
use fdsm::bezier::Point;
use fdsm::bezier::scanline::FillRule;
use fdsm::generate::generate_msdf;
use fdsm::render::correct_sign_msdf;
use fdsm::shape::{ColoredContour, Shape};
use image::{ImageBuffer, Rgb};

type Field = ImageBuffer<Rgb<f32>, Vec<f32>>;

/// Points along a contour (8 a curve), in order.
fn flatten(contour: &ColoredContour) -> Vec<Point> {
    let mut out = Vec::new();
    for s in &contour.segments {
        for i in 0..8 {
            out.push(s.segment.get(f64::from(i) / 8.0));
        }
    }
    out
}

/// Twice the signed area of a closed polygon.
fn area(ring: &[Point]) -> f64 {
    (0..ring.len())
        .map(|i| {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum()
}

/// Whether segments a–b and c–d cross or touch.
fn cross((a, b): (Point, Point), (c, d): (Point, Point)) -> bool {
    let side = |p: Point, q: Point, r: Point| (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    let (d1, d2) = (side(a, b, c), side(a, b, d));
    let (d3, d4) = (side(c, d, a), side(c, d, b));
    // Touching counts (a crossing may fall on a sample point); collinear pieces do not.
    let collinear = d1 == 0.0 && d2 == 0.0;
    !collinear && d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}

/// Each contour's winding (+1 filled, −1 a hole, by its orientation against the largest
/// contour's) when two contours of `shape` cross; `None` when none do (the usual case, left
/// to `fdsm` alone).
pub(super) fn windings(shape: &Shape<ColoredContour>) -> Option<Vec<i8>> {
    if shape.contours.len() < 2 {
        return None;
    }
    let rings: Vec<Vec<Point>> = shape.contours.iter().map(flatten).collect();
    let edges = |r: &[Point]| -> Vec<(Point, Point)> {
        (0..r.len()).map(|i| (r[i], r[(i + 1) % r.len()])).collect()
    };
    let crossing = (0..rings.len()).any(|i| {
        let a = edges(&rings[i]);
        rings[i + 1..]
            .iter()
            .any(|other| edges(other).iter().any(|&e| a.iter().any(|&f| cross(e, f))))
    });
    if !crossing {
        return None;
    }
    let areas: Vec<f64> = rings.iter().map(|r| area(r)).collect();
    let largest = areas
        .iter()
        .copied()
        .fold(0.0f64, |m, a| if a.abs() > m.abs() { a } else { m });
    Some(
        areas
            .iter()
            .map(|a| if a * largest >= 0.0 { 1 } else { -1 })
            .collect(),
    )
}

/// A distance as three channels (texels; positive inside the glyph).
type Distance = [f64; 3];

fn median(d: Distance) -> f64 {
    d[0].max(d[1]).min(d[0].min(d[1]).max(d[2]))
}

/// Per channel the distance nearest zero among `ds` (msdfgen's merged edge selectors);
/// −∞ when `ds` is empty.
fn merge<'a>(ds: impl Iterator<Item = &'a Distance>) -> Distance {
    let mut out = [f64::NEG_INFINITY; 3];
    for d in ds {
        for c in 0..3 {
            if d[c].abs() < out[c].abs() {
                out[c] = d[c];
            }
        }
    }
    out
}

/// msdfgen's `OverlappingContourCombiner::distance` over the contours' distances `ds` (each
/// positive inside the glyph where its winding is +1).
fn combine(ds: &[Distance], windings: &[i8]) -> Distance {
    let both = || ds.iter().zip(windings);
    let shape = merge(ds.iter());
    let inner = merge(
        both()
            .filter(|(d, w)| **w > 0 && median(**d) >= 0.0)
            .map(|(d, _)| d),
    );
    let outer = merge(
        both()
            .filter(|(d, w)| **w < 0 && median(**d) <= 0.0)
            .map(|(d, _)| d),
    );
    let (inner_s, outer_s) = (median(inner), median(outer));
    let (mut distance, winding) = if inner_s >= 0.0 && inner_s.abs() <= outer_s.abs() {
        let mut d = inner;
        for (c, _) in both().filter(|(_, w)| **w > 0) {
            let m = median(*c);
            if m.abs() < outer_s.abs() && m > median(d) {
                d = *c;
            }
        }
        (d, 1)
    } else if outer_s <= 0.0 && outer_s.abs() < inner_s.abs() {
        let mut d = outer;
        for (c, _) in both().filter(|(_, w)| **w < 0) {
            let m = median(*c);
            if m.abs() < inner_s.abs() && m < median(d) {
                d = *c;
            }
        }
        (d, -1)
    } else {
        return shape;
    };
    for (c, _) in both().filter(|(_, w)| i32::from(**w) != winding) {
        let m = median(*c);
        if m * median(distance) >= 0.0 && m.abs() < median(distance).abs() {
            distance = *c;
        }
    }
    if median(distance) == median(shape) {
        distance = shape;
    }
    distance
}

/// The glyph's field from its contours' fields combined by `windings`.
pub(super) fn combined_field(shape: &Shape<ColoredContour>, windings: &[i8], out: &mut Field) {
    let (w, h) = out.dimensions();
    let fields: Vec<Field> = shape
        .contours
        .iter()
        .map(|contour| {
            let alone = Shape {
                contours: vec![contour.clone()],
            }
            .prepare();
            let mut field = Field::new(w, h);
            generate_msdf(&alone, RANGE_PX, &mut field);
            // Positive inside this contour, whatever its orientation.
            correct_sign_msdf(&mut field, &alone, FillRule::Nonzero);
            field
        })
        .collect();
    let mut ds = vec![[0.0; 3]; fields.len()];
    for y in 0..h {
        for x in 0..w {
            for ((d, field), &winding) in ds.iter_mut().zip(&fields).zip(windings) {
                let p = field.get_pixel(x, y).0;
                // Inside a hole contour is outside the glyph.
                *d = p.map(|v| f64::from(winding) * (f64::from(v) - 0.5) * RANGE_PX);
            }
            let d = combine(&ds, windings);
            out.put_pixel(x, y, Rgb(d.map(|v| (v / RANGE_PX + 0.5) as f32)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdsm::bezier::Segment;
    use fdsm::shape::Contour;

    fn rectangle((x0, y0): (f64, f64), (x1, y1): (f64, f64)) -> Contour {
        let p = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)].map(|(x, y)| Point::new(x, y));
        Contour {
            segments: (0..4)
                .map(|i| Segment::line(p[i], p[(i + 1) % 4]))
                .collect(),
        }
    }

    /// Texels whose median sign disagrees with "inside the union of the two bars" (the
    /// texel centres over a texel from any edge).
    fn wrong(field: &Field, inside: impl Fn(f64, f64) -> bool) -> usize {
        let mut wrong = 0;
        for (x, y, p) in field.enumerate_pixels() {
            let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let m = median(p.0.map(|v| f64::from(v) - 0.5));
            let near_edge = [8.0, 24.0, 14.0, 18.0]
                .iter()
                .any(|e| (cx - e).abs() < 1.0 || (cy - e).abs() < 1.0);
            if !near_edge && (m > 0.0) != inside(cx, cy) {
                wrong += 1;
            }
        }
        wrong
    }

    #[test]
    fn a_cross_of_two_overlapping_bars_is_filled_where_they_meet() {
        // A plus: a horizontal and a vertical bar, both counter-clockwise, crossing.
        let shape = Shape {
            contours: vec![
                rectangle((8.0, 14.0), (24.0, 18.0)),
                rectangle((14.0, 8.0), (18.0, 24.0)),
            ],
        };
        let inside = |x: f64, y: f64| {
            let h = (8.0..24.0).contains(&x) && (14.0..18.0).contains(&y);
            let v = (14.0..18.0).contains(&x) && (8.0..24.0).contains(&y);
            h || v
        };
        let coloured = Shape::edge_coloring_simple(shape, 0.03, 7);
        let windings = windings(&coloured).expect("the bars cross");
        assert_eq!(windings, vec![1, 1]);
        let prepared = coloured.prepare();
        let mut combined = Field::new(32, 32);
        combined_field(&coloured, &windings, &mut combined);
        correct_sign_msdf(&mut combined, &prepared, FillRule::Nonzero);
        assert_eq!(wrong(&combined, inside), 0);
        // Negative control: fdsm alone leaves false edges where the bars overlap.
        let mut plain = Field::new(32, 32);
        generate_msdf(&prepared, RANGE_PX, &mut plain);
        correct_sign_msdf(&mut plain, &prepared, FillRule::Nonzero);
        // Texel (14, 16) lies in both bars, half a texel from the vertical bar's left edge
        // (inside the horizontal one) and 1.58 texels from the union's outline.
        let depth =
            |f: &Field| median(f.get_pixel(14, 16).0.map(|v| f64::from(v) - 0.5)) * RANGE_PX;
        let (combined, plain) = (depth(&combined), depth(&plain));
        assert!((combined - 1.58).abs() < 0.2, "combined {combined}");
        assert!(plain < 0.8, "fdsm alone sees the inner edge: {plain}");
    }
}
