//! The atlas against the fonts' exact outlines: at every texel centre away from the outline,
//! the sign of the MSDF's median must say what the outline's winding number says.

use cadre_text::atlas::texel_distance;
use cadre_text::{FontChain, GlyphKey, MsdfAtlas};

/// A glyph's outline flattened to closed polygons (font units).
#[derive(Default)]
struct Flat {
    rings: Vec<Vec<(f64, f64)>>,
}

impl ttf_parser::OutlineBuilder for Flat {
    fn move_to(&mut self, x: f32, y: f32) {
        self.rings.push(vec![(x.into(), y.into())]);
    }
    fn line_to(&mut self, x: f32, y: f32) {
        if let Some(r) = self.rings.last_mut() {
            r.push((x.into(), y.into()));
        }
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let Some(r) = self.rings.last_mut() else {
            return;
        };
        let (x0, y0) = *r.last().unwrap_or(&(0.0, 0.0));
        for i in 1..=32 {
            let t = f64::from(i) / 32.0;
            let u = 1.0 - t;
            r.push((
                u * u * x0 + 2.0 * u * t * f64::from(x1) + t * t * f64::from(x),
                u * u * y0 + 2.0 * u * t * f64::from(y1) + t * t * f64::from(y),
            ));
        }
    }
    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let Some(r) = self.rings.last_mut() else {
            return;
        };
        let (x0, y0) = *r.last().unwrap_or(&(0.0, 0.0));
        let [x1, y1, x2, y2, x, y] = [x1, y1, x2, y2, x, y].map(f64::from);
        for i in 1..=32 {
            let t = f64::from(i) / 32.0;
            let u = 1.0 - t;
            let (a, b, c, d) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
            r.push((
                a * x0 + b * x1 + c * x2 + d * x,
                a * y0 + b * y1 + c * y2 + d * y,
            ));
        }
    }
    fn close(&mut self) {}
}

impl Flat {
    fn of(chain: &FontChain, key: GlyphKey) -> Flat {
        let mut flat = Flat::default();
        chain.fonts()[usize::from(key.font)]
            .face()
            .outline_glyph(ttf_parser::GlyphId(key.glyph), &mut flat);
        flat
    }

    /// Non-zero winding: inside.
    fn inside(&self, (px, py): (f64, f64)) -> bool {
        let mut winding = 0i32;
        for ring in &self.rings {
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                if (a.1 <= py) != (b.1 <= py) {
                    let x = a.0 + (py - a.1) / (b.1 - a.1) * (b.0 - a.0);
                    if x > px {
                        winding += if b.1 > a.1 { 1 } else { -1 };
                    }
                }
            }
        }
        winding != 0
    }

    /// Distance to the outline.
    fn distance(&self, (px, py): (f64, f64)) -> f64 {
        let mut best = f64::INFINITY;
        for ring in &self.rings {
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len2 = dx * dx + dy * dy;
                let t = if len2 > 0.0 {
                    (((px - a.0) * dx + (py - a.1) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                best = best.min((px - a.0 - t * dx).hypot(py - a.1 - t * dy));
            }
        }
        best
    }
}

/// Texel centres of `field`'s box (atlas `atlas`) that disagree with `outline`, and how many
/// were checked (those over one texel from the outline).
fn disagreements(
    atlas: &MsdfAtlas,
    field: GlyphKey,
    outline: &Flat,
    units_per_em: f64,
) -> (usize, usize) {
    let g = atlas.glyph(field).expect("drawn glyph");
    let [x0, y0, w, h] = g.texels;
    // Texels per em of this glyph (the symbol fonts are drawn finer).
    let em_texels = f64::from(w) / f64::from(g.plane[2] - g.plane[0]);
    let per_texel = units_per_em / em_texels;
    let (mut wrong, mut checked) = (0, 0);
    for ty in 0..h {
        for tx in 0..w {
            // Texel centre in font units: the box's left/top from the plane bounds.
            let p = (
                (f64::from(g.plane[0]) * em_texels + f64::from(tx) + 0.5) * per_texel,
                (f64::from(g.plane[3]) * em_texels - f64::from(ty) - 0.5) * per_texel,
            );
            if outline.distance(p) < per_texel {
                continue;
            }
            checked += 1;
            let msdf_inside = texel_distance(atlas, x0 + tx, y0 + ty) > 0.0;
            if msdf_inside != outline.inside(p) {
                wrong += 1;
            }
        }
    }
    (wrong, checked)
}

#[test]
fn every_texel_off_the_outline_has_the_outlines_sign() {
    let chain = FontChain::bundled();
    let (keys, missing) = chain.resolve_all(FontChain::base_characters());
    assert!(missing.is_empty());
    let atlas = MsdfAtlas::build(chain, &keys).expect("atlas");
    let (mut wrong, mut checked) = (0, 0);
    for &key in &keys {
        let Some(_) = atlas.glyph(key) else { continue };
        let upem = f64::from(chain.fonts()[usize::from(key.font)].units_per_em);
        let (w, c) = disagreements(&atlas, key, &Flat::of(chain, key), upem);
        assert!(
            w * 100 <= c,
            "{key:?}: {w} of {c} texels have the wrong sign"
        );
        wrong += w;
        checked += c;
    }
    assert!(checked > 30_000, "{checked} texels checked");
    eprintln!("{wrong} of {checked} texels off the outline have the wrong sign");
    assert!(wrong * 1000 <= checked, "{wrong} of {checked} texels wrong");

    // Negative control: 'O' held against 'I''s outline disagrees almost everywhere it is ink.
    let o = chain.resolve('O').expect("O");
    let i = chain.resolve('I').expect("I");
    let upem = f64::from(chain.primary().units_per_em);
    let (w, c) = disagreements(&atlas, o, &Flat::of(chain, i), upem);
    assert!(w * 10 > c, "the wrong outline should disagree: {w} of {c}");
}

#[test]
fn glyph_quads_hold_their_outline_and_do_not_overlap() {
    let chain = FontChain::bundled();
    let (keys, _) = chain.resolve_all(FontChain::base_characters());
    let atlas = MsdfAtlas::build(chain, &keys).expect("atlas");
    assert_eq!(atlas.len(), keys.len(), "every base glyph known");
    let mut boxes: Vec<[u32; 4]> = Vec::new();
    for &key in &keys {
        let font = &chain.fonts()[usize::from(key.font)];
        let Some(g) = atlas.glyph(key) else { continue };
        let bbox = font
            .face()
            .glyph_bounding_box(ttf_parser::GlyphId(key.glyph))
            .expect("a drawn glyph has a box");
        let em = |v: i16| f32::from(v) / font.units_per_em;
        assert!(
            g.plane[0] < em(bbox.x_min) && g.plane[2] > em(bbox.x_max),
            "{key:?}"
        );
        assert!(
            g.plane[1] < em(bbox.y_min) && g.plane[3] > em(bbox.y_max),
            "{key:?}"
        );
        boxes.push(g.texels);
    }
    let (w, h) = atlas.size();
    for (n, a) in boxes.iter().enumerate() {
        assert!(a[0] + a[2] <= w && a[1] + a[3] <= h);
        for b in &boxes[n + 1..] {
            let apart = a[0] + a[2] <= b[0]
                || b[0] + b[2] <= a[0]
                || a[1] + a[3] <= b[1]
                || b[1] + b[3] <= a[1];
            assert!(apart, "{a:?} overlaps {b:?}");
        }
    }
}

#[test]
fn glyphs_added_later_go_below_and_change_the_generation() {
    let chain = FontChain::bundled();
    let (first, _) = chain.resolve_all("ABC".chars());
    let mut atlas = MsdfAtlas::build(chain, &first).expect("atlas");
    let generation = atlas.generation();
    let before: Vec<_> = first.iter().map(|k| atlas.glyph(*k).copied()).collect();
    let (more, _) = chain.resolve_all("ABCDé⌖".chars());
    assert_eq!(atlas.insert(chain, &more).expect("insert"), 3);
    assert!(atlas.generation() > generation);
    let after: Vec<_> = first.iter().map(|k| atlas.glyph(*k).copied()).collect();
    assert_eq!(before, after, "glyphs already placed stay where they were");
    assert_eq!(atlas.insert(chain, &more).expect("insert"), 0);
}
