//! Decoded parameter values of an instance (ISO 10303-21 §6.4 / §12).

use std::borrow::Cow;

/// One parameter of a record. Borrowed from the file's bytes wherever no decoding is needed.
#[derive(Clone, Debug, PartialEq)]
pub enum Param<'a> {
    /// `$`: value not given.
    Unset,
    /// `*`: value derived from other attributes.
    Derived,
    /// An integer.
    Integer(i64),
    /// A real, in any legal spelling (`1.`, `1.E3`, `-.5E-2`, `1.0e+03`, …).
    Real(f64),
    /// A string with `''` and the `\X\ \X2\ \X4\ \S\ \P\` directives decoded to UTF-8.
    String(Cow<'a, str>),
    /// An enumeration, without its dots, e.g. `T`, `F`, `U`, `UNSPECIFIED`.
    Enum(&'a str),
    /// A binary as its hex digits (the leading count digit included).
    Binary(&'a str),
    /// A reference to another instance, `#id`.
    Ref(u64),
    /// An aggregate `( … )`.
    List(Vec<Param<'a>>),
    /// A typed parameter such as `LENGTH_MEASURE(2.)`.
    Typed {
        /// Type keyword, upper case.
        keyword: &'a str,
        /// The wrapped value.
        value: Box<Param<'a>>,
    },
}

impl<'a> Param<'a> {
    /// The number, for integers, reals and typed numbers (`LENGTH_MEASURE(2.)`).
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Param::Integer(i) => Some(*i as f64),
            Param::Real(r) => Some(*r),
            Param::Typed { value, .. } => value.as_f64(),
            _ => None,
        }
    }

    /// The integer, for integers and typed integers.
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            Param::Integer(i) => Some(*i),
            Param::Typed { value, .. } => value.as_i64(),
            _ => None,
        }
    }

    /// The referenced instance id.
    pub fn as_ref_id(&self) -> Option<u64> {
        match self {
            Param::Ref(id) => Some(*id),
            _ => None,
        }
    }

    /// The aggregate's members.
    pub fn as_list(&self) -> Option<&[Param<'a>]> {
        match self {
            Param::List(items) => Some(items),
            _ => None,
        }
    }

    /// The decoded string.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Param::String(s) => Some(s),
            Param::Typed { value, .. } => value.as_str(),
            _ => None,
        }
    }

    /// The enumeration value without dots.
    pub fn as_enum(&self) -> Option<&'a str> {
        match self {
            Param::Enum(e) => Some(e),
            _ => None,
        }
    }

    /// A STEP BOOLEAN/LOGICAL: `.T.` is true, `.F.` false; `.U.` and anything else `None`.
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            Param::Enum("T") => Some(true),
            Param::Enum("F") => Some(false),
            Param::Typed { value, .. } => value.as_bool(),
            _ => None,
        }
    }

    /// Whether this is `$`.
    pub fn is_unset(&self) -> bool {
        matches!(self, Param::Unset)
    }
}

/// One `KEYWORD(params…)` record: a whole simple instance, or one part of a complex one.
#[derive(Clone, Debug, PartialEq)]
pub struct Record<'a> {
    /// Entity keyword, upper case, e.g. `CARTESIAN_POINT`.
    pub keyword: &'a str,
    /// Its parameters in order.
    pub params: Vec<Param<'a>>,
}

/// A decoded instance: `#id = KEYWORD(...)` (one record) or `#id = (A(...) B(...))`
/// (a complex instance, several records in the file's order).
#[derive(Clone, Debug, PartialEq)]
pub struct Instance<'a> {
    /// The instance's `#id`.
    pub id: u64,
    /// 1-based line of the `#id` in the file.
    pub line: u32,
    /// The records: one for a simple instance, several for a complex one.
    pub records: Vec<Record<'a>>,
    /// Whether it was written as a complex (multi-record) instance.
    pub complex: bool,
}

impl<'a> Instance<'a> {
    /// The record with this keyword (for a simple instance, its only record if it matches).
    pub fn record(&self, keyword: &str) -> Option<&Record<'a>> {
        self.records.iter().find(|r| r.keyword == keyword)
    }

    /// Whether one of the records has this keyword.
    pub fn has(&self, keyword: &str) -> bool {
        self.record(keyword).is_some()
    }

    /// The keyword of a simple instance (the first record's keyword for a complex one).
    pub fn keyword(&self) -> &'a str {
        self.records.first().map_or("", |r| r.keyword)
    }
}
