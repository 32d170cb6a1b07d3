//! Text for cadre: labels, dimensions and notes drawn with multi-channel signed distance
//! fields.
//!
//! - [`fonts`]: the bundled fonts (Noto Sans, Symbols, Symbols 2, Math; SIL OFL) and the
//!   fallback chain that covers the GD&T and engineering symbols.
//! - [`layout`]: a label's characters to positioned glyphs (HarfRust shaping with kerning,
//!   lines, alignment).
//! - [`atlas`]: the glyphs' MSDFs (`fdsm`), generated on worker threads and packed into one
//!   texture.
//! - [`cache`]: the base atlas kept on disk, so only the first run pays for it.

pub mod atlas;
pub mod cache;
pub mod fonts;
pub mod layout;

pub use atlas::{ATLAS_EM_PX, AtlasGlyph, MsdfAtlas, RANGE_PX};
pub use fonts::{ENGINEERING_SIGNS, FontChain, GDT_SYMBOLS, GlyphKey};
pub use layout::{Align, Baseline, PlacedGlyph, Shaper, TextLayout, layout};

/// What can go wrong with fonts and atlases.
#[derive(Debug, thiserror::Error)]
pub enum TextError {
    /// A font file ttf-parser cannot read.
    #[error("font {name}: {message}")]
    Font {
        /// The font's name.
        name: String,
        /// ttf-parser's reason.
        message: String,
    },
    /// A chain needs at least one font.
    #[error("a font chain needs at least one font")]
    EmptyChain,
    /// A glyph key names a font the chain does not have.
    #[error("no font {font} in the chain")]
    NoSuchFont {
        /// The font index.
        font: u16,
    },
    /// A glyph bigger than the atlas takes (512 texels a side).
    #[error("glyph {glyph} of {font} is larger than the atlas takes")]
    GlyphTooLarge {
        /// The font's name.
        font: &'static str,
        /// The glyph id.
        glyph: u16,
    },
    /// The atlas reached its height limit.
    #[error("the glyph atlas is full ({glyphs} glyphs)")]
    AtlasFull {
        /// Glyphs it holds.
        glyphs: usize,
    },
    /// Reading or writing the disk cache.
    #[error("atlas cache {path}: {source}")]
    Cache {
        /// The cache file.
        path: std::path::PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}
