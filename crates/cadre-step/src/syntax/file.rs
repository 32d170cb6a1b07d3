//! [`StepFile`]: the file's bytes plus a compact index of its DATA instances.
//!
//! Reading happens in two passes:
//!
//! 1. A sequential pass walks the exchange structure. Inside DATA sections it only looks for
//!    statement boundaries — the next `;` outside strings and comments, found with `memchr` —
//!    so it runs at memory speed and records one span per instance.
//! 2. The spans are split into chunks, and each chunk (in parallel with rayon for large
//!    files) reads every statement's head (`#id = KEYWORD(` or the record keywords of a
//!    complex instance), interns its keyword and counts line breaks. Chunk-local results are
//!    then merged: keyword ids remapped to the file's table, line numbers offset by a prefix
//!    sum of the chunks' line counts.
//!
//! Parameters are parsed only by [`StepFile::instance`], on demand, which therefore
//! re-validates the whole statement: the index vouches for boundaries and heads only.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use memchr::{memchr2, memchr3, memmem};
use rayon::prelude::*;

use super::header::{Header, Seen};
use super::lexer::{LexErrorKind, Lexer, Token, is_keyword_char, skip_trivia};
use super::parser::{MAX_DEPTH, Parser, as_written, describe};
use super::value::Instance;
use super::{Diagnostic, ParseError};

/// Files larger than this are indexed in parallel; below it the thread hand-off costs more
/// than it saves.
const PARALLEL_THRESHOLD: usize = 4 << 20;

/// At most this many diagnostics are kept (then one summary), so that a huge garbage file
/// cannot make the diagnostics list itself the memory problem.
const MAX_DIAGNOSTICS: usize = 1000;

/// Marks an [`Entry`] of a simple instance (no side-table row).
const SIMPLE: u32 = u32::MAX;

/// An interned entity keyword: an index into one [`StepFile`]'s keyword table.
///
/// Comparing two `Keyword`s is an integer comparison, which is why the mapper's frequent
/// "is this instance an X?" questions are cheap. Only meaningful with the file it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Keyword(u32);

impl Keyword {
    /// The index in the file's keyword table.
    pub fn index(self) -> u32 {
        self.0
    }
}

/// One indexed instance: 32 bytes.
#[derive(Clone, Copy, Debug)]
struct Entry {
    id: u64,
    /// Byte offset of the statement's `#`.
    offset: u64,
    /// Statement length up to (excluding) its `;`.
    len: u32,
    /// 1-based line of the `#`.
    line: u32,
    /// The keyword; for a complex instance, its first record's.
    keyword: Keyword,
    /// Row of the complex-keyword side table, or [`SIMPLE`].
    complex: u32,
}

const _: () = assert!(std::mem::size_of::<Entry>() == 32);

/// Id → index into `entries`.
#[derive(Debug)]
enum IdMap {
    /// `table[id]` is the entry index (`u32::MAX`: none). Used when ids are reasonably dense,
    /// which is what nearly every exporter writes.
    Dense(Vec<u32>),
    /// Entry indices sorted by id, for sparse or huge ids: 4 bytes per instance, searched
    /// through the entries' own ids.
    Sparse(Vec<u32>),
}

impl IdMap {
    fn get(&self, id: u64, entries: &[Entry]) -> Option<usize> {
        match self {
            IdMap::Dense(table) => {
                let slot = *table.get(usize::try_from(id).ok()?)?;
                (slot != u32::MAX).then_some(slot as usize)
            }
            IdMap::Sparse(order) => {
                let key = |&i: &u32| entries.get(i as usize).map_or(u64::MAX, |e| e.id);
                let at = order.binary_search_by_key(&id, key).ok()?;
                Some(order[at] as usize)
            }
        }
    }
}

/// The keyword table: upper-case names and the reverse map.
#[derive(Debug, Default)]
struct Keywords {
    names: Vec<Box<str>>,
    map: HashMap<Box<str>, Keyword>,
}

fn upper(name: &str) -> Cow<'_, str> {
    if name.bytes().any(|b| b.is_ascii_lowercase()) {
        Cow::Owned(name.to_ascii_uppercase())
    } else {
        Cow::Borrowed(name)
    }
}

impl Keywords {
    fn intern(&mut self, name: &str) -> Keyword {
        let name = upper(name);
        if let Some(&k) = self.map.get(&*name) {
            return k;
        }
        // The table cannot outgrow u32: every name comes from a distinct statement, and the
        // instance count is checked against u32 before indexing.
        let k = Keyword(u32::try_from(self.names.len()).unwrap_or(u32::MAX));
        let boxed: Box<str> = name.into();
        self.names.push(boxed.clone());
        self.map.insert(boxed, k);
        k
    }

    fn get(&self, name: &str) -> Option<Keyword> {
        self.map.get(&*upper(name)).copied()
    }

    /// The upper-case table spelling of `name` if it has one (borrowed from the table, so it
    /// lives as long as the file), else `name` as written.
    fn canonical<'a>(&'a self, name: &'a str) -> &'a str {
        if !name.bytes().any(|b| b.is_ascii_lowercase()) {
            return name;
        }
        match self.get(name) {
            Some(k) => &self.names[k.0 as usize],
            None => name,
        }
    }
}

/// A parsed ISO 10303-21 file: its bytes, HEADER, and an index of its DATA instances whose
/// parameters are decoded on demand by [`StepFile::instance`].
#[derive(Debug)]
pub struct StepFile {
    bytes: Vec<u8>,
    header: Header,
    entries: Vec<Entry>,
    ids: IdMap,
    keywords: Keywords,
    /// Record keywords of complex instances, in file order.
    complex: Vec<Box<[Keyword]>>,
    diagnostics: Vec<Diagnostic>,
}

/// Counts `\n` bytes. Blocks of 64 with a byte-sized accumulator let the compiler use
/// byte-wide SIMD compares and one horizontal sum per block (a plain `filter().count()`
/// widens every byte to a 64-bit lane and runs several times slower).
#[inline]
fn count_newlines(bytes: &[u8]) -> u32 {
    let mut blocks = bytes.chunks_exact(64);
    let mut total = 0usize;
    for block in &mut blocks {
        let mut n = 0u8;
        for &b in block {
            n += u8::from(b == b'\n');
        }
        total += usize::from(n);
    }
    total += blocks.remainder().iter().filter(|&&b| b == b'\n').count();
    u32::try_from(total).unwrap_or(u32::MAX)
}

/// Line numbers for monotonically increasing offsets, counting only the bytes in between.
struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: u32,
}

impl<'a> Lines<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Lines {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    fn at(&mut self, pos: usize) -> u32 {
        let pos = pos.min(self.bytes.len());
        if pos < self.pos {
            // Rare (diagnostics out of order): count again from the start.
            self.pos = 0;
            self.line = 1;
        }
        self.line = self
            .line
            .saturating_add(count_newlines(&self.bytes[self.pos..pos]));
        self.pos = pos;
        self.line
    }
}

/// Diagnostics with a cap.
#[derive(Default)]
struct Diags {
    list: Vec<Diagnostic>,
    dropped: usize,
}

impl Diags {
    fn push(&mut self, line: u32, id: Option<u64>, message: impl Into<String>) {
        if self.list.len() < MAX_DIAGNOSTICS {
            self.list.push(Diagnostic {
                line,
                id,
                message: message.into(),
            });
        } else {
            self.dropped += 1;
        }
    }

    fn finish(mut self, last_line: u32) -> Vec<Diagnostic> {
        if self.dropped > 0 {
            self.list.push(Diagnostic {
                line: last_line,
                id: None,
                message: format!("{} further diagnostics suppressed", self.dropped),
            });
        }
        self.list
    }
}

/// How a statement ends, as found by [`statement_end`].
enum End {
    /// At the `;` at this offset.
    Semicolon(usize),
    /// A string ran into a line that begins a new instance: the string is unterminated, and
    /// scanning resumes at that line.
    BrokenString { string: usize, resume: usize },
    /// A string with no closing quote before the end of input.
    UnterminatedString(usize),
    /// A comment with no closing `*/`.
    UnterminatedComment(usize),
    /// End of input before any `;`.
    Eof,
}

/// Whether `bytes[pos..]` starts like an instance definition, `#123 =` (after blanks).
fn instance_start_at(bytes: &[u8], mut pos: usize) -> bool {
    while matches!(bytes.get(pos), Some(b' ' | b'\t' | b'\r')) {
        pos += 1;
    }
    if bytes.get(pos) != Some(&b'#') {
        return false;
    }
    let digits = pos + 1;
    pos = digits;
    while bytes.get(pos).is_some_and(u8::is_ascii_digit) {
        pos += 1;
    }
    if pos == digits {
        return false;
    }
    while matches!(bytes.get(pos), Some(b' ' | b'\t')) {
        pos += 1;
    }
    bytes.get(pos) == Some(&b'=')
}

/// Finds the `;` ending the statement that starts at `from`, skipping strings and comments
/// (which may contain `;`). This is the hot loop of indexing: `memchr3` jumps between the only
/// three bytes that matter.
fn statement_end(bytes: &[u8], from: usize) -> End {
    let mut pos = from;
    loop {
        let Some(i) = memchr3(b';', b'\'', b'/', &bytes[pos..]) else {
            return End::Eof;
        };
        let at = pos + i;
        match bytes[at] {
            b';' => return End::Semicolon(at),
            b'\'' => {
                let mut q = at + 1;
                loop {
                    match memchr2(b'\'', b'\n', &bytes[q..]) {
                        None => return End::UnterminatedString(at),
                        Some(j) if bytes[q + j] == b'\n' => {
                            // Strings may wrap lines, but a line that starts a new instance
                            // means the quote was never closed: resynchronise there rather
                            // than swallowing the rest of the file.
                            if instance_start_at(bytes, q + j + 1) {
                                return End::BrokenString {
                                    string: at,
                                    resume: q + j + 1,
                                };
                            }
                            q += j + 1;
                        }
                        Some(j) if bytes.get(q + j + 1) == Some(&b'\'') => q += j + 2,
                        Some(j) => {
                            pos = q + j + 1;
                            break;
                        }
                    }
                }
            }
            _ => {
                if bytes.get(at + 1) == Some(&b'*') {
                    match memmem::find(&bytes[at + 2..], b"*/") {
                        Some(j) => pos = at + 2 + j + 2,
                        None => return End::UnterminatedComment(at),
                    }
                } else {
                    pos = at + 1;
                }
            }
        }
    }
}

/// A statement's byte range (excluding its `;`).
#[derive(Clone, Copy, Debug)]
struct Span {
    start: usize,
    end: usize,
}

/// Which section a statement scan is in.
#[derive(Clone, Copy, PartialEq, Eq)]
enum SectionKind {
    Header,
    Data,
    /// A section this layer does not read (ANCHOR, REFERENCE, SIGNATURE).
    Skipped,
}

/// The sequential first pass.
struct Structure<'a> {
    bytes: &'a [u8],
    lines: Lines<'a>,
    diags: Diags,
    /// DATA statement spans (those starting with `#`).
    spans: Vec<Span>,
    header: Header,
}

/// The instance id of a statement, if its first token is `#id`.
fn statement_id(stmt: &[u8]) -> Option<u64> {
    match Lexer::at(stmt, 0).next_token() {
        Ok(Some(Token::Ref(id))) => Some(id),
        _ => None,
    }
}

impl<'a> Structure<'a> {
    fn diag(&mut self, pos: usize, id: Option<u64>, message: impl Into<String>) {
        let line = self.lines.at(pos);
        self.diags.push(line, id, message);
    }

    /// Skips trivia from `pos`; an unterminated comment is reported and ends the input.
    fn skip(&mut self, pos: usize) -> usize {
        match skip_trivia(self.bytes, pos) {
            Ok(p) => p,
            Err(e) => {
                self.diag(e.offset, None, "unterminated comment");
                self.bytes.len()
            }
        }
    }

    /// Reports a statement that could not be ended properly; returns where to resume.
    fn bad_end(&mut self, start: usize, end: End, kind: SectionKind) -> usize {
        let id = statement_id(&self.bytes[start..]);
        let what = if kind == SectionKind::Data && id.is_some() {
            "instance"
        } else {
            "statement"
        };
        match end {
            End::Semicolon(e) => e + 1,
            End::BrokenString { string, resume } => {
                self.diag(string, id, format!("unterminated string; {what} skipped"));
                resume
            }
            End::UnterminatedString(at) => {
                self.diag(at, id, format!("unterminated string; {what} skipped"));
                self.bytes.len()
            }
            End::UnterminatedComment(at) => {
                self.diag(at, id, format!("unterminated comment; {what} skipped"));
                self.bytes.len()
            }
            End::Eof => {
                self.diag(
                    start,
                    id,
                    format!("{what} not terminated by ';' before the end of the file (truncated?)"),
                );
                self.bytes.len()
            }
        }
    }

    /// Scans one section's statements from `pos` up to and including its `ENDSEC;`. Returns
    /// where scanning stopped and, for the header, the statements found.
    fn section(&mut self, mut pos: usize, kind: SectionKind, name: &str) -> (usize, Vec<Span>) {
        let bytes = self.bytes;
        let mut statements = Vec::new();
        loop {
            pos = self.skip(pos);
            if pos >= bytes.len() {
                self.diag(pos, None, format!("{name} section not closed by ENDSEC"));
                return (pos, statements);
            }
            if bytes[pos] != b'#' {
                // Not an instance: ENDSEC, the start of something else, or junk.
                let mut lexer = Lexer::at(bytes, pos);
                match lexer.next_token() {
                    Ok(Some(Token::Keyword(k))) if k.eq_ignore_ascii_case("ENDSEC") => {
                        let after = lexer.position();
                        return match lexer.next_token() {
                            Ok(Some(Token::Semicolon)) => (lexer.position(), statements),
                            _ => {
                                self.diag(after, None, "missing ';' after ENDSEC");
                                (after, statements)
                            }
                        };
                    }
                    Ok(Some(Token::ExchangeEnd)) => {
                        self.diag(pos, None, format!("{name} section not closed by ENDSEC"));
                        return (pos, statements);
                    }
                    Ok(Some(Token::Keyword(k)))
                        if kind != SectionKind::Skipped
                            && is_section_keyword(k)
                            && matches!(
                                lexer.next_token(),
                                Ok(Some(Token::Semicolon | Token::LParen))
                            ) =>
                    {
                        self.diag(pos, None, format!("{name} section not closed by ENDSEC"));
                        return (pos, statements);
                    }
                    Ok(_) if kind == SectionKind::Header => {}
                    Ok(token) if kind == SectionKind::Data => {
                        let found = describe(token);
                        self.diag(
                            pos,
                            None,
                            format!("expected an instance '#id = …', found {found}; skipped"),
                        );
                    }
                    Ok(_) => {}
                    Err(e) => {
                        if kind != SectionKind::Skipped {
                            self.diag(e.offset, None, format!("{}; statement skipped", e.kind));
                        }
                    }
                }
                match statement_end(bytes, pos) {
                    End::Semicolon(e) => {
                        if kind == SectionKind::Header {
                            statements.push(Span { start: pos, end: e });
                        }
                        pos = e + 1;
                    }
                    end => pos = self.bad_end(pos, end, kind),
                }
                continue;
            }
            match statement_end(bytes, pos) {
                End::Semicolon(e) => {
                    match kind {
                        SectionKind::Data => self.spans.push(Span { start: pos, end: e }),
                        SectionKind::Header => {
                            let id = statement_id(&bytes[pos..e]);
                            self.diag(pos, id, "instance in the HEADER section; skipped");
                        }
                        SectionKind::Skipped => {}
                    }
                    pos = e + 1;
                }
                end => pos = self.bad_end(pos, end, kind),
            }
        }
    }

    fn parse_header(&mut self, statements: &[Span]) {
        let mut seen = Seen::default();
        for span in statements {
            let stmt = &self.bytes[span.start..span.end];
            match Parser::new(stmt, as_written).record_statement() {
                Ok(record) => {
                    self.header.absorb(&record, &mut seen);
                }
                Err(f) => {
                    self.diag(
                        span.start + f.offset,
                        None,
                        format!("malformed HEADER entity: {}", f.message),
                    );
                }
            }
        }
        let end = statements.last().map_or(0, |s| s.end);
        for (present, name) in [
            (seen.description, "FILE_DESCRIPTION"),
            (seen.name, "FILE_NAME"),
            (seen.schema, "FILE_SCHEMA"),
        ] {
            if !present {
                self.diag(end, None, format!("HEADER has no {name}"));
            }
        }
    }

    /// Walks the exchange structure; fills `spans` and `header`.
    fn run(&mut self) -> Result<(), ParseError> {
        let bytes = self.bytes;
        let mut pos = if bytes.starts_with(b"\xEF\xBB\xBF") {
            3
        } else {
            0
        };
        let mut lexer = Lexer::at(bytes, pos);
        let not_step = |lexer: &Lexer<'_>, found: String| {
            let line = 1 + count_newlines(&bytes[..lexer.token_start()]);
            ParseError::NotExchangeStructure { line, found }
        };
        match lexer.next_token() {
            Ok(Some(Token::ExchangeStart)) => {}
            Ok(t) => return Err(not_step(&lexer, describe(t))),
            Err(e) => return Err(not_step(&lexer, e.kind.to_string())),
        }
        match lexer.next_token() {
            Ok(Some(Token::Semicolon)) => {}
            Ok(t) => {
                return Err(not_step(
                    &lexer,
                    format!("ISO-10303-21 followed by {}", describe(t)),
                ));
            }
            Err(e) => return Err(not_step(&lexer, e.kind.to_string())),
        }
        pos = lexer.position();

        // HEADER; … ENDSEC;
        let mut lexer = Lexer::at(bytes, pos);
        match lexer.next_token() {
            Ok(Some(Token::Keyword(k))) if k.eq_ignore_ascii_case("HEADER") => {
                match lexer.next_token() {
                    Ok(Some(Token::Semicolon)) => pos = lexer.position(),
                    _ => {
                        self.diag(lexer.token_start(), None, "missing ';' after HEADER");
                        pos = lexer.token_start();
                    }
                }
                let (end, statements) = self.section(pos, SectionKind::Header, "HEADER");
                pos = end;
                self.parse_header(&statements);
            }
            _ => self.diag(pos, None, "missing HEADER section"),
        }

        let mut found_data = false;
        loop {
            pos = self.skip(pos);
            if pos >= bytes.len() {
                self.diag(pos, None, "missing END-ISO-10303-21 (file truncated?)");
                break;
            }
            let mut lexer = Lexer::at(bytes, pos);
            match lexer.next_token() {
                Ok(Some(Token::ExchangeEnd)) => break,
                Ok(Some(Token::Keyword(k))) if is_section_keyword(k) => {
                    let data = k.eq_ignore_ascii_case("DATA");
                    let name = k.to_ascii_uppercase();
                    // The section's own statement: `DATA;` or `DATA('name', (…));`.
                    let start = pos;
                    pos = match statement_end(bytes, start) {
                        End::Semicolon(e) => {
                            if let Err(f) =
                                Parser::new(&bytes[start..e], as_written).keyword_statement()
                            {
                                self.diag(
                                    start + f.offset,
                                    None,
                                    format!("malformed {name}: {}", f.message),
                                );
                            }
                            e + 1
                        }
                        end => self.bad_end(start, end, SectionKind::Skipped),
                    };
                    if data {
                        found_data = true;
                        pos = self.section(pos, SectionKind::Data, &name).0;
                    } else {
                        self.diag(start, None, format!("{name} section ignored"));
                        pos = self.section(pos, SectionKind::Skipped, &name).0;
                    }
                }
                other => {
                    let found = match other {
                        Ok(t) => describe(t),
                        Err(e) => e.kind.to_string(),
                    };
                    self.diag(
                        pos,
                        statement_id(&bytes[pos..]),
                        format!("unexpected {found} outside of a section; skipped"),
                    );
                    pos = match statement_end(bytes, pos) {
                        End::Semicolon(e) => e + 1,
                        end => self.bad_end(pos, end, SectionKind::Skipped),
                    };
                }
            }
        }
        if !found_data {
            return Err(ParseError::NoDataSection {
                line: self.lines.at(pos),
            });
        }
        Ok(())
    }
}

fn is_section_keyword(k: &str) -> bool {
    ["DATA", "HEADER", "ANCHOR", "REFERENCE", "SIGNATURE"]
        .iter()
        .any(|s| k.eq_ignore_ascii_case(s))
}

/// What one chunk of statements yields; keyword ids are chunk-local, lines relative to the
/// chunk's first statement.
struct Chunk<'a> {
    entries: Vec<Entry>,
    keywords: Vec<&'a [u8]>,
    complex: Vec<Vec<u32>>,
    diags: Vec<(u32, Option<u64>, String)>,
    /// Line breaks from the first statement's start to the next chunk's.
    newlines: u32,
}

/// The head of one instance statement: its id and record keyword(s).
enum Head<'a> {
    Simple(u64, &'a [u8]),
    Complex(u64, Vec<&'a [u8]>),
}

/// Reads `#id = KEYWORD(` or `#id = (A( … ) B( … ))`. Errors are `(offset, id, message)`.
fn read_head(stmt: &[u8]) -> Result<Head<'_>, (usize, Option<u64>, String)> {
    let mut lexer = Lexer::new(stmt);
    let fail = |lexer: &Lexer<'_>, id, msg: String| Err((lexer.token_start(), id, msg));
    let id = match lexer.next_token() {
        Ok(Some(Token::Ref(id))) => id,
        Ok(t) => {
            return fail(
                &lexer,
                None,
                format!("expected '#id', found {}", describe(t)),
            );
        }
        Err(e) if e.kind == LexErrorKind::InstanceNameOverflow => {
            let digits: String = stmt
                .iter()
                .skip(1)
                .take_while(|b| b.is_ascii_digit())
                .take(40)
                .map(|&b| char::from(b))
                .collect();
            return fail(
                &lexer,
                None,
                format!("instance id #{digits} out of range; skipped"),
            );
        }
        Err(e) => return fail(&lexer, None, format!("{}; skipped", e.kind)),
    };
    let some_id = Some(id);
    match lexer.next_token() {
        Ok(Some(Token::Equals)) => {}
        Ok(t) => {
            return fail(
                &lexer,
                some_id,
                format!("expected '=', found {}", describe(t)),
            );
        }
        Err(e) => return fail(&lexer, some_id, e.kind.to_string()),
    }
    match lexer.next_token() {
        Ok(Some(Token::Keyword(k))) => match lexer.next_token() {
            Ok(Some(Token::LParen)) => Ok(Head::Simple(id, k.as_bytes())),
            Ok(t) => fail(
                &lexer,
                some_id,
                format!("expected '(' after {k}, found {}", describe(t)),
            ),
            Err(e) => fail(&lexer, some_id, e.kind.to_string()),
        },
        Ok(Some(Token::LParen)) => {
            // Complex instance: the keywords at depth 1 that open a record.
            let mut keywords = Vec::new();
            let mut depth = 1usize;
            let mut pending: Option<&str> = None;
            while depth > 0 {
                let token = match lexer.next_token() {
                    Ok(Some(t)) => t,
                    Ok(None) => return fail(&lexer, some_id, "unbalanced parentheses".to_owned()),
                    Err(e) => return fail(&lexer, some_id, e.kind.to_string()),
                };
                match token {
                    Token::LParen => {
                        if let Some(k) = pending.take() {
                            keywords.push(k.as_bytes());
                        }
                        depth += 1;
                        if depth > MAX_DEPTH {
                            return fail(
                                &lexer,
                                some_id,
                                format!("nesting deeper than {MAX_DEPTH} levels"),
                            );
                        }
                    }
                    Token::RParen => depth -= 1,
                    Token::Keyword(k) if depth == 1 => pending = Some(k),
                    _ => {}
                }
                if depth == 1 && !matches!(token, Token::Keyword(_) | Token::RParen) {
                    pending = None;
                }
            }
            if keywords.is_empty() {
                return fail(
                    &lexer,
                    some_id,
                    "complex instance without records".to_owned(),
                );
            }
            Ok(Head::Complex(id, keywords))
        }
        Ok(t) => fail(
            &lexer,
            some_id,
            format!("expected an entity keyword or '(', found {}", describe(t)),
        ),
        Err(e) => fail(&lexer, some_id, e.kind.to_string()),
    }
}

/// The common head `#123 = KEYWORD(`, read straight from the bytes: the id and the keyword.
/// `None` for anything else (complex instances, comments, errors), which then takes the
/// general path through the lexer in [`read_head`].
#[inline]
fn quick_head(stmt: &[u8]) -> Option<(u64, &[u8])> {
    let blank = |b: &u8| matches!(b, b' ' | b'\t' | b'\r' | b'\n');
    let mut i = 1;
    let mut id: u64 = 0;
    while let Some(&c) = stmt.get(i).filter(|c| c.is_ascii_digit()) {
        id = id.checked_mul(10)?.checked_add(u64::from(c - b'0'))?;
        i += 1;
    }
    if i == 1 {
        return None;
    }
    while stmt.get(i).is_some_and(blank) {
        i += 1;
    }
    if stmt.get(i) != Some(&b'=') {
        return None;
    }
    i += 1;
    while stmt.get(i).is_some_and(blank) {
        i += 1;
    }
    let start = i;
    if stmt.get(i) == Some(&b'!') {
        i += 1;
    }
    if !stmt
        .get(i)
        .is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_')
    {
        return None;
    }
    while stmt.get(i).is_some_and(|&c| is_keyword_char(c)) {
        i += 1;
    }
    let end = i;
    while stmt.get(i).is_some_and(blank) {
        i += 1;
    }
    (stmt.get(i) == Some(&b'(')).then(|| (id, &stmt[start..end]))
}

fn index_chunk<'a>(bytes: &'a [u8], spans: &[Span], next_start: usize) -> Chunk<'a> {
    let mut chunk = Chunk {
        entries: Vec::with_capacity(spans.len()),
        keywords: Vec::new(),
        complex: Vec::new(),
        diags: Vec::new(),
        newlines: 0,
    };
    let Some(first) = spans.first() else {
        return chunk;
    };
    let mut local: HashMap<&'a [u8], u32> = HashMap::new();
    // A file uses a few hundred distinct keywords at most, so a small direct-mapped cache in
    // front of the (DoS-resistant, but slower) SipHash map answers nearly every lookup with
    // one short comparison.
    let mut cache: [(&'a [u8], u32); 64] = [(b"", 0); 64];
    let mut intern = |k: &'a [u8], table: &mut Vec<&'a [u8]>| -> u32 {
        let byte = |i: usize| usize::from(k.get(i).copied().unwrap_or(0));
        let slot =
            (k.len() ^ byte(0) << 1 ^ byte(k.len() / 2) << 2 ^ byte(k.len().wrapping_sub(1)) << 3)
                & 63;
        if cache[slot].0 == k && !k.is_empty() {
            return cache[slot].1;
        }
        let id = *local.entry(k).or_insert_with(|| {
            table.push(k);
            u32::try_from(table.len() - 1).unwrap_or(u32::MAX)
        });
        cache[slot] = (k, id);
        id
    };
    let mut line = 0u32;
    let mut prev = first.start;
    for span in spans {
        line = line.saturating_add(count_newlines(&bytes[prev..span.start]));
        prev = span.start;
        let stmt = &bytes[span.start..span.end];
        let Ok(len) = u32::try_from(stmt.len()) else {
            chunk.diags.push((
                line,
                statement_id(stmt),
                "instance longer than 4 GiB; skipped".into(),
            ));
            continue;
        };
        let head = match quick_head(stmt) {
            Some((id, k)) => Ok(Head::Simple(id, k)),
            None => read_head(stmt),
        };
        let (id, keyword, complex) = match head {
            Ok(Head::Simple(id, k)) => (id, intern(k, &mut chunk.keywords), SIMPLE),
            Ok(Head::Complex(id, ks)) => {
                let ks: Vec<u32> = ks
                    .into_iter()
                    .map(|k| intern(k, &mut chunk.keywords))
                    .collect();
                let first = ks.first().copied().unwrap_or(0);
                chunk.complex.push(ks);
                (
                    id,
                    first,
                    u32::try_from(chunk.complex.len() - 1).unwrap_or(u32::MAX),
                )
            }
            Err((offset, id, message)) => {
                let at = line.saturating_add(count_newlines(&stmt[..offset.min(stmt.len())]));
                chunk.diags.push((at, id, message));
                continue;
            }
        };
        chunk.entries.push(Entry {
            id,
            offset: span.start as u64,
            len,
            line,
            keyword: Keyword(keyword),
            complex,
        });
    }
    chunk.newlines = line.saturating_add(count_newlines(&bytes[prev..next_start.max(prev)]));
    chunk
}

/// Builds the id map, dropping later duplicates of an id (with a diagnostic each).
fn build_ids(entries: &mut Vec<Entry>, diags: &mut Diags) -> IdMap {
    let max_id = entries.iter().map(|e| e.id).max().unwrap_or(0);
    let dense_limit = (entries.len() as u64)
        .saturating_mul(2)
        .saturating_add(1024);
    let build = |entries: &[Entry]| -> (IdMap, Vec<usize>) {
        let mut dups = Vec::new();
        if max_id <= dense_limit {
            let mut table = vec![u32::MAX; max_id as usize + 1];
            for (i, e) in entries.iter().enumerate() {
                let slot = &mut table[e.id as usize];
                if *slot == u32::MAX {
                    *slot = i as u32;
                } else {
                    dups.push(i);
                }
            }
            (IdMap::Dense(table), dups)
        } else {
            let mut order: Vec<u32> = (0..entries.len() as u32).collect();
            // By (id, index): among duplicates the first in the file sorts first and is kept.
            order.par_sort_unstable_by_key(|&i| (entries[i as usize].id, i));
            let mut previous: Option<u64> = None;
            order.retain(|&i| {
                let id = entries[i as usize].id;
                let duplicate = previous == Some(id);
                if duplicate {
                    dups.push(i as usize);
                }
                previous = Some(id);
                !duplicate
            });
            (IdMap::Sparse(order), dups)
        }
    };
    let (map, mut dups) = build(entries);
    if dups.is_empty() {
        return map;
    }
    dups.sort_unstable();
    for &i in &dups {
        let e = entries[i];
        let first_line = map.get(e.id, entries).map_or(0, |f| entries[f].line);
        diags.push(
            e.line,
            Some(e.id),
            format!(
                "duplicate instance #{} (first defined on line {first_line}); ignored",
                e.id
            ),
        );
    }
    let mut index = 0usize;
    let mut next_dup = dups.iter().peekable();
    entries.retain(|_| {
        let keep = next_dup.peek() != Some(&&index);
        if !keep {
            next_dup.next();
        }
        index += 1;
        keep
    });
    build(entries).0
}

impl StepFile {
    /// Parses an exchange structure and indexes its DATA instances.
    ///
    /// Fails only when the input is not an exchange structure at all (no `ISO-10303-21;`
    /// first, or no DATA section); every other problem becomes a [`Diagnostic`] and the
    /// affected instance is skipped while everything valid is kept.
    pub fn parse(bytes: Vec<u8>) -> Result<StepFile, ParseError> {
        let mut structure = Structure {
            bytes: &bytes,
            lines: Lines::new(&bytes),
            diags: Diags::default(),
            spans: Vec::new(),
            header: Header::default(),
        };
        structure.run()?;
        let Structure {
            mut diags,
            spans,
            header,
            mut lines,
            ..
        } = structure;
        if u32::try_from(spans.len()).is_err() {
            return Err(ParseError::TooLarge {
                what: format!("{} instances (at most {} supported)", spans.len(), u32::MAX),
            });
        }

        // Second pass: heads, keywords and lines per chunk.
        let parallel = bytes.len() > PARALLEL_THRESHOLD && spans.len() >= 4096;
        let chunk_count = if parallel {
            rayon::current_num_threads().max(1) * 8
        } else {
            1
        };
        let chunk_len = spans.len().div_ceil(chunk_count).max(1);
        let work = |k: usize| {
            let from = k * chunk_len;
            let to = (from + chunk_len).min(spans.len());
            let next_start = spans.get(to).map_or(bytes.len(), |s| s.start);
            index_chunk(&bytes, &spans[from..to], next_start)
        };
        let n = spans.len().div_ceil(chunk_len);
        let chunks: Vec<Chunk<'_>> = if parallel {
            (0..n).into_par_iter().map(work).collect()
        } else {
            (0..n).map(work).collect()
        };
        let mut line = 1 + spans
            .first()
            .map_or(0, |s| count_newlines(&bytes[..s.start]));
        drop(spans);

        // Merge: remap keywords, offset lines, concatenate.
        let total: usize = chunks.iter().map(|c| c.entries.len()).sum();
        let mut entries = Vec::with_capacity(total);
        let mut keywords = Keywords::default();
        let mut complex: Vec<Box<[Keyword]>> = Vec::new();
        for chunk in chunks {
            // Keywords are ASCII (both head readers accept only keyword characters).
            let remap: Vec<Keyword> = chunk
                .keywords
                .iter()
                .map(|k| keywords.intern(std::str::from_utf8(k).unwrap_or("")))
                .collect();
            let map = |k: u32| remap.get(k as usize).copied().unwrap_or(Keyword(0));
            let complex_base = u32::try_from(complex.len()).unwrap_or(u32::MAX);
            complex.extend(
                chunk
                    .complex
                    .iter()
                    .map(|ks| ks.iter().map(|&k| map(k)).collect::<Box<[Keyword]>>()),
            );
            entries.extend(chunk.entries.iter().map(|e| Entry {
                keyword: map(e.keyword.0),
                line: line.saturating_add(e.line),
                complex: if e.complex == SIMPLE {
                    SIMPLE
                } else {
                    complex_base.saturating_add(e.complex)
                },
                ..*e
            }));
            for (l, id, message) in chunk.diags {
                diags.push(line.saturating_add(l), id, message);
            }
            line = line.saturating_add(chunk.newlines);
        }
        // After the last chunk `line` is the file's last line (its count runs to the end).
        let last_line = if n > 0 { line } else { lines.at(bytes.len()) };
        // Diagnostics came per phase; present them in file order.
        let ids = build_ids(&mut entries, &mut diags);
        let mut diagnostics = diags.finish(last_line);
        diagnostics.sort_by_key(|d| d.line);
        Ok(StepFile {
            bytes,
            header,
            entries,
            ids,
            keywords,
            complex,
            diagnostics,
        })
    }

    /// Reads the file at `path` and [parses](StepFile::parse) it.
    pub fn read(path: &Path) -> Result<StepFile, ParseError> {
        let bytes = std::fs::read(path).map_err(|source| ParseError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        StepFile::parse(bytes)
    }

    /// The HEADER section.
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Problems found while reading the structure and indexing, in line order. Problems
    /// inside an instance's parameters surface only when it is decoded (see
    /// [`StepFile::check_all`]).
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }

    /// Number of indexed instances.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the DATA sections hold no valid instance.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Instance ids in file order.
    pub fn ids(&self) -> impl Iterator<Item = u64> + '_ {
        self.entries.iter().map(|e| e.id)
    }

    fn entry(&self, id: u64) -> Option<&Entry> {
        self.ids
            .get(id, &self.entries)
            .and_then(|i| self.entries.get(i))
    }

    /// Whether instance `#id` exists.
    pub fn contains(&self, id: u64) -> bool {
        self.entry(id).is_some()
    }

    /// 1-based line of `#id =` in the file.
    pub fn line(&self, id: u64) -> Option<u32> {
        self.entry(id).map(|e| e.line)
    }

    /// The instance's record keywords: one for a simple instance, several (in file order)
    /// for a complex one. Turn them into names with [`StepFile::keyword_name`].
    pub fn keywords(&self, id: u64) -> Option<&[Keyword]> {
        let e = self.entry(id)?;
        if e.complex == SIMPLE {
            Some(std::slice::from_ref(&e.keyword))
        } else {
            self.complex.get(e.complex as usize).map(|ks| &ks[..])
        }
    }

    /// The upper-case name of an interned keyword ("" for one from another file).
    pub fn keyword_name(&self, keyword: Keyword) -> &str {
        self.keywords
            .names
            .get(keyword.0 as usize)
            .map_or("", |n| n)
    }

    /// The interned keyword with this name (case-insensitive), if any instance uses it.
    /// Resolving a name once and then using [`StepFile::has_keyword_id`] saves a hash lookup
    /// per question.
    pub fn keyword(&self, name: &str) -> Option<Keyword> {
        self.keywords.get(name)
    }

    /// Whether `#id` is a simple instance of `keyword` or a complex instance with a record of
    /// `keyword` (case-insensitive).
    pub fn has_keyword(&self, id: u64, keyword: &str) -> bool {
        self.keyword(keyword)
            .is_some_and(|k| self.has_keyword_id(id, k))
    }

    /// [`StepFile::has_keyword`] for an already resolved keyword.
    pub fn has_keyword_id(&self, id: u64, keyword: Keyword) -> bool {
        self.keywords(id).is_some_and(|ks| ks.contains(&keyword))
    }

    /// All instances, simple or complex, having a record with this keyword, in file order.
    pub fn ids_with_keyword(&self, keyword: &str) -> Vec<u64> {
        let Some(k) = self.keyword(keyword) else {
            return Vec::new();
        };
        self.entries
            .iter()
            .filter(|e| {
                if e.complex == SIMPLE {
                    e.keyword == k
                } else {
                    self.complex
                        .get(e.complex as usize)
                        .is_some_and(|ks| ks.contains(&k))
                }
            })
            .map(|e| e.id)
            .collect()
    }

    /// The statement text of `#id` (from `#` up to, excluding, its `;`), e.g. for messages.
    pub fn source(&self, id: u64) -> Option<&[u8]> {
        let e = self.entry(id)?;
        let start = usize::try_from(e.offset).ok()?;
        self.bytes.get(start..start.checked_add(e.len as usize)?)
    }

    /// Decodes instance `#id`'s parameters.
    ///
    /// The whole statement is parsed and validated here (indexing only checked its head), so
    /// a malformed body — unbalanced parentheses, bad tokens, a real beyond `f64`, nesting
    /// deeper than the cap — is an error naming the line and the id. An unknown id is an
    /// error with line 0.
    pub fn instance(&self, id: u64) -> Result<Instance<'_>, Diagnostic> {
        let (Some(e), Some(stmt)) = (self.entry(id), self.source(id)) else {
            return Err(Diagnostic {
                line: 0,
                id: Some(id),
                message: "no such instance".to_owned(),
            });
        };
        let canon = |k| self.keywords.canonical(k);
        match Parser::new(stmt, canon).instance() {
            Ok(parsed) => Ok(Instance {
                id: parsed.id,
                line: e.line,
                records: parsed.records,
                complex: parsed.complex,
            }),
            Err(f) => Err(Diagnostic {
                line: e
                    .line
                    .saturating_add(count_newlines(&stmt[..f.offset.min(stmt.len())])),
                id: Some(id),
                message: f.message,
            }),
        }
    }

    /// Decodes every instance (in parallel) and returns the failures in file order: a full
    /// validation, for tools and tests; the mapper decodes lazily instead.
    pub fn check_all(&self) -> Vec<Diagnostic> {
        self.entries
            .par_iter()
            .filter_map(|e| self.instance(e.id).err())
            .collect()
    }
}
