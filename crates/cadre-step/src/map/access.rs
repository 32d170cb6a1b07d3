//! Typed access to an instance's attributes, with errors that name the instance.
//!
//! STEP writes a simple instance with all inherited attributes in order, and a complex
//! instance as one record per entity type with only that type's own attributes. [`Attrs`]
//! hides the difference: it is the flat attribute list the mapper reads by position.

use super::error::{MapError, MapResult};
use crate::syntax::{Instance, Param};

/// The attributes of one instance, read by position, with errors naming the instance.
pub struct Attrs<'i, 'a> {
    /// Instance id, for errors.
    pub id: u64,
    /// Keyword the attributes belong to, for errors.
    pub keyword: &'a str,
    /// The parameters.
    pub params: &'i [Param<'a>],
}

impl<'i, 'a> Attrs<'i, 'a> {
    /// The attributes of the record named `keyword` (for a simple instance, its only record).
    pub fn of(inst: &'i Instance<'a>, keyword: &str) -> MapResult<Self> {
        let rec = inst
            .record(keyword)
            .ok_or_else(|| MapError::new(inst.id, format!("expected {keyword}")))?;
        Ok(Self {
            id: inst.id,
            keyword: rec.keyword,
            params: &rec.params,
        })
    }

    /// The attributes of a simple instance's record (or the first record of a complex one).
    pub fn first(inst: &'i Instance<'a>) -> MapResult<Self> {
        let rec = inst
            .records
            .first()
            .ok_or_else(|| MapError::new(inst.id, "instance has no record"))?;
        Ok(Self {
            id: inst.id,
            keyword: rec.keyword,
            params: &rec.params,
        })
    }

    /// An error about this instance.
    pub fn err(&self, message: impl Into<String>) -> MapError {
        MapError::new(self.id, format!("{}: {}", self.keyword, message.into()))
    }

    /// Parameter `i`, or an arity error.
    pub fn get(&self, i: usize) -> MapResult<&'i Param<'a>> {
        self.params.get(i).ok_or_else(|| {
            self.err(format!(
                "has {} parameters, expected at least {}",
                self.params.len(),
                i + 1
            ))
        })
    }

    /// A finite number.
    pub fn f64(&self, i: usize) -> MapResult<f64> {
        let v = self
            .get(i)?
            .as_f64()
            .ok_or_else(|| self.err(format!("parameter {} is not a number", i + 1)))?;
        if !v.is_finite() {
            return Err(self.err(format!("parameter {} is not finite", i + 1)));
        }
        Ok(v)
    }

    /// A non-negative integer that fits a count.
    pub fn usize(&self, i: usize) -> MapResult<usize> {
        let v = self
            .get(i)?
            .as_i64()
            .ok_or_else(|| self.err(format!("parameter {} is not an integer", i + 1)))?;
        usize::try_from(v).map_err(|_| self.err(format!("parameter {} is negative", i + 1)))
    }

    /// A reference.
    pub fn r#ref(&self, i: usize) -> MapResult<u64> {
        self.get(i)?
            .as_ref_id()
            .ok_or_else(|| self.err(format!("parameter {} is not a reference", i + 1)))
    }

    /// A reference, or `None` when `$` (or absent).
    pub fn opt_ref(&self, i: usize) -> Option<u64> {
        self.params.get(i).and_then(Param::as_ref_id)
    }

    /// A list.
    pub fn list(&self, i: usize) -> MapResult<&'i [Param<'a>]> {
        self.get(i)?
            .as_list()
            .ok_or_else(|| self.err(format!("parameter {} is not a list", i + 1)))
    }

    /// A list of references (non-references in it are an error).
    pub fn refs(&self, i: usize) -> MapResult<Vec<u64>> {
        self.list(i)?
            .iter()
            .map(|p| {
                p.as_ref_id()
                    .ok_or_else(|| self.err(format!("parameter {} holds a non-reference", i + 1)))
            })
            .collect()
    }

    /// A list of finite numbers.
    pub fn f64s(&self, i: usize) -> MapResult<Vec<f64>> {
        list_f64(self, self.list(i)?, i)
    }

    /// A BOOLEAN / LOGICAL; `.U.` reads as `default`.
    pub fn bool_or(&self, i: usize, default: bool) -> bool {
        self.params
            .get(i)
            .and_then(Param::as_bool)
            .unwrap_or(default)
    }

    /// A string, empty when `$` or absent.
    pub fn str_or_empty(&self, i: usize) -> String {
        self.params
            .get(i)
            .and_then(Param::as_str)
            .unwrap_or("")
            .to_string()
    }

    /// An enumeration value, `None` when absent.
    pub fn enumeration(&self, i: usize) -> Option<&'a str> {
        self.params.get(i).and_then(Param::as_enum)
    }
}

/// Finite numbers from a list parameter.
pub fn list_f64(a: &Attrs<'_, '_>, items: &[Param<'_>], i: usize) -> MapResult<Vec<f64>> {
    items
        .iter()
        .map(|p| match p.as_f64() {
            Some(v) if v.is_finite() => Ok(v),
            _ => Err(a.err(format!(
                "parameter {} holds a non-finite or non-number",
                i + 1
            ))),
        })
        .collect()
}
