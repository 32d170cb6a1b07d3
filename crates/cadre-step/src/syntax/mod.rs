//! The ISO 10303-21 exchange structure: lexing, the HEADER section, and an index of the DATA
//! section's instances whose parameters are decoded on demand.
//!
//! Reading keeps the file's bytes and an index entry per instance (id, byte span, line,
//! keyword) rather than a tree of every parameter, so memory stays a small multiple of the file
//! size; [`StepFile::instance`] decodes one instance's parameters when the mapper asks for it.
//!
//! CONTRACT (implemented by the parser work; the mapper relies on exactly this API):
//! - `StepFile::parse(bytes: Vec<u8>) -> Result<StepFile, ParseError>`: fatal only when the
//!   input is not an exchange structure at all (no `ISO-10303-21;`, no DATA section). Every
//!   other problem (bad instance, truncated file, duplicate id, …) becomes a [`Diagnostic`] and
//!   the instance is skipped, everything valid is kept.
//! - `StepFile::read(path)` reads a file then parses it.
//! - `header()`, `diagnostics()`, `len()`, `ids()` (file order), `line(id)`,
//!   `keywords(id) -> Option<&[…]>`/`has_keyword(id, kw)`, `ids_with_keyword(kw)`,
//!   `instance(id) -> Result<Instance<'_>, Diagnostic>`.

mod value;

pub use value::{Instance, Param, Record};
