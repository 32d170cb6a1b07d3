//! Part 21 string encoding (§6.4.3): `''` escapes, the `\` control directives, and line breaks
//! that exporters insert to wrap long strings.
//!
//! Decoding is deliberately lenient because real files break the rules: Windows paths with
//! single backslashes (`'D:\TEMP\x.stp'`), raw 8-bit bytes from code pages other than UTF-8,
//! and malformed directives. None of these is an error; an unrecognised or malformed
//! directive is kept as literal text, and bytes that are not valid UTF-8 are read as
//! ISO 8859-1 (every byte maps to the code point of the same value), which never fails.

use std::borrow::Cow;

/// Decodes a string token's raw bytes (between the quotes, see
/// [`Token::String`](super::lexer::Token::String)) to UTF-8.
///
/// Handles `''` (one quote), `\\` (backslash), `\S\c` (the ISO 8859 character `c` + 128),
/// `\P?\` (code page switch: accepted and ignored), `\X\hh` (one ISO 8859-1 byte),
/// `\X2\hhhh…\X0\` (UCS-2, surrogate pairs accepted), `\X4\hhhhhhhh…\X0\` (UCS-4), and drops
/// line breaks, which the standard says are not part of the value. Returns
/// [`Cow::Borrowed`] when the bytes are UTF-8 and contain nothing to decode.
pub fn decode_string(raw: &[u8]) -> Cow<'_, str> {
    if !raw
        .iter()
        .any(|&b| matches!(b, b'\\' | b'\'' | b'\n' | b'\r'))
        && let Ok(s) = std::str::from_utf8(raw)
    {
        return Cow::Borrowed(s);
    }
    Cow::Owned(decode_slow(raw))
}

fn decode_slow(raw: &[u8]) -> String {
    let stripped: Cow<'_, [u8]> = if raw.iter().any(|&b| b == b'\n' || b == b'\r') {
        Cow::Owned(
            raw.iter()
                .copied()
                .filter(|&b| b != b'\n' && b != b'\r')
                .collect(),
        )
    } else {
        Cow::Borrowed(raw)
    };
    let s: &[u8] = &stripped;
    // Plain bytes are UTF-8 when the whole string is; otherwise the exporter wrote some 8-bit
    // code page we cannot identify, and Latin-1 is the lossless, infallible reading.
    let utf8 = std::str::from_utf8(s).is_ok();
    let mut out = String::with_capacity(s.len());
    let push_plain = |out: &mut String, run: &[u8]| {
        if run.is_empty() {
            return;
        }
        // Runs are split only at ASCII bytes, so they stay valid UTF-8 when `s` is.
        match (utf8, std::str::from_utf8(run)) {
            (true, Ok(text)) => out.push_str(text),
            _ => out.extend(run.iter().map(|&b| char::from(b))),
        }
    };
    let mut i = 0;
    let mut run_start = 0;
    while i < s.len() {
        match s[i] {
            b'\'' => {
                push_plain(&mut out, &s[run_start..i]);
                out.push('\'');
                // `''` is one quote; a lone quote (impossible from the lexer) is kept as is.
                i += if s.get(i + 1) == Some(&b'\'') { 2 } else { 1 };
                run_start = i;
            }
            b'\\' => {
                push_plain(&mut out, &s[run_start..i]);
                i = match directive(s, i, &mut out) {
                    Some(next) => next,
                    None => {
                        out.push('\\');
                        i + 1
                    }
                };
                run_start = i;
            }
            _ => i += 1,
        }
    }
    push_plain(&mut out, &s[run_start..]);
    out
}

fn hex(digits: &[u8]) -> Option<u32> {
    digits.iter().try_fold(0u32, |acc, &d| {
        let v = char::from(d).to_digit(16)?;
        Some(acc << 4 | v)
    })
}

/// Decodes the directive starting at `s[i] == '\\'`, appending its text; returns the index
/// after it, or `None` if this is not a well-formed directive (the backslash is then literal).
fn directive(s: &[u8], i: usize, out: &mut String) -> Option<usize> {
    let rest = &s[i..];
    match rest.get(1)? {
        b'\\' => {
            out.push('\\');
            Some(i + 2)
        }
        b'S' if rest.get(2) == Some(&b'\\') => {
            let c = *rest.get(3)?;
            if !(0x20..0x7f).contains(&c) {
                return None;
            }
            out.push(char::from(c + 0x80));
            // A quote as the character is written doubled, like any quote in a string.
            let doubled = c == b'\'' && rest.get(4) == Some(&b'\'');
            Some(i + if doubled { 5 } else { 4 })
        }
        b'P' if rest.get(3) == Some(&b'\\') && rest.get(2).is_some_and(u8::is_ascii_uppercase) => {
            // Selects the ISO 8859 part for later `\S\`: accepted and ignored (Latin-1 kept).
            Some(i + 4)
        }
        b'X' => match rest.get(2)? {
            b'\\' => {
                let v = hex(rest.get(3..5)?)?;
                out.push(char::from_u32(v)?);
                Some(i + 5)
            }
            b'2' if rest.get(3) == Some(&b'\\') => wide(s, i + 4, 4, out),
            b'4' if rest.get(3) == Some(&b'\\') => wide(s, i + 4, 8, out),
            _ => None,
        },
        _ => None,
    }
}

/// `\X2\` / `\X4\` payload starting at `start`: groups of `width` hex digits up to `\X0\`.
fn wide(s: &[u8], start: usize, width: usize, out: &mut String) -> Option<usize> {
    let end_rel = memchr::memmem::find(&s[start..], b"\\X0\\")?;
    let payload = &s[start..start + end_rel];
    if !payload.len().is_multiple_of(width) {
        return None;
    }
    let units = payload.chunks(width).map(hex);
    // Decode into a scratch buffer so that a bad group leaves `out` untouched.
    let mut text = String::with_capacity(payload.len() / width);
    if width == 4 {
        let units: Option<Vec<u16>> = units
            .map(|u| u.and_then(|v| u16::try_from(v).ok()))
            .collect();
        text.extend(char::decode_utf16(units?).map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER)));
    } else {
        for unit in units {
            text.push(char::from_u32(unit?).unwrap_or(char::REPLACEMENT_CHARACTER));
        }
    }
    out.push_str(&text);
    Some(start + end_rel + 4)
}

/// Encodes `text` as the inside of a Part 21 string (without the surrounding quotes), so that
/// [`decode_string`] gives `text` back: quotes doubled, backslashes as `\\`, everything outside
/// printable ASCII as `\X\hh`, `\X2\…\X0\` or `\X4\…\X0\`.
pub fn encode_string(text: &str, out: &mut String) {
    use std::fmt::Write as _;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            '\u{0}'..='\u{ff}' => {
                let _ = write!(out, "\\X\\{:02X}", u32::from(c));
            }
            _ => {
                // Group a run of wide characters into one directive, as exporters do.
                let astral = |c: char| u32::from(c) > 0xffff;
                let four = astral(c);
                out.push_str(if four { "\\X4\\" } else { "\\X2\\" });
                let mut c = c;
                loop {
                    if four {
                        let _ = write!(out, "{:08X}", u32::from(c));
                    } else {
                        let _ = write!(out, "{:04X}", u32::from(c));
                    }
                    match chars.peek() {
                        Some(&n) if u32::from(n) > 0xff && astral(n) == four => {
                            c = n;
                            chars.next();
                        }
                        _ => break,
                    }
                }
                out.push_str("\\X0\\");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dec(raw: &[u8]) -> String {
        decode_string(raw).into_owned()
    }

    #[test]
    fn plain_ascii_is_borrowed() {
        assert!(matches!(
            decode_string(b"abc def"),
            Cow::Borrowed("abc def")
        ));
        assert!(matches!(decode_string(b""), Cow::Borrowed("")));
    }

    #[test]
    fn utf8_without_directives_is_borrowed() {
        let raw = "Größe ✓".as_bytes();
        assert!(matches!(decode_string(raw), Cow::Borrowed("Größe ✓")));
    }

    #[test]
    fn doubled_quote() {
        assert_eq!(dec(b"it''s"), "it's");
        assert_eq!(dec(b"''''"), "''");
    }

    #[test]
    fn backslash_directive() {
        assert_eq!(dec(br"a\\b"), r"a\b");
        assert_eq!(dec(br"\\\\"), r"\\");
    }

    #[test]
    fn s_directive() {
        // \S\D is 'D' + 128 = U+00C4 (Ä); \S\' (doubled) is U+00A7.
        assert_eq!(dec(br"\S\Dx"), "\u{c4}x");
        assert_eq!(dec(br"\S\0"), "\u{b0}");
        assert_eq!(dec(br"\S\''x"), "\u{a7}x");
    }

    #[test]
    fn p_directive_is_ignored() {
        assert_eq!(dec(br"\PA\abc"), "abc");
        assert_eq!(dec(br"\PE\\S\D"), "\u{c4}");
    }

    #[test]
    fn x_directive() {
        assert_eq!(dec(br"caf\X\E9"), "café");
        assert_eq!(dec(br"\X\0A"), "\n");
    }

    #[test]
    fn x2_directive() {
        assert_eq!(dec(br"\X2\00E9041F\X0\!"), "éП!");
        // A surrogate pair; and a lone surrogate becomes U+FFFD rather than an error.
        assert_eq!(dec(br"\X2\D83DDE00\X0\"), "😀");
        assert_eq!(dec(br"\X2\D83D\X0\"), "\u{fffd}");
    }

    #[test]
    fn x4_directive() {
        assert_eq!(dec(br"\X4\0001F600000000E9\X0\"), "😀é");
        assert_eq!(dec(br"\X4\00110000\X0\"), "\u{fffd}");
    }

    #[test]
    fn malformed_directives_are_literal() {
        assert_eq!(dec(br"D:\TEMP\tom\a.stp"), r"D:\TEMP\tom\a.stp");
        assert_eq!(dec(br"\X2\00E"), r"\X2\00E");
        assert_eq!(dec(br"\X2\00E9"), r"\X2\00E9");
        assert_eq!(dec(br"\X\G1"), r"\X\G1");
        assert_eq!(dec(br"\X\E"), r"\X\E");
        assert_eq!(dec(br"\S\"), r"\S\");
        assert_eq!(dec(br"x\"), r"x\");
        assert_eq!(dec(br"\P1\"), r"\P1\");
    }

    #[test]
    fn line_breaks_are_dropped() {
        assert_eq!(dec(b"Tue Feb 12 2002\r\n"), "Tue Feb 12 2002");
        // A space is content, so this payload is malformed and stays literal.
        assert_eq!(dec(b"\\X2\\00\n E9\\X0\\"), r"\X2\00 E9\X0\");
        assert_eq!(dec(b"\\X2\\00\nE9\\X0\\"), "é");
    }

    #[test]
    fn non_utf8_bytes_are_latin1() {
        // Windows-1251 "Привет": not UTF-8, read byte-for-byte as Latin-1 without failing.
        let raw = b"\xcf\xf0\xe8\xe2\xe5\xf2";
        let s = dec(raw);
        assert_eq!(s.chars().count(), 6);
        assert_eq!(s, "\u{cf}\u{f0}\u{e8}\u{e2}\u{e5}\u{f2}");
        // Mixed with directives and quotes.
        assert_eq!(dec(b"\xe9''\\X\\41"), "\u{e9}'A");
    }

    #[test]
    fn encode_roundtrip() {
        for text in [
            "",
            "plain",
            "it's a \\ path",
            "café",
            "Привет, мир",
            "😀 and é and \u{7f}\n\t",
            "mixed 😀П😀",
        ] {
            let mut enc = String::new();
            encode_string(text, &mut enc);
            assert!(enc.bytes().all(|b| (0x20..0x7f).contains(&b)), "{enc}");
            assert_eq!(dec(enc.as_bytes()), text, "{enc}");
        }
    }
}
