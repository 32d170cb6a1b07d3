//! Writing [`Param`]s and [`Record`]s back as Part 21 text.
//!
//! The reader does not need this; it exists so that tests (the round-trip property test in
//! particular) and debugging tools can produce exactly the text the reader must accept. The
//! output is strict Part 21: reals always carry a point, strings are pure ASCII.

use std::fmt::Write as _;

use super::string::encode_string;
use super::value::{Param, Record};

/// Appends a real in a spelling that parses back to the same `f64`: Rust's shortest
/// round-trip digits, with the point Part 21 requires (`1E0` becomes `1.E0`). Non-finite
/// values have no Part 21 spelling and are written as `$`.
pub fn write_real(value: f64, out: &mut String) {
    if !value.is_finite() {
        out.push('$');
        return;
    }
    let text = format!("{value:E}");
    match text.split_once('E') {
        Some((mantissa, exponent)) if !mantissa.contains('.') => {
            let _ = write!(out, "{mantissa}.E{exponent}");
        }
        _ => out.push_str(&text),
    }
}

/// Appends one parameter as Part 21 text.
pub fn write_param(param: &Param<'_>, out: &mut String) {
    match param {
        Param::Unset => out.push('$'),
        Param::Derived => out.push('*'),
        Param::Integer(i) => {
            let _ = write!(out, "{i}");
        }
        Param::Real(r) => write_real(*r, out),
        Param::String(s) => {
            out.push('\'');
            encode_string(s, out);
            out.push('\'');
        }
        Param::Enum(e) => {
            let _ = write!(out, ".{e}.");
        }
        Param::Binary(b) => {
            let _ = write!(out, "\"{b}\"");
        }
        Param::Ref(id) => {
            let _ = write!(out, "#{id}");
        }
        Param::List(items) => write_list(items, out),
        Param::Typed { keyword, value } => {
            out.push_str(keyword);
            out.push('(');
            write_param(value, out);
            out.push(')');
        }
    }
}

fn write_list(items: &[Param<'_>], out: &mut String) {
    out.push('(');
    for (i, item) in items.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        write_param(item, out);
    }
    out.push(')');
}

/// Appends `KEYWORD(params…)`.
pub fn write_record(record: &Record<'_>, out: &mut String) {
    out.push_str(record.keyword);
    write_list(&record.params, out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::lexer::parse_real;
    use std::borrow::Cow;

    #[test]
    fn reals_keep_a_point_and_round_trip() {
        for v in [0.0, -0.0, 1.0, -1.5e-3, 1e300, 5e-324, 123456.789, f64::MAX] {
            let mut s = String::new();
            write_real(v, &mut s);
            assert!(s.contains('.'), "{s}");
            assert_eq!(parse_real(&s), Some(v), "{s}");
        }
        let mut s = String::new();
        write_real(f64::NAN, &mut s);
        assert_eq!(s, "$");
    }

    #[test]
    fn record_text() {
        let record = Record {
            keyword: "A",
            params: vec![
                Param::String(Cow::Borrowed("it's")),
                Param::List(vec![Param::Integer(-1), Param::Ref(3)]),
                Param::Typed {
                    keyword: "LENGTH_MEASURE",
                    value: Box::new(Param::Real(2.0)),
                },
                Param::Enum("T"),
                Param::Binary("0F"),
                Param::Unset,
                Param::Derived,
            ],
        };
        let mut s = String::new();
        write_record(&record, &mut s);
        assert_eq!(s, r#"A('it''s',(-1,#3),LENGTH_MEASURE(2.E0),.T.,"0F",$,*)"#);
    }
}

/// `text` (a whole Part 21 file) with every entity instance name `#n` of its DATA sections
/// moved to `#(n + offset)`: references and definitions alike, not inside strings or
/// comments, not in the HEADER. `None` when an id would pass `u64`, or the text has no DATA
/// section. For merging files into one id space, and for tests of ids past 2³².
pub fn shift_entity_ids(text: &str, offset: u64) -> Option<String> {
    let data = text.find("DATA;")?;
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    out.push_str(&text[..data]);
    let rest = &text[data..];
    let bytes = rest.as_bytes();
    let mut i = 0;
    let mut copied = 0;
    while i < bytes.len() {
        match bytes[i] {
            // A string: to its closing quote ('' is an escaped quote inside it).
            b'\'' => {
                i += 1;
                while i < bytes.len() {
                    if bytes[i] == b'\'' {
                        if bytes.get(i + 1) == Some(&b'\'') {
                            i += 2;
                            continue;
                        }
                        break;
                    }
                    i += 1;
                }
                i += 1;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = rest[i + 2..]
                    .find("*/")
                    .map_or(bytes.len(), |k| i + 2 + k + 2);
            }
            b'#' => {
                let start = i + 1;
                let digits = bytes[start..]
                    .iter()
                    .take_while(|b| b.is_ascii_digit())
                    .count();
                if digits > 0 {
                    let n: u64 = rest[start..start + digits].parse().ok()?;
                    out.push_str(&rest[copied..start]);
                    out.push_str(&n.checked_add(offset)?.to_string());
                    copied = start + digits;
                }
                i = start + digits;
            }
            _ => i += 1,
        }
    }
    out.push_str(&rest[copied..]);
    Some(out)
}

#[cfg(test)]
mod shift_tests {
    use super::shift_entity_ids;

    #[test]
    fn ids_move_but_not_in_strings_comments_or_the_header() {
        let text = "HEADER; FILE_NAME('#1'); ENDSEC;\nDATA;\n#1=A('it''s #2',#2) /* #3 */;\n#2=B(#1);\nENDSEC;";
        let out = shift_entity_ids(text, 1 << 32).unwrap();
        assert_eq!(
            out,
            "HEADER; FILE_NAME('#1'); ENDSEC;\nDATA;\n#4294967297=A('it''s #2',#4294967298) /* #3 */;\n#4294967298=B(#4294967297);\nENDSEC;"
        );
        assert_eq!(shift_entity_ids("DATA;#1=A();", u64::MAX), None);
        assert_eq!(shift_entity_ids("#1=A();", 1), None);
    }
}
