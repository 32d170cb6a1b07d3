//! One line of a program read into a statement: comments (`( … )`, `;` to the end) and
//! spaces removed, letters lower-cased (G-code is case- and space-insensitive outside
//! comments), then either an o-word (`o100 sub`, `o<loop> while [#1 lt 3]`, …), or a block of
//! words (`g1 x[#1 + 2] f300`) and parameter settings (`#1 = 2`, `#<depth> = -3`).

use crate::GcodeError;
use crate::expr::{Expr, real_value};

/// A cursor over a cleaned line.
pub(crate) struct Cursor<'a> {
    text: &'a [u8],
    at: usize,
    line: u32,
}

impl<'a> Cursor<'a> {
    pub fn new(text: &'a [u8], line: u32) -> Cursor<'a> {
        Cursor { text, at: 0, line }
    }

    pub fn peek(&self) -> Option<u8> {
        self.text.get(self.at).copied()
    }

    pub fn bump(&mut self) {
        self.at += 1;
    }

    pub fn advance(&mut self, n: usize) {
        self.at = (self.at + n).min(self.text.len());
    }

    pub fn at_end(&self) -> bool {
        self.at >= self.text.len()
    }

    pub fn starts_with(&self, s: &str) -> bool {
        self.text[self.at.min(self.text.len())..].starts_with(s.as_bytes())
    }

    /// An error at the cursor.
    pub fn error(&self, message: &str) -> GcodeError {
        GcodeError::Syntax {
            line: self.line,
            column: self.at + 1,
            message: message.to_string(),
        }
    }

    pub fn expect(&mut self, byte: u8) -> Result<(), GcodeError> {
        if self.peek() == Some(byte) {
            self.bump();
            Ok(())
        } else {
            Err(self.error(&format!("'{}' expected", byte as char)))
        }
    }

    /// A number: digits with at most one decimal point (`1`, `1.`, `.5`, `12.250`).
    pub fn number(&mut self) -> Result<f64, GcodeError> {
        let start = self.at;
        let mut dot = false;
        while let Some(b) = self.peek() {
            match b {
                b'0'..=b'9' => self.bump(),
                b'.' if !dot => {
                    dot = true;
                    self.bump();
                }
                _ => break,
            }
        }
        let digits = std::str::from_utf8(&self.text[start..self.at]).unwrap_or("");
        match digits.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ if digits == "." || digits.is_empty() => Err(self.error("a number is missing")),
            _ => Err(self.error(&format!("'{digits}' is not a number"))),
        }
    }

    /// A parameter name `<…>` at the cursor (the brackets consumed; spaces are already
    /// gone, letters lower case).
    pub fn name(&mut self) -> Result<String, GcodeError> {
        self.expect(b'<')?;
        let start = self.at;
        while let Some(b) = self.peek() {
            if b == b'>' {
                let name = String::from_utf8_lossy(&self.text[start..self.at]).into_owned();
                self.bump();
                if name.is_empty() {
                    return Err(self.error("an empty name"));
                }
                return Ok(name);
            }
            self.bump();
        }
        Err(self.error("'>' expected to close the name"))
    }
}

/// One word: a letter and its value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Word {
    pub letter: u8,
    pub value: Expr,
}

/// What sets a parameter.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Target {
    Numbered(Expr),
    Named(String),
}

/// An o-word's keyword.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Keyword {
    Sub,
    EndSub,
    Return,
    Call,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Break,
    Continue,
    Repeat,
    EndRepeat,
}

/// What a line says.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Statement {
    /// Nothing (blank, a comment, a block number alone).
    Empty,
    /// `%`: the program's start or end marker.
    Percent,
    /// Words and parameter settings.
    Block {
        words: Vec<Word>,
        settings: Vec<(Target, Expr)>,
    },
    /// An o-word: label, keyword, bracketed arguments.
    OWord {
        label: String,
        keyword: Keyword,
        args: Vec<Expr>,
    },
    /// A line that does not parse: warned when it is reached.
    Bad(GcodeError),
}

/// The line without comments and spaces, lower case; a `(MSG, …)` and the like are comments
/// too (nothing is displayed).
fn clean(raw: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(raw.len());
    let mut in_comment = false;
    for b in raw.bytes() {
        if in_comment {
            if b == b')' {
                in_comment = false;
            }
            continue;
        }
        match b {
            b'(' => in_comment = true,
            b';' => break,
            b' ' | b'\t' | b'\r' => {}
            _ => out.push(b.to_ascii_lowercase()),
        }
    }
    out
}

/// Reads line `number` (1-based) of a program.
pub(crate) fn statement(raw: &str, number: u32) -> Statement {
    let text = clean(raw);
    let mut c = Cursor::new(&text, number);
    match parse(&mut c) {
        Ok(s) => s,
        Err(e) => Statement::Bad(e),
    }
}

fn parse(c: &mut Cursor<'_>) -> Result<Statement, GcodeError> {
    // Block delete: executed (the switch is off).
    if c.peek() == Some(b'/') {
        c.bump();
    }
    if c.peek() == Some(b'%') {
        return Ok(Statement::Percent);
    }
    // A block number first.
    if c.peek() == Some(b'n') {
        c.bump();
        while matches!(c.peek(), Some(b'0'..=b'9' | b'.')) {
            c.bump();
        }
    }
    if c.peek() == Some(b'o') {
        c.bump();
        return oword(c);
    }
    let mut words = Vec::new();
    let mut settings = Vec::new();
    while let Some(b) = c.peek() {
        match b {
            b'#' => {
                c.bump();
                let target = if c.peek() == Some(b'<') {
                    Target::Named(c.name()?)
                } else {
                    Target::Numbered(real_value(c)?)
                };
                c.expect(b'=')?;
                settings.push((target, real_value(c)?));
            }
            b'a'..=b'z' => {
                c.bump();
                words.push(Word {
                    letter: b,
                    value: real_value(c)?,
                });
            }
            _ => return Err(c.error(&format!("unexpected '{}'", b as char))),
        }
    }
    if words.is_empty() && settings.is_empty() {
        return Ok(Statement::Empty);
    }
    Ok(Statement::Block { words, settings })
}

fn oword(c: &mut Cursor<'_>) -> Result<Statement, GcodeError> {
    let label = if c.peek() == Some(b'<') {
        c.name()?
    } else {
        let start_digits = c.number()?;
        format!("{start_digits}")
    };
    const KEYWORDS: [(&str, Keyword); 15] = [
        ("endsub", Keyword::EndSub),
        ("endif", Keyword::EndIf),
        ("endwhile", Keyword::EndWhile),
        ("endrepeat", Keyword::EndRepeat),
        ("elseif", Keyword::ElseIf),
        ("else", Keyword::Else),
        ("sub", Keyword::Sub),
        ("return", Keyword::Return),
        ("call", Keyword::Call),
        ("if", Keyword::If),
        ("while", Keyword::While),
        ("do", Keyword::Do),
        ("break", Keyword::Break),
        ("continue", Keyword::Continue),
        ("repeat", Keyword::Repeat),
    ];
    let Some((name, keyword)) = KEYWORDS.iter().find(|(k, _)| c.starts_with(k)) else {
        return Err(c.error("an o-word keyword (sub, call, if, while, …) expected"));
    };
    c.advance(name.len());
    let mut args = Vec::new();
    while c.peek() == Some(b'[') {
        args.push(real_value(c)?);
    }
    if !c.at_end() {
        return Err(c.error("only bracketed arguments may follow an o-word"));
    }
    Ok(Statement::OWord {
        label,
        keyword: *keyword,
        args,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_spaces_and_case_are_dropped() {
        let s = statement("N10 G1 X 1.5 (move) y-2 ; rest", 1);
        let Statement::Block { words, .. } = s else {
            panic!("{s:?}")
        };
        let letters: Vec<u8> = words.iter().map(|w| w.letter).collect();
        assert_eq!(letters, b"gxy");
        assert_eq!(words[1].value, Expr::Num(1.5));
    }

    #[test]
    fn owords_and_settings_parse() {
        assert!(matches!(
            statement("o100 while [#1 LT 10]", 3),
            Statement::OWord {
                keyword: Keyword::While,
                ref label,
                ..
            } if label == "100"
        ));
        assert!(matches!(
            statement("O<Peck Loop> endwhile", 3),
            Statement::OWord { keyword: Keyword::EndWhile, ref label, .. } if label == "peckloop"
        ));
        let Statement::Block { settings, .. } = statement("#<depth> = [1 + 2]", 4) else {
            panic!()
        };
        assert_eq!(settings[0].0, Target::Named("depth".into()));
    }

    #[test]
    fn bad_lines_say_where() {
        let Statement::Bad(e) = statement("G1 X[1 + ", 7) else {
            panic!()
        };
        assert!(e.to_string().contains("line 7"), "{e}");
        assert!(matches!(statement("G1 X1 @", 2), Statement::Bad(_)));
        assert!(matches!(statement("o100 frobnicate", 2), Statement::Bad(_)));
    }
}
