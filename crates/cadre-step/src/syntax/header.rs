//! The HEADER section's three mandatory entities (ISO 10303-21 §8.2).

use super::value::{Param, Record};

/// The HEADER section: `FILE_DESCRIPTION`, `FILE_NAME` and `FILE_SCHEMA`.
///
/// Fields the file leaves out, gives as `$`, or spells with the wrong type are empty: the
/// header is informational, so a sloppy one must not stop a file from loading (a
/// [`Diagnostic`](super::Diagnostic) records entities that are missing or malformed).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Header {
    /// `FILE_DESCRIPTION.description`: free-form lines describing the content.
    pub description: Vec<String>,
    /// `FILE_DESCRIPTION.implementation_level`, e.g. `2;1`.
    pub implementation_level: String,
    /// `FILE_NAME.name`: the name the file was exported under.
    pub file_name: String,
    /// `FILE_NAME.time_stamp`, as written (ISO 8601 by the standard, not always in practice).
    pub time_stamp: String,
    /// `FILE_NAME.author`.
    pub author: Vec<String>,
    /// `FILE_NAME.organization`.
    pub organization: Vec<String>,
    /// `FILE_NAME.preprocessor_version`: the STEP toolkit that wrote the file.
    pub preprocessor_version: String,
    /// `FILE_NAME.originating_system`: the CAD system the data came from.
    pub originating_system: String,
    /// `FILE_NAME.authorization`.
    pub authorization: String,
    /// `FILE_SCHEMA` identifiers, e.g. `AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }`.
    pub schemas: Vec<String>,
}

/// Which mandatory header entities a header section contained.
#[derive(Default)]
pub(crate) struct Seen {
    pub description: bool,
    pub name: bool,
    pub schema: bool,
}

fn text(param: Option<&Param<'_>>) -> String {
    param
        .and_then(Param::as_str)
        .map(str::to_owned)
        .unwrap_or_default()
}

/// A `LIST OF STRING`; a lone string is accepted as a one-element list, since some exporters
/// forget the parentheses.
fn texts(param: Option<&Param<'_>>) -> Vec<String> {
    match param {
        Some(Param::List(items)) => items
            .iter()
            .filter_map(Param::as_str)
            .map(str::to_owned)
            .collect(),
        Some(p) => p.as_str().map(str::to_owned).into_iter().collect(),
        None => Vec::new(),
    }
}

impl Header {
    /// Takes what it knows from one header record; returns whether the keyword was one of
    /// the three mandatory entities.
    pub(crate) fn absorb(&mut self, record: &Record<'_>, seen: &mut Seen) -> bool {
        let p = |i: usize| record.params.get(i);
        let keyword = record.keyword;
        if keyword.eq_ignore_ascii_case("FILE_DESCRIPTION") {
            self.description = texts(p(0));
            self.implementation_level = text(p(1));
            seen.description = true;
        } else if keyword.eq_ignore_ascii_case("FILE_NAME") {
            self.file_name = text(p(0));
            self.time_stamp = text(p(1));
            self.author = texts(p(2));
            self.organization = texts(p(3));
            self.preprocessor_version = text(p(4));
            self.originating_system = text(p(5));
            self.authorization = text(p(6));
            seen.name = true;
        } else if keyword.eq_ignore_ascii_case("FILE_SCHEMA") {
            self.schemas = texts(p(0));
            seen.schema = true;
        } else {
            return false;
        }
        true
    }
}
