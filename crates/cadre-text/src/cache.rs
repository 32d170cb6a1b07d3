//! The base atlas kept on disk: the first run builds it (about 0.2 s of work on worker
//! threads), later runs read it back in milliseconds.
//!
//! The file is named by a hash of everything that shapes its texels (this format's version,
//! the atlas resolution and range, the fonts' bytes, the glyph list), so a change of any of
//! them makes a new file rather than reading a stale one. A file that is short, damaged or
//! fails its checksum is ignored and rebuilt.

use crate::TextError;
use crate::atlas::{ATLAS_EM_PX, AtlasGlyph, MsdfAtlas, RANGE_PX};
use crate::fonts::{FontChain, GlyphKey};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Bumped whenever the file layout or the glyph generation changes.
const FORMAT: &[u8; 10] = b"CADREMSDF\x04";

/// Where cadre keeps its caches: `CADRE_CACHE_DIR`, else `$XDG_CACHE_HOME/cadre`, else
/// `~/.cache/cadre`; `None` when none is known (the atlas is then built every run).
pub fn cache_dir() -> Option<PathBuf> {
    let from_env = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = from_env("CADRE_CACHE_DIR") {
        return Some(PathBuf::from(dir));
    }
    if let Some(dir) = from_env("XDG_CACHE_HOME") {
        return Some(PathBuf::from(dir).join("cadre"));
    }
    from_env("HOME").map(|home| PathBuf::from(home).join(".cache").join("cadre"))
}

/// FNV-1a, 64 bits: the cache's name and checksum (not a security boundary).
fn fnv(bytes: &[u8], mut hash: u64) -> u64 {
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash
}
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// The cache file name for an atlas of `keys` from `chain`.
fn file_name(chain: &FontChain, keys: &[GlyphKey]) -> String {
    let mut h = fnv(FORMAT, FNV_START);
    h = fnv(&ATLAS_EM_PX.to_le_bytes(), h);
    h = fnv(&RANGE_PX.to_le_bytes(), h);
    for font in chain.fonts() {
        h = fnv(font.bytes, h);
        h = fnv(&font.atlas_em_px.to_le_bytes(), h);
    }
    for k in keys {
        h = fnv(&k.font.to_le_bytes(), h);
        h = fnv(&k.glyph.to_le_bytes(), h);
    }
    format!("msdf-{h:016x}.bin")
}

/// The atlas of the base characters ([`FontChain::base_characters`]) of the bundled chain:
/// read from the cache, else built and saved there. Made once a process.
pub fn base_atlas() -> Arc<MsdfAtlas> {
    static BASE: std::sync::OnceLock<Arc<MsdfAtlas>> = std::sync::OnceLock::new();
    BASE.get_or_init(|| {
        let chain = FontChain::bundled();
        let (keys, _) = chain.resolve_all(FontChain::base_characters());
        let dir = cache_dir();
        Arc::new(load_or_build(chain, &keys, dir.as_deref()))
    })
    .clone()
}

/// The atlas of `keys`: from `dir`'s cache file when it is there and sound, else built (and
/// written there when `dir` is given; a write that fails is logged, the atlas still used).
pub fn load_or_build(chain: &FontChain, keys: &[GlyphKey], dir: Option<&Path>) -> MsdfAtlas {
    let path = dir.map(|d| d.join(file_name(chain, keys)));
    if let Some(atlas) = path.as_deref().and_then(|p| read(p).ok().flatten()) {
        return atlas;
    }
    let mut atlas = MsdfAtlas::new();
    if let Err(e) = atlas.insert(chain, keys) {
        tracing::warn!("glyph atlas: {e}");
    }
    if let Some(path) = path
        && let Err(e) = write(&path, &atlas)
    {
        tracing::warn!("{e}");
    }
    atlas
}

/// Writes `atlas` to `path` (through a temporary file renamed into place, so a reader never
/// sees half a file).
pub fn write(path: &Path, atlas: &MsdfAtlas) -> Result<(), TextError> {
    let error = |source| TextError::Cache {
        path: path.to_path_buf(),
        source,
    };
    let mut out = Vec::with_capacity(atlas.pixels().len() + 64 * atlas.len());
    out.extend_from_slice(FORMAT);
    let (w, h) = atlas.size();
    let mut glyphs: Vec<(GlyphKey, Option<&AtlasGlyph>)> = atlas.glyphs().collect();
    glyphs.sort_by_key(|(k, _)| *k);
    for v in [w, h, glyphs.len() as u32] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for (key, glyph) in glyphs {
        out.extend_from_slice(&key.font.to_le_bytes());
        out.extend_from_slice(&key.glyph.to_le_bytes());
        out.push(u8::from(glyph.is_some()));
        let g = glyph.copied().unwrap_or(AtlasGlyph {
            texels: [0; 4],
            plane: [0.0; 4],
        });
        g.texels
            .iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        g.plane
            .iter()
            .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
    }
    out.extend_from_slice(atlas.pixels());
    let sum = fnv(&out, FNV_START);
    out.extend_from_slice(&sum.to_le_bytes());
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(error)?;
    }
    let temporary = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&temporary, &out).map_err(error)?;
    std::fs::rename(&temporary, path).map_err(error)
}

/// Reads an atlas written by [`write`]; `Ok(None)` when the file is missing, damaged or of
/// another format.
pub fn read(path: &Path) -> Result<Option<MsdfAtlas>, TextError> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(TextError::Cache {
                path: path.to_path_buf(),
                source,
            });
        }
    };
    Ok(parse(&bytes))
}

/// The atlas in `bytes`, or `None` when they are not a sound cache file.
fn parse(bytes: &[u8]) -> Option<MsdfAtlas> {
    let (body, sum) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
    if fnv(body, FNV_START).to_le_bytes() != sum || !body.starts_with(FORMAT) {
        return None;
    }
    let mut at = FORMAT.len();
    let mut take = |n: usize| -> Option<&[u8]> {
        let s = body.get(at..at.checked_add(n)?)?;
        at += n;
        Some(s)
    };
    let word = |s: &[u8]| u32::from_le_bytes([s[0], s[1], s[2], s[3]]);
    let head = take(12)?;
    let (w, h, count) = (word(&head[0..4]), word(&head[4..8]), word(&head[8..12]));
    if w == 0 || h > crate::atlas::MAX_ATLAS_HEIGHT || count > 1 << 20 {
        return None;
    }
    let mut glyphs = HashMap::with_capacity(count as usize);
    for _ in 0..count {
        let r = take(37)?;
        let key = GlyphKey {
            font: u16::from_le_bytes([r[0], r[1]]),
            glyph: u16::from_le_bytes([r[2], r[3]]),
        };
        let texels = [0, 1, 2, 3].map(|i| word(&r[5 + 4 * i..]));
        let plane = [0, 1, 2, 3].map(|i| f32::from_bits(word(&r[21 + 4 * i..])));
        let inside = texels[0].checked_add(texels[2]).is_some_and(|x| x <= w)
            && texels[1].checked_add(texels[3]).is_some_and(|y| y <= h);
        if r[4] == 1 && !inside {
            return None;
        }
        glyphs.insert(key, (r[4] == 1).then_some(AtlasGlyph { texels, plane }));
    }
    let pixels = take((w as usize) * (h as usize) * 4)?.to_vec();
    Some(MsdfAtlas::from_parts((w, h), pixels, glyphs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_atlas_survives_the_disk_and_damage_is_refused() {
        let chain = FontChain::bundled();
        let (keys, _) = chain.resolve_all("Ab ⌀".chars());
        let dir = std::env::temp_dir().join(format!("cadre-msdf-test-{}", std::process::id()));
        let built = load_or_build(chain, &keys, Some(&dir));
        let path = dir.join(file_name(chain, &keys));
        let read_back = read(&path).expect("readable").expect("sound");
        assert_eq!(read_back.size(), built.size());
        assert_eq!(read_back.pixels(), built.pixels());
        for key in &keys {
            assert_eq!(read_back.glyph(*key), built.glyph(*key), "{key:?}");
            assert!(read_back.contains(*key));
        }
        // One flipped byte fails the checksum: the file is ignored, not trusted.
        let mut bytes = std::fs::read(&path).expect("file");
        let middle = bytes.len() / 2;
        bytes[middle] ^= 0x40;
        assert!(parse(&bytes).is_none());
        assert!(parse(&bytes[..bytes.len() / 3]).is_none());
        assert!(parse(b"").is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
