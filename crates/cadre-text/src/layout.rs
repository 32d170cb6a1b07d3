//! Laying out a label: characters to glyphs of the fallback chain, shaped with kerning,
//! lines stacked, the block aligned on its anchor.
//!
//! The text is cut into runs of characters that resolve to the same font of the chain; each
//! run is shaped by HarfRust (OpenType GSUB/GPOS: kerning, ligatures where the font has them,
//! simple scripts), positions in em.

use crate::fonts::{FontChain, GlyphKey};
use glam::Vec2;
use harfrust::{Direction, FontRef, Script, ShapeOptions, ShapePlan, ShaperData, UnicodeBuffer};
use std::collections::HashMap;
use std::sync::Mutex;

/// Horizontal alignment of each line on the anchor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Align {
    /// Lines start at the anchor.
    #[default]
    Left,
    /// Lines are centred on the anchor.
    Centre,
    /// Lines end at the anchor.
    Right,
}

/// Which height of the block sits on the anchor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Baseline {
    /// The first line's baseline.
    #[default]
    Alphabetic,
    /// The top of the block (the first line's ascender).
    Top,
    /// The middle of the block (for one line: half the cap height above the baseline).
    Middle,
    /// The bottom of the block (the last line's descender).
    Bottom,
}

/// A glyph's pen position in a laid-out block (em, y up, the anchor at the origin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedGlyph {
    /// Which glyph.
    pub key: GlyphKey,
    /// Pen position.
    pub pen: Vec2,
}

/// A laid-out label.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TextLayout {
    /// The glyphs, outlines or not (spaces are kept: they cost nothing to draw).
    pub glyphs: Vec<PlacedGlyph>,
    /// The block's box (em): lower-left corner.
    pub min: Vec2,
    /// The block's box (em): upper-right corner.
    pub max: Vec2,
    /// Characters no font of the chain has (drawn as the missing-glyph box of the font of
    /// their run, and reported).
    pub missing: Vec<char>,
}

/// Shaping data of each font of a chain, made once, and the shape plans made so far (a
/// plan per font, script and direction: making one for every run was a third of a label's
/// layout time).
pub struct Shaper {
    data: Vec<ShaperData>,
    fonts: Vec<Option<FontRef<'static>>>,
    plans: Mutex<HashMap<(u16, Script, Direction), std::sync::Arc<ShapePlan>>>,
}

impl Shaper {
    /// The shaping tables of every font of `chain`.
    pub fn new(chain: &FontChain) -> Shaper {
        let fonts: Vec<Option<FontRef<'static>>> = chain
            .fonts()
            .iter()
            .map(|f| FontRef::new(f.bytes).ok())
            .collect();
        Shaper {
            data: fonts
                .iter()
                .map(|font| ShaperData::new(font.as_ref().unwrap_or(&empty_font())))
                .collect(),
            fonts,
            plans: Mutex::new(HashMap::new()),
        }
    }

    /// The shaper of the bundled chain.
    pub fn bundled() -> &'static Shaper {
        static SHAPER: std::sync::OnceLock<Shaper> = std::sync::OnceLock::new();
        SHAPER.get_or_init(|| Shaper::new(FontChain::bundled()))
    }
}

/// A font of no tables, for a font HarfRust refuses (its runs then shape to nothing).
fn empty_font() -> FontRef<'static> {
    // The smallest valid sfnt header: version 1.0, no tables.
    static EMPTY: [u8; 12] = [0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    FontRef::new(&EMPTY).unwrap_or_else(|_| unreachable!("an empty sfnt parses"))
}

/// Lays out `text` (lines split at `\n`) with `chain`, aligned by `align` and `baseline`;
/// lines are `line_spacing` × the first font's line height apart.
pub fn layout(
    chain: &FontChain,
    shaper: &Shaper,
    text: &str,
    (align, baseline): (Align, Baseline),
    line_spacing: f32,
) -> TextLayout {
    let primary = chain.primary();
    let line_height = (primary.ascender - primary.descender + primary.line_gap) * line_spacing;
    let mut out = TextLayout::default();
    let mut widths = Vec::new();
    let mut line_starts = Vec::new();
    for (row, line) in text.split('\n').enumerate() {
        line_starts.push(out.glyphs.len());
        let y = -(row as f32) * line_height;
        let width = shape_line(chain, shaper, line, y, &mut out);
        widths.push(width);
    }
    line_starts.push(out.glyphs.len());
    let rows = widths.len() as f32;
    let widest = widths.iter().copied().fold(0.0f32, f32::max);
    // Horizontal: each line moved on its own.
    for (row, width) in widths.iter().enumerate() {
        let dx = match align {
            Align::Left => 0.0,
            Align::Centre => -0.5 * width,
            Align::Right => -width,
        };
        for g in &mut out.glyphs[line_starts[row]..line_starts[row + 1]] {
            g.pen.x += dx;
        }
    }
    let top = primary.ascender;
    let bottom = -(rows - 1.0) * line_height + primary.descender;
    let dy = match baseline {
        Baseline::Alphabetic => 0.0,
        Baseline::Top => -top,
        Baseline::Bottom => -bottom,
        Baseline::Middle if rows <= 1.0 => -0.5 * primary.cap_height,
        Baseline::Middle => -0.5 * (top + bottom),
    };
    for g in &mut out.glyphs {
        g.pen.y += dy;
    }
    let x0 = match align {
        Align::Left => 0.0,
        Align::Centre => -0.5 * widest,
        Align::Right => -widest,
    };
    out.min = Vec2::new(x0, bottom + dy);
    out.max = Vec2::new(x0 + widest, top + dy);
    out.missing.sort_unstable();
    out.missing.dedup();
    out
}

/// Shapes one line at height `y` into `out`; returns its advance width (em).
fn shape_line(chain: &FontChain, shaper: &Shaper, line: &str, y: f32, out: &mut TextLayout) -> f32 {
    let mut pen = 0.0f32;
    for (font, run) in runs(chain, line, &mut out.missing) {
        let info = &chain.fonts()[usize::from(font)];
        let Some(Some(font_ref)) = shaper.fonts.get(usize::from(font)) else {
            continue;
        };
        let built = shaper.data[usize::from(font)].shaper(font_ref).build();
        let mut buffer = UnicodeBuffer::new();
        buffer.push_str(run);
        buffer.guess_segment_properties();
        let key = (font, buffer.script(), buffer.direction());
        let plan = {
            let mut plans = shaper.plans.lock().unwrap_or_else(|e| e.into_inner());
            plans
                .entry(key)
                .or_insert_with(|| {
                    std::sync::Arc::new(ShapePlan::new(&built, key.2, Some(key.1), None, &[]))
                })
                .clone()
        };
        let shaped = built.shape(buffer, ShapeOptions::new().plan(Some(&plan)));
        let per_unit = 1.0 / info.units_per_em;
        for (glyph, position) in shaped.glyph_infos().iter().zip(shaped.glyph_positions()) {
            out.glyphs.push(PlacedGlyph {
                key: GlyphKey {
                    font,
                    glyph: glyph.glyph_id as u16,
                },
                pen: Vec2::new(
                    pen + position.x_offset as f32 * per_unit,
                    y + position.y_offset as f32 * per_unit,
                ),
            });
            pen += position.x_advance as f32 * per_unit;
        }
    }
    pen
}

/// `line` cut into runs of the same font (characters no font has go with their neighbours'
/// font, as the first font's missing glyph, and into `missing`).
fn runs<'a>(chain: &FontChain, line: &'a str, missing: &mut Vec<char>) -> Vec<(u16, &'a str)> {
    let mut runs: Vec<(u16, &str)> = Vec::new();
    let mut start = 0;
    let mut current: Option<u16> = None;
    for (at, c) in line.char_indices() {
        let font = match chain.resolve(c) {
            Some(key) => Some(key.font),
            // Spaces and marks stay in the run they are in.
            None if c.is_whitespace() || c.is_control() => current,
            None => {
                missing.push(c);
                current
            }
        };
        let font = font.or(current).unwrap_or(0);
        if current.is_some_and(|f| f != font) {
            runs.push((current.unwrap_or(0), &line[start..at]));
            start = at;
        }
        current = Some(font);
    }
    if start < line.len() {
        runs.push((current.unwrap_or(0), &line[start..]));
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lay(text: &str, align: Align, baseline: Baseline) -> TextLayout {
        let chain = FontChain::bundled();
        layout(chain, Shaper::bundled(), text, (align, baseline), 1.0)
    }

    #[test]
    fn kerning_pulls_av_together() {
        let pair = lay("AV", Align::Left, Baseline::Alphabetic);
        let a = lay("A", Align::Left, Baseline::Alphabetic);
        assert_eq!(pair.glyphs.len(), 2);
        // Negative control of the kerning: "AV" is narrower than "A" then "V" set apart.
        let v = lay("V", Align::Left, Baseline::Alphabetic);
        let unkerned = a.max.x + v.max.x;
        assert!(
            pair.max.x < unkerned - 0.01,
            "AV {} vs A + V {unkerned}",
            pair.max.x
        );
        assert!((pair.glyphs[1].pen.x - a.max.x).abs() > 0.01);
    }

    #[test]
    fn symbols_fall_back_and_keep_their_order() {
        let out = lay("⌀12 ±0.1 ⌖", Align::Left, Baseline::Alphabetic);
        assert!(out.missing.is_empty());
        let fonts: Vec<u16> = out.glyphs.iter().map(|g| g.key.font).collect();
        assert!(fonts[0] > 0, "⌀ from a symbol font: {fonts:?}");
        assert_eq!(fonts[1], 0);
        assert!(*fonts.last().unwrap_or(&0) > 0);
        let xs: Vec<f32> = out.glyphs.iter().map(|g| g.pen.x).collect();
        assert!(xs.windows(2).all(|w| w[1] > w[0]), "pens advance: {xs:?}");
    }

    #[test]
    fn alignment_and_lines() {
        let left = lay("Part 1\nBolt", Align::Left, Baseline::Alphabetic);
        let centre = lay("Part 1\nBolt", Align::Centre, Baseline::Middle);
        let right = lay("Part 1\nBolt", Align::Right, Baseline::Top);
        assert!((left.min.x).abs() < 1e-6 && left.max.x > 2.0);
        assert!((centre.min.x + centre.max.x).abs() < 1e-5);
        assert!((centre.min.y + centre.max.y).abs() < 1e-5);
        assert!((right.max.x).abs() < 1e-6 && right.max.y.abs() < 1e-6);
        // The second line is one line height below the first.
        let second = left.glyphs[6].pen.y;
        assert!(second < -1.0 && second > -1.6, "{second}");
        assert!(lay("\u{E000}x", Align::Left, Baseline::Alphabetic).missing == vec!['\u{E000}']);
    }
}
