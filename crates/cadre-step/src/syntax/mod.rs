//! The ISO 10303-21 exchange structure: lexing, the HEADER section, and an index of the DATA
//! section's instances whose parameters are decoded on demand.
//!
//! Reading keeps the file's bytes and an index entry per instance (id, byte span, line,
//! keyword) rather than a tree of every parameter, so memory stays a small multiple of the file
//! size; [`StepFile::instance`] decodes one instance's parameters when the mapper asks for it.
//!
//! The API the mapper relies on:
//! - `StepFile::parse(bytes: Vec<u8>) -> Result<StepFile, ParseError>`: fatal only when the
//!   input is not an exchange structure at all (no `ISO-10303-21;`, no DATA section). Every
//!   other problem (bad instance, truncated file, duplicate id, …) becomes a [`Diagnostic`] and
//!   the instance is skipped, everything valid is kept.
//! - `StepFile::read(path)` reads a file then parses it.
//! - `header()`, `diagnostics()`, `len()`, `ids()` (file order), `line(id)`,
//!   `keywords(id) -> Option<&[…]>`/`has_keyword(id, kw)`, `ids_with_keyword(kw)`,
//!   `instance(id) -> Result<Instance<'_>, Diagnostic>`.
//!
//! What indexing checks: statement boundaries and each instance's head (`#id = KEYWORD(` or
//! the record keywords of a complex instance); an instance failing those is skipped with a
//! diagnostic. Parameters are checked only when decoded, so a malformed body (unbalanced
//! parentheses, a bad token, an out-of-range number, excessive nesting) is an `Err` from
//! [`StepFile::instance`] naming the line and id; [`StepFile::check_all`] decodes everything.
//!
//! Modules: [`lexer`] (tokens, public for benchmarks and tools), `string` (string directive
//! decoding), `parser` (one statement's records and parameters), `file` (the two-pass
//! indexer behind [`StepFile`]), `header`, and `writer` (Part 21 output for tests and tools).

mod file;
mod header;
pub mod lexer;
mod parser;
mod string;
mod value;
mod writer;

#[cfg(test)]
mod tests;

use std::path::PathBuf;

pub use file::{Keyword, StepFile};
pub use header::Header;
pub use lexer::{LexError, LexErrorKind, Lexer, Token};
pub use parser::MAX_DEPTH;
pub use string::{decode_string, encode_string};
pub use value::{Instance, Param, Record};
pub use writer::{shift_entity_ids, write_param, write_real, write_record};

/// A problem found in a file, located by line and, when known, instance id.
///
/// Displays as `line 12, #34: message` (or `line 12: message` without an id).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}{}: {message}", .id.map(|id| format!(", #{id}")).unwrap_or_default())]
pub struct Diagnostic {
    /// 1-based line in the file (0 when the problem has no place in the file, such as a
    /// request for an id that does not exist).
    pub line: u32,
    /// The instance concerned, when known.
    pub id: Option<u64>,
    /// What is wrong.
    pub message: String,
}

/// Why a file could not be read at all. Anything less severe is a [`Diagnostic`].
#[derive(Debug, thiserror::Error)]
pub enum ParseError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The input does not start with `ISO-10303-21;`.
    #[error("not an ISO 10303-21 file: line {line}: expected ISO-10303-21;, found {found}")]
    NotExchangeStructure {
        /// Line where the first token was expected.
        line: u32,
        /// What was there instead.
        found: String,
    },
    /// The exchange structure has no DATA section, so there is nothing to read.
    #[error("no DATA section (scanning ended at line {line})")]
    NoDataSection {
        /// Line where the structure scan ended.
        line: u32,
    },
    /// The file exceeds what the index can address.
    #[error("file too large: {what}")]
    TooLarge {
        /// Which limit was exceeded.
        what: String,
    },
}
