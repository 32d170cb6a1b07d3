//! The fonts cadre bundles and the fallback chain that finds a glyph for a character.
//!
//! Noto Sans first (Latin, Greek, Cyrillic, ± ° µ × …), then Noto Sans Symbols, Symbols 2 and
//! Math for the engineering and GD&T symbols (⌀ ⌖ ⏥ ⌓ ⟂ ∥ Ⓜ …) that no single font covers: the
//! survey measured Noto Sans alone at 2 of the 27 GD&T symbols and the chain at 27 of 27. All
//! four are under the SIL Open Font License (`fonts/OFL.txt`).

use crate::TextError;

/// A font's bytes and the metrics layout needs, in em (font units ÷ units per em).
#[derive(Clone)]
pub struct Font {
    /// The font's name, for messages and the atlas cache key.
    pub name: &'static str,
    /// The whole TrueType file.
    pub bytes: &'static [u8],
    /// Font units per em.
    pub units_per_em: f32,
    /// Height above the baseline of the tallest letters (em).
    pub ascender: f32,
    /// Depth below the baseline (em, negative).
    pub descender: f32,
    /// Extra space between lines (em).
    pub line_gap: f32,
    /// Height of a capital letter (em).
    pub cap_height: f32,
    /// Atlas texels per em for this font's glyphs: [`crate::ATLAS_EM_PX`], or twice that
    /// for fonts of hairline strokes (the symbol fonts draw ⌖'s bars 0.04 em wide: 1.3
    /// texels at 32, too thin for a distance field to keep at 200 px).
    pub atlas_em_px: f64,
    /// The parsed face, kept: parsing its table directory for every character looked up
    /// was most of the time of laying out a label (26 ms for 3,000 labels).
    face: ttf_parser::Face<'static>,
}

impl std::fmt::Debug for Font {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Font")
            .field("name", &self.name)
            .field("units_per_em", &self.units_per_em)
            .field("atlas_em_px", &self.atlas_em_px)
            .finish_non_exhaustive()
    }
}

impl Font {
    /// Reads a font's metrics; an error when `bytes` is not a font ttf-parser can read.
    pub fn parse(name: &'static str, bytes: &'static [u8]) -> Result<Font, TextError> {
        let face = ttf_parser::Face::parse(bytes, 0).map_err(|e| TextError::Font {
            name: name.to_string(),
            message: e.to_string(),
        })?;
        let units = f32::from(face.units_per_em());
        Ok(Font {
            name,
            bytes,
            units_per_em: units,
            ascender: f32::from(face.ascender()) / units,
            descender: f32::from(face.descender()) / units,
            line_gap: f32::from(face.line_gap()) / units,
            cap_height: face.capital_height().map_or(0.7 * units, f32::from) / units,
            atlas_em_px: crate::ATLAS_EM_PX,
            face,
        })
    }

    /// The font's face.
    pub fn face(&self) -> &ttf_parser::Face<'static> {
        &self.face
    }
}

/// The characters engineering drawings use beyond ASCII, GD&T first: the 27 symbols of
/// ASME Y14.5 / ISO 1101 the survey checked (form, orientation, location, runout, profile,
/// modifiers, counterbore, countersink, depth), then the usual signs of dimensions.
pub const GDT_SYMBOLS: &[char] = &[
    '⌀', '±', '°', '⏥', '○', '⌭', '⌒', '⌓', '∠', '⟂', '∥', '⌖', '◎', '⌯', '↗', '⌰', 'Ⓜ', 'Ⓛ', 'Ⓟ',
    'Ⓢ', 'Ⓤ', 'Ⓕ', '⌴', '⌵', '↧', '△', '⫽',
];

/// Signs of dimensions and notes beyond ASCII and the GD&T symbols.
pub const ENGINEERING_SIGNS: &[char] = &[
    'Ø', 'µ', '×', '÷', '≤', '≥', '≈', '≠', '√', '∞', '′', '″', '²', '³', '½', '¼', '¾', '…', '—',
    '–', '→', '←', '↑', '↓', '■', '□', '▽', '▼', '◇', 'Ⓔ', 'Ⓘ', 'Ⓝ', 'Ⓡ', 'Ⓣ', 'ⓟ', 'Ⓐ', 'Ⓑ', 'Ⓒ',
    'Ⓓ', '⌲', '⌳', '•', '⏤', '−',
];

/// Where a character's glyph comes from: a font of the chain and a glyph in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct GlyphKey {
    /// Index of the font in its [`FontChain`].
    pub font: u16,
    /// Glyph id in that font.
    pub glyph: u16,
}

/// Fonts tried in order for each character.
#[derive(Debug)]
pub struct FontChain {
    fonts: Vec<Font>,
}

impl FontChain {
    /// The bundled chain: Noto Sans, Noto Sans Symbols, Noto Sans Symbols 2, Noto Sans Math.
    pub fn bundled() -> &'static FontChain {
        static CHAIN: std::sync::OnceLock<FontChain> = std::sync::OnceLock::new();
        CHAIN.get_or_init(|| {
            let fonts = [
                (
                    "Noto Sans",
                    &include_bytes!("../fonts/NotoSans-Regular.ttf")[..],
                ),
                (
                    "Noto Sans Symbols",
                    &include_bytes!("../fonts/NotoSansSymbols-Regular.ttf")[..],
                ),
                (
                    "Noto Sans Symbols 2",
                    &include_bytes!("../fonts/NotoSansSymbols2-Regular.ttf")[..],
                ),
                (
                    "Noto Sans Math",
                    &include_bytes!("../fonts/NotoSansMath-Regular.ttf")[..],
                ),
            ];
            FontChain {
                fonts: fonts
                    .into_iter()
                    .enumerate()
                    .filter_map(|(i, (name, bytes))| {
                        let mut font = Font::parse(name, bytes).ok()?;
                        // The symbol fonts' strokes are hairlines.
                        if i > 0 {
                            font.atlas_em_px = 2.0 * crate::ATLAS_EM_PX;
                        }
                        Some(font)
                    })
                    .collect(),
            }
        })
    }

    /// A chain of the given fonts, tried in order (the first one sets the line metrics).
    pub fn new(fonts: Vec<Font>) -> Result<FontChain, TextError> {
        if fonts.is_empty() {
            return Err(TextError::EmptyChain);
        }
        Ok(FontChain { fonts })
    }

    /// The fonts, in the order they are tried.
    pub fn fonts(&self) -> &[Font] {
        &self.fonts
    }

    /// The first font (the one whose metrics set the lines).
    pub fn primary(&self) -> &Font {
        &self.fonts[0]
    }

    /// The first font of the chain that has a glyph for `c`, and that glyph.
    pub fn resolve(&self, c: char) -> Option<GlyphKey> {
        self.fonts.iter().enumerate().find_map(|(i, font)| {
            let glyph = font.face().glyph_index(c)?;
            Some(GlyphKey {
                font: i as u16,
                glyph: glyph.0,
            })
        })
    }

    /// The keys of every character of `chars` the chain covers (sorted, no repeats) and the
    /// characters it does not.
    pub fn resolve_all(&self, chars: impl IntoIterator<Item = char>) -> (Vec<GlyphKey>, Vec<char>) {
        let mut keys = Vec::new();
        let mut missing = Vec::new();
        for c in chars {
            match self.resolve(c) {
                Some(key) => keys.push(key),
                None if !c.is_whitespace() && !c.is_control() => missing.push(c),
                None => {}
            }
        }
        keys.sort_unstable();
        keys.dedup();
        missing.sort_unstable();
        missing.dedup();
        (keys, missing)
    }

    /// The characters an atlas holds from the start: printable ASCII, Latin-1, the GD&T
    /// symbols and the engineering signs.
    pub fn base_characters() -> impl Iterator<Item = char> {
        (' '..='~')
            .chain('¡'..='ÿ')
            .chain(GDT_SYMBOLS.iter().copied())
            .chain(ENGINEERING_SIGNS.iter().copied())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chain_covers_every_gdt_symbol_and_noto_sans_alone_does_not() {
        let chain = FontChain::bundled();
        assert_eq!(chain.fonts().len(), 4, "all four bundled fonts parse");
        let (_, missing) = chain.resolve_all(GDT_SYMBOLS.iter().copied());
        assert!(missing.is_empty(), "not covered: {missing:?}");
        let (_, missing) = chain.resolve_all(ENGINEERING_SIGNS.iter().copied());
        assert!(missing.is_empty(), "not covered: {missing:?}");
        // Negative control: the first font alone misses most of them.
        let alone = chain.fonts()[0].face();
        let covered = GDT_SYMBOLS
            .iter()
            .filter(|&&c| alone.glyph_index(c).is_some())
            .count();
        assert!(covered < 10, "Noto Sans alone covers {covered} of 27");
    }

    #[test]
    fn latin_comes_from_the_first_font_and_symbols_from_later_ones() {
        let chain = FontChain::bundled();
        assert_eq!(chain.resolve('A').map(|k| k.font), Some(0));
        assert!(chain.resolve('⌖').is_some_and(|k| k.font > 0));
        assert_eq!(
            chain.resolve('\u{E000}'),
            None,
            "a private-use character is missing"
        );
        let metrics = chain.primary();
        assert!(metrics.ascender > 0.5 && metrics.descender < 0.0);
        assert!(metrics.cap_height > 0.6 && metrics.cap_height < 0.8);
    }
}
