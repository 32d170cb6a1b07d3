//! A hand-written byte lexer for ISO 10303-21 tokens (§5 / §6 of the standard).
//!
//! The lexer borrows the input and never allocates: strings, reals, enumerations and binaries
//! are handed out as slices of the input, and the (comparatively costly) conversions — string
//! directive decoding in [`super::decode_string`], float parsing in [`parse_real`] — happen only
//! when a parameter is actually decoded. That keeps a full tokenisation pass cheap enough to
//! run over hundreds of megabytes.
//!
//! Leniency (inputs real exporters write that the standard does not allow): lower-case letters
//! in keywords and enumerations, reals without digits before the point (`.5`), reals with an
//! exponent but no point (`1e5`), and vertical tab / form feed as white space.

use memchr::{memchr, memmem};

/// One token. Slices borrow the lexer's input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Token<'a> {
    /// A standard keyword (`CARTESIAN_POINT`, `HEADER`, `DATA`, …) or a user-defined keyword,
    /// which keeps its leading `!` (`!MY_ENTITY`). Spelled as in the file.
    Keyword(&'a str),
    /// An entity instance name `#12`, as a reference or as the name being defined.
    Ref(u64),
    /// An integer such as `12`, `+12` or `-3`.
    Integer(i64),
    /// A real in the file's spelling (`1.`, `-1.5E-3`, `1.E+03`, …); convert with
    /// [`parse_real`]. Kept as text so that tokenising does not pay for float conversion.
    Real(&'a str),
    /// A string's raw bytes between the quotes: `''` escapes and `\` directives are still
    /// encoded, and the bytes need not be UTF-8. Decode with [`super::decode_string`].
    String(&'a [u8]),
    /// An enumeration value without its dots, e.g. `T` for `.T.`.
    Enum(&'a str),
    /// A binary's hex digits without the quotes, e.g. `0123` for `"0123"`.
    Binary(&'a str),
    /// `$`: the value is not given.
    Unset,
    /// `*`: the value is derived.
    Derived,
    /// `(`.
    LParen,
    /// `)`.
    RParen,
    /// `,`.
    Comma,
    /// `;`.
    Semicolon,
    /// `=`.
    Equals,
    /// `ISO-10303-21`, which opens an exchange structure.
    ExchangeStart,
    /// `END-ISO-10303-21`, which closes it.
    ExchangeEnd,
}

/// What went wrong while lexing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LexErrorKind {
    /// A byte that cannot start any token (the byte is given).
    #[error("unexpected byte 0x{0:02X}")]
    UnexpectedByte(u8),
    /// A `'` string with no closing quote.
    #[error("unterminated string")]
    UnterminatedString,
    /// A `/*` comment with no closing `*/`.
    #[error("unterminated comment")]
    UnterminatedComment,
    /// A `"` binary with no closing quote.
    #[error("unterminated binary")]
    UnterminatedBinary,
    /// A binary that is empty or holds something other than hex digits.
    #[error("invalid binary (expected hex digits)")]
    InvalidBinary,
    /// An enumeration without a name or without its closing dot.
    #[error("invalid enumeration (expected .NAME.)")]
    InvalidEnum,
    /// A malformed number, such as a lone sign or `1.E` without exponent digits.
    #[error("invalid number")]
    InvalidNumber,
    /// An integer outside the 64-bit signed range.
    #[error("integer out of range")]
    IntegerOverflow,
    /// `#` not followed by digits.
    #[error("expected digits after '#'")]
    InvalidInstanceName,
    /// An instance name beyond 64 bits.
    #[error("instance id out of range")]
    InstanceNameOverflow,
}

/// A lexing error and the byte offset (in the lexer's input) where the bad token starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{kind} at byte {offset}")]
pub struct LexError {
    /// Byte offset of the offending token in the lexer's input.
    pub offset: usize,
    /// What went wrong.
    pub kind: LexErrorKind,
}

/// Tokenises a byte slice of Part 21 text, skipping white space and `/* … */` comments.
///
/// Use [`Lexer::next_token`] (or the [`Iterator`] impl, which stops after the first error).
#[derive(Clone, Debug)]
pub struct Lexer<'a> {
    bytes: &'a [u8],
    /// The input's longest valid UTF-8 prefix (all of it, nearly always). Token text inside it
    /// is sliced from here in O(1) instead of being re-validated token by token.
    text: &'a str,
    pos: usize,
    token_start: usize,
}

/// Whether `b` separates tokens. Vertical tab and form feed are accepted leniently.
#[inline]
pub(crate) fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\n' | b'\r' | b'\t' | 0x0b | 0x0c)
}

#[inline]
fn is_keyword_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

/// `[A-Za-z0-9_]` as a table: one load per byte in the keyword and enumeration loops, which
/// dominate lexing of files with long entity names.
static KEYWORD_CHAR: [bool; 256] = {
    let mut table = [false; 256];
    let mut i = 0;
    while i < 256 {
        let b = i as u8;
        table[i] = b.is_ascii_alphanumeric() || b == b'_';
        i += 1;
    }
    table
};

#[inline]
pub(crate) fn is_keyword_char(b: u8) -> bool {
    KEYWORD_CHAR[usize::from(b)]
}

/// The longest valid UTF-8 prefix of `bytes`.
fn utf8_prefix(bytes: &[u8]) -> &str {
    match std::str::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or(""),
    }
}

/// Skips white space and comments from `pos`; returns the offset of the next token (or the
/// input's length). An unterminated comment is an error at the comment's start.
#[inline]
pub(crate) fn skip_trivia(bytes: &[u8], mut pos: usize) -> Result<usize, LexError> {
    loop {
        match bytes.get(pos) {
            Some(&b) if is_space(b) => pos += 1,
            Some(b'/') if bytes.get(pos + 1) == Some(&b'*') => {
                match memmem::find(&bytes[pos + 2..], b"*/") {
                    Some(i) => pos += 2 + i + 2,
                    None => {
                        return Err(LexError {
                            offset: pos,
                            kind: LexErrorKind::UnterminatedComment,
                        });
                    }
                }
            }
            _ => return Ok(pos),
        }
    }
}

/// Converts a [`Token::Real`]'s text to a finite `f64`; `None` if it overflows to infinity
/// (or is not a number at all), since no consumer can use a non-finite coordinate.
pub fn parse_real(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `bytes`, for lexing all of it.
    ///
    /// Checks UTF-8 once up front (one fast pass) so that token text can be sliced without
    /// per-token validation; to read just a few tokens out of a large buffer use
    /// [`Lexer::at`], which skips that pass.
    pub fn new(bytes: &'a [u8]) -> Self {
        Lexer {
            bytes,
            text: utf8_prefix(bytes),
            pos: 0,
            token_start: 0,
        }
    }

    /// A lexer over `bytes` that starts at byte `pos` (clamped to the input's length) and
    /// does no up-front work, for reading a few tokens out of a large buffer.
    pub fn at(bytes: &'a [u8], pos: usize) -> Self {
        let pos = pos.min(bytes.len());
        Lexer {
            bytes,
            text: "",
            pos,
            token_start: pos,
        }
    }

    /// `bytes[start..end]`, which the caller has checked to be ASCII, as `&str`.
    #[inline]
    fn ascii(&self, start: usize, end: usize) -> &'a str {
        match self.text.get(start..end) {
            Some(s) => s,
            // Outside the checked prefix (or a lexer made by `at`): validate this token
            // alone. It is ASCII, so this cannot fail; the fallback only avoids a panic path.
            None => self
                .bytes
                .get(start..end)
                .and_then(|b| std::str::from_utf8(b).ok())
                .unwrap_or(""),
        }
    }

    /// Byte offset just after the last token (or error) returned.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Byte offset where the last returned token (or error) starts.
    pub fn token_start(&self) -> usize {
        self.token_start
    }

    /// The input the lexer reads.
    pub fn input(&self) -> &'a [u8] {
        self.bytes
    }

    fn err(&mut self, offset: usize, kind: LexErrorKind) -> LexError {
        // Jump to the end so that an iterator over a broken input terminates.
        self.token_start = offset;
        self.pos = self.bytes.len();
        LexError { offset, kind }
    }

    /// The next token, `Ok(None)` at the end of input.
    ///
    /// After an error the lexer is positioned at the end of its input, so that callers
    /// looping until `None` always terminate; recovery is the caller's business (the
    /// indexer restarts at the next statement boundary).
    #[inline]
    pub fn next_token(&mut self) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        let start = match skip_trivia(bytes, self.pos) {
            Ok(p) => p,
            Err(e) => return Err(self.err(e.offset, e.kind)),
        };
        self.token_start = start;
        let Some(&b) = bytes.get(start) else {
            self.pos = start;
            return Ok(None);
        };
        let simple = |lexer: &mut Self, token| {
            lexer.pos = start + 1;
            Ok(Some(token))
        };
        match b {
            b'(' => simple(self, Token::LParen),
            b')' => simple(self, Token::RParen),
            b',' => simple(self, Token::Comma),
            b'#' => self.instance_name(start),
            b'\'' => self.string(start),
            b'A'..=b'Z' | b'a'..=b'z' | b'_' => Ok(Some(self.keyword(start))),
            b'0'..=b'9' | b'+' | b'-' => self.number(start),
            b'.' => {
                if bytes.get(start + 1).is_some_and(u8::is_ascii_digit) {
                    self.number(start)
                } else {
                    self.enumeration(start)
                }
            }
            b'$' => simple(self, Token::Unset),
            b'*' => simple(self, Token::Derived),
            b';' => simple(self, Token::Semicolon),
            b'=' => simple(self, Token::Equals),
            b'"' => self.binary(start),
            b'!' => {
                if bytes.get(start + 1).is_some_and(|&c| is_keyword_start(c)) {
                    let end = self.word_end(start + 1);
                    self.pos = end;
                    Ok(Some(Token::Keyword(self.ascii(start, end))))
                } else {
                    Err(self.err(start, LexErrorKind::UnexpectedByte(b)))
                }
            }
            _ => Err(self.err(start, LexErrorKind::UnexpectedByte(b))),
        }
    }

    #[inline]
    fn word_end(&self, mut i: usize) -> usize {
        while self.bytes.get(i).is_some_and(|&c| is_keyword_char(c)) {
            i += 1;
        }
        i
    }

    /// A keyword, or one of the two hyphenated exchange-structure delimiters.
    #[inline]
    fn keyword(&mut self, start: usize) -> Token<'a> {
        let bytes = self.bytes;
        let end = self.word_end(start + 1);
        let word = &bytes[start..end];
        if bytes.get(end) == Some(&b'-') {
            let rest = &bytes[end..];
            if word.eq_ignore_ascii_case(b"ISO") && starts_with_ci(rest, b"-10303-21") {
                self.pos = end + 9;
                return Token::ExchangeStart;
            }
            if word.eq_ignore_ascii_case(b"END") && starts_with_ci(rest, b"-ISO-10303-21") {
                self.pos = end + 13;
                return Token::ExchangeEnd;
            }
        }
        self.pos = end;
        Token::Keyword(self.ascii(start, end))
    }

    fn instance_name(&mut self, start: usize) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        let mut i = start + 1;
        let mut value: u64 = 0;
        let mut overflow = false;
        while let Some(&c) = bytes.get(i) {
            if !c.is_ascii_digit() {
                break;
            }
            match value
                .checked_mul(10)
                .and_then(|v| v.checked_add(u64::from(c - b'0')))
            {
                Some(v) => value = v,
                None => overflow = true,
            }
            i += 1;
        }
        if i == start + 1 {
            return Err(self.err(start, LexErrorKind::InvalidInstanceName));
        }
        if overflow {
            return Err(self.err(start, LexErrorKind::InstanceNameOverflow));
        }
        self.pos = i;
        Ok(Some(Token::Ref(value)))
    }

    #[inline]
    fn string(&mut self, start: usize) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        let mut i = start + 1;
        loop {
            match memchr(b'\'', &bytes[i..]) {
                // `''` is an escaped quote inside the string: keep going.
                Some(q) if bytes.get(i + q + 1) == Some(&b'\'') => i += q + 2,
                Some(q) => {
                    self.pos = i + q + 1;
                    return Ok(Some(Token::String(&bytes[start + 1..i + q])));
                }
                None => return Err(self.err(start, LexErrorKind::UnterminatedString)),
            }
        }
    }

    fn binary(&mut self, start: usize) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        let Some(len) = memchr(b'"', &bytes[start + 1..]) else {
            return Err(self.err(start, LexErrorKind::UnterminatedBinary));
        };
        let digits = &bytes[start + 1..start + 1 + len];
        if digits.is_empty() || !digits.iter().all(u8::is_ascii_hexdigit) {
            return Err(self.err(start, LexErrorKind::InvalidBinary));
        }
        self.pos = start + len + 2;
        Ok(Some(Token::Binary(self.ascii(start + 1, start + 1 + len))))
    }

    fn enumeration(&mut self, start: usize) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        if !bytes.get(start + 1).is_some_and(|&c| is_keyword_start(c)) {
            return Err(self.err(start, LexErrorKind::InvalidEnum));
        }
        let end = self.word_end(start + 2);
        if bytes.get(end) != Some(&b'.') {
            return Err(self.err(start, LexErrorKind::InvalidEnum));
        }
        self.pos = end + 1;
        Ok(Some(Token::Enum(self.ascii(start + 1, end))))
    }

    #[inline]
    fn number(&mut self, start: usize) -> Result<Option<Token<'a>>, LexError> {
        let bytes = self.bytes;
        let digit_at = |i: usize| bytes.get(i).is_some_and(u8::is_ascii_digit);
        let mut i = start;
        let negative = bytes[start] == b'-';
        if matches!(bytes[start], b'+' | b'-') {
            i += 1;
        }
        let int_start = i;
        let mut magnitude: u64 = 0;
        let mut overflow = false;
        while let Some(&c) = bytes.get(i) {
            if !c.is_ascii_digit() {
                break;
            }
            match magnitude
                .checked_mul(10)
                .and_then(|v| v.checked_add(u64::from(c - b'0')))
            {
                Some(v) => magnitude = v,
                None => overflow = true,
            }
            i += 1;
        }
        let int_digits = i - int_start;
        let mut real = false;
        if bytes.get(i) == Some(&b'.') {
            real = true;
            i += 1;
            let frac_start = i;
            while digit_at(i) {
                i += 1;
            }
            if int_digits == 0 && i == frac_start {
                return Err(self.err(start, LexErrorKind::InvalidNumber));
            }
        } else if int_digits == 0 {
            return Err(self.err(start, LexErrorKind::InvalidNumber));
        }
        if matches!(bytes.get(i), Some(b'E' | b'e')) {
            let mut j = i + 1;
            if matches!(bytes.get(j), Some(b'+' | b'-')) {
                j += 1;
            }
            if digit_at(j) {
                while digit_at(j) {
                    j += 1;
                }
                i = j;
                real = true;
            } else if real {
                // `1.E` / `1.E+`: an exponent marker with no exponent.
                return Err(self.err(start, LexErrorKind::InvalidNumber));
            }
        }
        self.pos = i;
        if real {
            return Ok(Some(Token::Real(self.ascii(start, i))));
        }
        let value = if overflow {
            None
        } else if negative {
            // Through i128 so that i64::MIN itself is representable.
            i64::try_from(-i128::from(magnitude)).ok()
        } else {
            i64::try_from(magnitude).ok()
        };
        match value {
            Some(v) => Ok(Some(Token::Integer(v))),
            None => Err(self.err(start, LexErrorKind::IntegerOverflow)),
        }
    }
}

fn starts_with_ci(haystack: &[u8], needle: &[u8]) -> bool {
    haystack
        .get(..needle.len())
        .is_some_and(|h| h.eq_ignore_ascii_case(needle))
}

impl<'a> Iterator for Lexer<'a> {
    type Item = Result<Token<'a>, LexError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_token().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lex(s: &str) -> Vec<Token<'_>> {
        Lexer::new(s.as_bytes())
            .collect::<Result<Vec<_>, _>>()
            .unwrap_or_else(|e| panic!("lexing {s:?}: {e}"))
    }

    fn lex_err(s: &str) -> LexError {
        match Lexer::new(s.as_bytes()).find_map(Result::err) {
            Some(e) => e,
            None => panic!("expected an error lexing {s:?}"),
        }
    }

    #[test]
    fn punctuation() {
        assert_eq!(
            lex("( ) , ; = $ *"),
            vec![
                Token::LParen,
                Token::RParen,
                Token::Comma,
                Token::Semicolon,
                Token::Equals,
                Token::Unset,
                Token::Derived
            ]
        );
    }

    #[test]
    fn keywords() {
        assert_eq!(
            lex("CARTESIAN_POINT _X1 lower !USER_DEF"),
            vec![
                Token::Keyword("CARTESIAN_POINT"),
                Token::Keyword("_X1"),
                Token::Keyword("lower"),
                Token::Keyword("!USER_DEF")
            ]
        );
    }

    #[test]
    fn exchange_delimiters() {
        assert_eq!(
            lex("ISO-10303-21; END-ISO-10303-21;"),
            vec![
                Token::ExchangeStart,
                Token::Semicolon,
                Token::ExchangeEnd,
                Token::Semicolon
            ]
        );
        // `ISO` alone is an ordinary keyword.
        assert_eq!(lex("ISO"), vec![Token::Keyword("ISO")]);
    }

    #[test]
    fn integers() {
        assert_eq!(
            lex("0 12 +12 -3 9223372036854775807 -9223372036854775808"),
            vec![
                Token::Integer(0),
                Token::Integer(12),
                Token::Integer(12),
                Token::Integer(-3),
                Token::Integer(i64::MAX),
                Token::Integer(i64::MIN)
            ]
        );
    }

    #[test]
    fn integer_overflow() {
        assert_eq!(
            lex_err("9223372036854775808").kind,
            LexErrorKind::IntegerOverflow
        );
        assert_eq!(
            lex_err("99999999999999999999999").kind,
            LexErrorKind::IntegerOverflow
        );
    }

    #[test]
    fn reals_in_every_spelling() {
        let cases = [
            ("1.", 1.0),
            ("-1.5E-3", -1.5e-3),
            ("1.E+03", 1000.0),
            ("1.0e+03", 1000.0),
            ("+2.5", 2.5),
            ("0.E+00", 0.0),
            (".5", 0.5),
            ("-.5E-2", -0.005),
            ("1e5", 1e5),
            ("3E-2", 0.03),
        ];
        for (text, value) in cases {
            assert_eq!(lex(text), vec![Token::Real(text)], "{text}");
            assert_eq!(parse_real(text), Some(value), "{text}");
        }
    }

    #[test]
    fn real_overflow_is_rejected_on_conversion() {
        assert_eq!(lex("1.E400"), vec![Token::Real("1.E400")]);
        assert_eq!(parse_real("1.E400"), None);
        assert_eq!(parse_real("-1.E400"), None);
    }

    #[test]
    fn invalid_numbers() {
        assert_eq!(lex_err("1.E").kind, LexErrorKind::InvalidNumber);
        assert_eq!(lex_err("1.E+,").kind, LexErrorKind::InvalidNumber);
        assert_eq!(lex_err("-").kind, LexErrorKind::InvalidNumber);
        assert_eq!(lex_err("+.").kind, LexErrorKind::InvalidNumber);
    }

    #[test]
    fn integer_then_keyword_e() {
        // No exponent digits and no point: an integer followed by a keyword, which the
        // parser then rejects; the lexer must not misread it as a real.
        assert_eq!(lex("1E"), vec![Token::Integer(1), Token::Keyword("E")]);
    }

    #[test]
    fn strings_stay_raw() {
        assert_eq!(
            lex(r"'' 'abc' 'it''s' '\X2\00E9\X0\'"),
            vec![
                Token::String(b""),
                Token::String(b"abc"),
                Token::String(b"it''s"),
                Token::String(br"\X2\00E9\X0\")
            ]
        );
        // Semicolons, comment markers and line breaks inside a string are content.
        assert_eq!(lex("'a;b/*c*/\nd'"), vec![Token::String(b"a;b/*c*/\nd")]);
    }

    #[test]
    fn non_utf8_string_bytes() {
        let bytes = b"'\xcf\xf0\xe8\xe2\xe5\xf2' 1";
        let tokens: Vec<_> = Lexer::new(bytes).collect::<Result<_, _>>().unwrap();
        assert_eq!(
            tokens,
            vec![
                Token::String(b"\xcf\xf0\xe8\xe2\xe5\xf2"),
                Token::Integer(1)
            ]
        );
    }

    #[test]
    fn unterminated_string() {
        let e = lex_err("A('abc");
        assert_eq!(e.kind, LexErrorKind::UnterminatedString);
        assert_eq!(e.offset, 2);
        assert_eq!(lex_err("'it''").kind, LexErrorKind::UnterminatedString);
    }

    #[test]
    fn enumerations() {
        assert_eq!(
            lex(".T. .F. .UNSPECIFIED. .x_1."),
            vec![
                Token::Enum("T"),
                Token::Enum("F"),
                Token::Enum("UNSPECIFIED"),
                Token::Enum("x_1")
            ]
        );
        assert_eq!(lex_err(".T").kind, LexErrorKind::InvalidEnum);
        assert_eq!(lex_err("..").kind, LexErrorKind::InvalidEnum);
    }

    #[test]
    fn binaries() {
        assert_eq!(
            lex(r#""0123" "3ABCdef""#),
            vec![Token::Binary("0123"), Token::Binary("3ABCdef")]
        );
        assert_eq!(lex_err(r#""0G""#).kind, LexErrorKind::InvalidBinary);
        assert_eq!(lex_err(r#""""#).kind, LexErrorKind::InvalidBinary);
        assert_eq!(lex_err(r#""01"#).kind, LexErrorKind::UnterminatedBinary);
    }

    #[test]
    fn references() {
        assert_eq!(
            lex("#1 #0 #18446744073709551615"),
            vec![Token::Ref(1), Token::Ref(0), Token::Ref(u64::MAX)]
        );
        assert_eq!(
            lex_err("#18446744073709551616").kind,
            LexErrorKind::InstanceNameOverflow
        );
        assert_eq!(lex_err("# 1").kind, LexErrorKind::InvalidInstanceName);
    }

    #[test]
    fn comments_and_whitespace() {
        assert_eq!(
            lex("/* a ; ' */#1/**/=\r\n\tA\x0c(/*x*/)"),
            vec![
                Token::Ref(1),
                Token::Equals,
                Token::Keyword("A"),
                Token::LParen,
                Token::RParen
            ]
        );
        let e = lex_err("A /* open");
        assert_eq!(e.kind, LexErrorKind::UnterminatedComment);
        assert_eq!(e.offset, 2);
    }

    #[test]
    fn garbage_bytes() {
        assert_eq!(lex_err("A \u{1}").kind, LexErrorKind::UnexpectedByte(1));
        assert_eq!(lex_err("\u{e9}").kind, LexErrorKind::UnexpectedByte(0xC3));
        assert_eq!(lex_err("/x").kind, LexErrorKind::UnexpectedByte(b'/'));
        assert_eq!(lex_err("!1").kind, LexErrorKind::UnexpectedByte(b'!'));
    }

    #[test]
    fn iterator_stops_after_error() {
        let mut lexer = Lexer::new(b"A \x01 B");
        assert!(matches!(lexer.next(), Some(Ok(Token::Keyword("A")))));
        assert!(matches!(lexer.next(), Some(Err(_))));
        assert!(lexer.next().is_none());
    }

    #[test]
    fn token_positions() {
        let mut lexer = Lexer::new(b"  #12 = A");
        assert_eq!(lexer.next_token(), Ok(Some(Token::Ref(12))));
        assert_eq!(lexer.token_start(), 2);
        assert_eq!(lexer.position(), 5);
    }
}
