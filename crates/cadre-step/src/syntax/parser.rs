//! Recursive-descent parsing of one statement's tokens into [`Record`]s and [`Param`]s.
//!
//! The parser works on a single statement (the bytes the indexer found between two `;`), so a
//! mistake in one instance can never leak into another. Nesting is capped at [`MAX_DEPTH`] so
//! that hostile input cannot overflow the stack.

use super::lexer::{LexError, Lexer, Token, parse_real};
use super::string::decode_string;
use super::value::{Param, Record};

/// Deepest nesting of lists and typed parameters accepted. Real files stay below ten; the cap
/// only exists to bound recursion on hostile input.
pub const MAX_DEPTH: usize = 128;

/// A parse failure at a byte offset of the statement.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Failure {
    pub offset: usize,
    pub message: String,
}

impl From<LexError> for Failure {
    fn from(e: LexError) -> Self {
        Failure {
            offset: e.offset,
            message: e.kind.to_string(),
        }
    }
}

/// A short human description of a token for error messages.
pub(crate) fn describe(token: Option<Token<'_>>) -> String {
    match token {
        None => "end of instance".to_owned(),
        Some(Token::Keyword(k)) => format!("keyword {k}"),
        Some(Token::Ref(id)) => format!("#{id}"),
        Some(Token::Integer(i)) => format!("integer {i}"),
        Some(Token::Real(r)) => format!("real {r}"),
        Some(Token::String(_)) => "a string".to_owned(),
        Some(Token::Enum(e)) => format!(".{e}."),
        Some(Token::Binary(_)) => "a binary".to_owned(),
        Some(Token::Unset) => "'$'".to_owned(),
        Some(Token::Derived) => "'*'".to_owned(),
        Some(Token::LParen) => "'('".to_owned(),
        Some(Token::RParen) => "')'".to_owned(),
        Some(Token::Comma) => "','".to_owned(),
        Some(Token::Semicolon) => "';'".to_owned(),
        Some(Token::Equals) => "'='".to_owned(),
        Some(Token::ExchangeStart) => "ISO-10303-21".to_owned(),
        Some(Token::ExchangeEnd) => "END-ISO-10303-21".to_owned(),
    }
}

/// A parsed instance statement.
pub(crate) struct ParsedInstance<'a> {
    pub id: u64,
    pub records: Vec<Record<'a>>,
    pub complex: bool,
}

pub(crate) struct Parser<'a, K> {
    lexer: Lexer<'a>,
    /// Maps a keyword as written to its canonical (upper-case) spelling.
    canon: K,
}

/// A token and its start offset.
type At<'a> = (Option<Token<'a>>, usize);

impl<'a, K: Fn(&'a str) -> &'a str> Parser<'a, K> {
    pub fn new(bytes: &'a [u8], canon: K) -> Self {
        Parser {
            lexer: Lexer::new(bytes),
            canon,
        }
    }

    /// The next token and its start offset. The grammar needs no look-ahead beyond the
    /// token in hand, so there is no peek buffer to pay for on every token.
    #[inline]
    fn next(&mut self) -> Result<At<'a>, Failure> {
        let token = self.lexer.next_token()?;
        Ok((token, self.lexer.token_start()))
    }

    #[cold]
    fn unexpected<T>(token: Option<Token<'_>>, at: usize, expected: &str) -> Result<T, Failure> {
        Err(Failure {
            offset: at,
            message: format!("expected {expected}, found {}", describe(token)),
        })
    }

    fn expect(&mut self, want: Token<'static>, what: &str) -> Result<(), Failure> {
        match self.next()? {
            (Some(t), _) if t == want => Ok(()),
            (t, at) => Self::unexpected(t, at, what),
        }
    }

    fn expect_end(&mut self) -> Result<(), Failure> {
        match self.next()? {
            (None, _) => Ok(()),
            (t, at) => Self::unexpected(t, at, "end of instance"),
        }
    }

    /// `#id = KEYWORD(…)` or `#id = (A(…) B(…))`, then the end of the statement.
    pub fn instance(mut self) -> Result<ParsedInstance<'a>, Failure> {
        let id = match self.next()? {
            (Some(Token::Ref(id)), _) => id,
            (t, at) => return Self::unexpected(t, at, "an instance name '#…'"),
        };
        self.expect(Token::Equals, "'='")?;
        let (records, complex) = match self.next()? {
            (Some(Token::Keyword(k)), _) => (vec![self.record_body(k)?], false),
            (Some(Token::LParen), _) => {
                let mut records = Vec::new();
                loop {
                    match self.next()? {
                        (Some(Token::Keyword(k)), _) => records.push(self.record_body(k)?),
                        (Some(Token::RParen), at) if records.is_empty() => {
                            return Self::unexpected(Some(Token::RParen), at, "a record");
                        }
                        (Some(Token::RParen), _) => break,
                        (t, at) => return Self::unexpected(t, at, "a record or ')'"),
                    }
                }
                (records, true)
            }
            (t, at) => return Self::unexpected(t, at, "an entity keyword or '('"),
        };
        self.expect_end()?;
        Ok(ParsedInstance {
            id,
            records,
            complex,
        })
    }

    /// `KEYWORD(…)` and the end of the statement, e.g. a HEADER entity.
    pub fn record_statement(mut self) -> Result<Record<'a>, Failure> {
        let record = match self.next()? {
            (Some(Token::Keyword(k)), _) => self.record_body(k)?,
            (t, at) => return Self::unexpected(t, at, "an entity keyword"),
        };
        self.expect_end()?;
        Ok(record)
    }

    /// A keyword, optionally followed by a parenthesised parameter list (as in
    /// `DATA('name', (…))`), and the end of the statement.
    pub fn keyword_statement(mut self) -> Result<Record<'a>, Failure> {
        let keyword = match self.next()? {
            (Some(Token::Keyword(k)), _) => (self.canon)(k),
            (t, at) => return Self::unexpected(t, at, "a keyword"),
        };
        let params = match self.next()? {
            (None, _) => {
                return Ok(Record {
                    keyword,
                    params: Vec::new(),
                });
            }
            (Some(Token::LParen), _) => self.param_list(1)?,
            (t, at) => return Self::unexpected(t, at, "'(' or end of statement"),
        };
        self.expect_end()?;
        Ok(Record { keyword, params })
    }

    /// The `(…)` after a record's keyword.
    fn record_body(&mut self, keyword: &'a str) -> Result<Record<'a>, Failure> {
        let keyword = (self.canon)(keyword);
        self.expect(Token::LParen, "'(' after the keyword")?;
        let params = self.param_list(1)?;
        Ok(Record { keyword, params })
    }

    /// Parameters after an already consumed `(`, through the closing `)`.
    fn param_list(&mut self, depth: usize) -> Result<Vec<Param<'a>>, Failure> {
        let mut params = Vec::new();
        let mut token = self.next()?;
        if token.0 == Some(Token::RParen) {
            return Ok(params);
        }
        loop {
            params.push(self.param(token, depth)?);
            match self.next()? {
                (Some(Token::Comma), _) => token = self.next()?,
                (Some(Token::RParen), _) => return Ok(params),
                (t, at) => return Self::unexpected(t, at, "',' or ')'"),
            }
        }
    }

    /// The parameter that starts with `token`.
    fn param(&mut self, (token, at): At<'a>, depth: usize) -> Result<Param<'a>, Failure> {
        Ok(match token {
            Some(Token::Ref(id)) => Param::Ref(id),
            Some(Token::Real(text)) => match parse_real(text) {
                Some(v) => Param::Real(v),
                None => {
                    return Err(Failure {
                        offset: at,
                        message: format!("real {text} is out of range"),
                    });
                }
            },
            Some(Token::Integer(i)) => Param::Integer(i),
            Some(Token::String(raw)) => Param::String(decode_string(raw)),
            Some(Token::Enum(e)) => Param::Enum(e),
            Some(Token::Unset) => Param::Unset,
            Some(Token::Derived) => Param::Derived,
            Some(Token::Binary(b)) => Param::Binary(b),
            Some(Token::LParen) => {
                check_depth(depth, at)?;
                Param::List(self.param_list(depth + 1)?)
            }
            Some(Token::Keyword(k)) => {
                check_depth(depth, at)?;
                let keyword = (self.canon)(k);
                self.expect(Token::LParen, "'(' after the type keyword")?;
                let inner = self.next()?;
                let value = self.param(inner, depth + 1)?;
                self.expect(Token::RParen, "')' closing the typed parameter")?;
                Param::Typed {
                    keyword,
                    value: Box::new(value),
                }
            }
            t => return Self::unexpected(t, at, "a parameter"),
        })
    }
}

fn check_depth(depth: usize, at: usize) -> Result<(), Failure> {
    if depth >= MAX_DEPTH {
        Err(Failure {
            offset: at,
            message: format!("nesting deeper than {MAX_DEPTH} levels"),
        })
    } else {
        Ok(())
    }
}

/// Keyword canonicalisation that keeps the spelling as written (the header and tests, where
/// no keyword table exists).
pub(crate) fn as_written(k: &str) -> &str {
    k
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::borrow::Cow;

    fn inst(s: &str) -> Result<ParsedInstance<'_>, Failure> {
        Parser::new(s.as_bytes(), as_written).instance()
    }

    fn params(s: &str) -> Vec<Param<'_>> {
        match inst(s) {
            Ok(p) => p
                .records
                .into_iter()
                .next()
                .map(|r| r.params)
                .unwrap_or_default(),
            Err(e) => panic!("{s}: {e:?}"),
        }
    }

    #[test]
    fn simple_instance() {
        let p = inst("#7 = CARTESIAN_POINT('', (0., 1.5, -2.E1))").unwrap();
        assert_eq!(p.id, 7);
        assert!(!p.complex);
        assert_eq!(p.records.len(), 1);
        assert_eq!(p.records[0].keyword, "CARTESIAN_POINT");
        assert_eq!(
            p.records[0].params,
            vec![
                Param::String(Cow::Borrowed("")),
                Param::List(vec![Param::Real(0.0), Param::Real(1.5), Param::Real(-20.0)])
            ]
        );
    }

    #[test]
    fn every_param_kind() {
        let p = params(
            r#"#1=X($,*,12,-3,1.,'it''s',.T.,"0F",#12,(),((1)),LENGTH_MEASURE(2.),A(B(.U.)))"#,
        );
        assert_eq!(
            p,
            vec![
                Param::Unset,
                Param::Derived,
                Param::Integer(12),
                Param::Integer(-3),
                Param::Real(1.0),
                Param::String(Cow::Owned("it's".to_owned())),
                Param::Enum("T"),
                Param::Binary("0F"),
                Param::Ref(12),
                Param::List(vec![]),
                Param::List(vec![Param::List(vec![Param::Integer(1)])]),
                Param::Typed {
                    keyword: "LENGTH_MEASURE",
                    value: Box::new(Param::Real(2.0))
                },
                Param::Typed {
                    keyword: "A",
                    value: Box::new(Param::Typed {
                        keyword: "B",
                        value: Box::new(Param::Enum("U"))
                    })
                },
            ]
        );
    }

    #[test]
    fn empty_record() {
        assert_eq!(params("#1=A()"), vec![]);
    }

    #[test]
    fn complex_instance() {
        let p = inst("#3=(A(1) B() C((2),$))").unwrap();
        assert!(p.complex);
        let kws: Vec<_> = p.records.iter().map(|r| r.keyword).collect();
        assert_eq!(kws, ["A", "B", "C"]);
        assert!(inst("#3=()").is_err());
        assert!(inst("#3=(A(1),B())").is_err());
    }

    #[test]
    fn unbalanced_parentheses() {
        for bad in ["#1=A((1,2)", "#1=A(1))", "#1=A(1", "#1=(A(1)", "#1=A(1,)"] {
            assert!(inst(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn real_overflow_is_a_failure() {
        let e = inst("#1=A(1.E999)").err().unwrap();
        assert!(e.message.contains("out of range"), "{}", e.message);
        assert_eq!(e.offset, 5);
    }

    #[test]
    fn depth_is_capped() {
        let ok = format!(
            "#1=A({}1{})",
            "(".repeat(MAX_DEPTH - 1),
            ")".repeat(MAX_DEPTH - 1)
        );
        assert!(inst(&ok).is_ok());
        let deep = format!("#1=A({}1{})", "(".repeat(MAX_DEPTH), ")".repeat(MAX_DEPTH));
        let e = inst(&deep).err().unwrap();
        assert!(e.message.contains("nesting"), "{}", e.message);
        // Far deeper than the cap must fail fast, not overflow the stack.
        let hostile = format!("#1=A({}", "(".repeat(1_000_000));
        assert!(inst(&hostile).is_err());
        let hostile_typed = format!("#1=A({}", "T(".repeat(1_000_000));
        assert!(inst(&hostile_typed).is_err());
    }

    #[test]
    fn trailing_tokens_rejected() {
        assert!(inst("#1=A(1) B(2)").is_err());
        assert!(inst("#1=A(1);").is_err());
    }

    #[test]
    fn keyword_statement_with_and_without_params() {
        let r = Parser::new(b"DATA", as_written)
            .keyword_statement()
            .unwrap();
        assert_eq!(r.keyword, "DATA");
        assert!(r.params.is_empty());
        let r = Parser::new(b"DATA('x',('S'))", as_written)
            .keyword_statement()
            .unwrap();
        assert_eq!(r.params.len(), 2);
    }
}
