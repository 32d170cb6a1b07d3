//! Property tests: parameters written as Part 21 text parse back to the same values, whole
//! files with arbitrary layout index correctly, and arbitrary bytes never panic.

use std::borrow::Cow;

use cadre_step::syntax::{Param, Record, StepFile, write_param, write_record};
use proptest::prelude::*;

const HEADER: &str = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\n\
    FILE_NAME('','',(''),(''),'','','');\nFILE_SCHEMA(('X'));\nENDSEC;\nDATA;\n";
const FOOTER: &str = "ENDSEC;\nEND-ISO-10303-21;\n";

const KEYWORDS: &[&str] = &[
    "LENGTH_MEASURE",
    "PLANE_ANGLE_MEASURE",
    "A",
    "X_1",
    "POSITIVE_LENGTH_MEASURE",
];
const ENUMS: &[&str] = &["T", "F", "U", "UNSPECIFIED", "MILLI", "A_1"];
const BINARIES: &[&str] = &["0", "1F", "2ABC", "3DEADBEEF0"];

fn leaf() -> impl Strategy<Value = Param<'static>> {
    use proptest::num::f64::{NORMAL, SUBNORMAL, ZERO};
    prop_oneof![
        Just(Param::Unset),
        Just(Param::Derived),
        any::<i64>().prop_map(Param::Integer),
        (NORMAL | SUBNORMAL | ZERO).prop_map(Param::Real),
        any::<String>().prop_map(|s| Param::String(Cow::Owned(s))),
        "[ -~]{0,12}".prop_map(|s| Param::String(Cow::Owned(s))),
        prop::sample::select(ENUMS).prop_map(Param::Enum),
        prop::sample::select(BINARIES).prop_map(Param::Binary),
        any::<u64>().prop_map(Param::Ref),
    ]
}

fn param() -> impl Strategy<Value = Param<'static>> {
    leaf().prop_recursive(6, 64, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Param::List),
            (prop::sample::select(KEYWORDS), inner).prop_map(|(keyword, value)| Param::Typed {
                keyword,
                value: Box::new(value)
            }),
        ]
    })
}

fn parse(text: String) -> StepFile {
    match StepFile::parse(text.into_bytes()) {
        Ok(f) => f,
        Err(e) => panic!("{e}"),
    }
}

/// Blanks, line breaks or comments to put between statements.
fn separator() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("\n".to_owned()),
        Just("\r\n\r\n".to_owned()),
        Just(" /* a ; 'comment' */ ".to_owned()),
        Just("/*\n*/\n".to_owned()),
    ]
}

proptest! {
    #[test]
    fn params_round_trip(params in prop::collection::vec(param(), 0..8)) {
        let record = Record { keyword: "ENTITY", params };
        let mut text = String::from(HEADER);
        text.push_str("#1=");
        write_record(&record, &mut text);
        text.push_str(";\n");
        text.push_str(FOOTER);
        let file = parse(text);
        prop_assert!(file.diagnostics().is_empty(), "{:?}", file.diagnostics());
        let instance = file.instance(1).map_err(|d| TestCaseError::fail(d.to_string()))?;
        prop_assert_eq!(&instance.records, &vec![record]);
    }

    #[test]
    fn complex_instances_round_trip(
        records in prop::collection::vec(
            (prop::sample::select(KEYWORDS), prop::collection::vec(param(), 0..4)),
            1..4,
        )
    ) {
        let records: Vec<Record<'static>> = records
            .into_iter()
            .map(|(keyword, params)| Record { keyword, params })
            .collect();
        let mut text = String::from(HEADER);
        text.push_str("#7=(");
        for r in &records {
            write_record(r, &mut text);
            text.push('\n');
        }
        text.push_str(");\n");
        text.push_str(FOOTER);
        let file = parse(text);
        let instance = file.instance(7).map_err(|d| TestCaseError::fail(d.to_string()))?;
        prop_assert!(instance.complex);
        prop_assert_eq!(&instance.records, &records);
        for r in &records {
            prop_assert!(file.has_keyword(7, r.keyword));
        }
    }

    /// Whole files: arbitrary ids (unique), separators and parameters; the index must report
    /// every instance with the right keyword and line.
    #[test]
    fn files_index_correctly(
        instances in prop::collection::btree_map(
            any::<u64>(),
            (separator(), prop::sample::select(KEYWORDS), prop::collection::vec(param(), 0..3)),
            0..20,
        )
    ) {
        let mut text = String::from(HEADER);
        let mut expected = Vec::new();
        for (id, (sep, keyword, params)) in &instances {
            text.push_str(sep);
            let line = 1 + text.matches('\n').count() as u32;
            let mut p = String::new();
            for (i, param) in params.iter().enumerate() {
                if i > 0 {
                    p.push_str(",\n");
                }
                write_param(param, &mut p);
            }
            text.push_str(&format!("#{id} =\t{keyword}({p});"));
            expected.push((*id, line, *keyword));
        }
        text.push('\n');
        text.push_str(FOOTER);
        let file = parse(text);
        prop_assert!(file.diagnostics().is_empty(), "{:?}", file.diagnostics());
        prop_assert_eq!(file.ids().collect::<Vec<_>>(), instances.keys().copied().collect::<Vec<_>>());
        for (id, line, keyword) in expected {
            prop_assert_eq!(file.line(id), Some(line));
            prop_assert!(file.has_keyword(id, keyword));
        }
        prop_assert!(file.check_all().is_empty());
    }

    /// Arbitrary bytes after a valid prefix: no panic, and every indexed instance either
    /// decodes or reports its own id.
    #[test]
    fn arbitrary_bytes_never_panic(tail in prop::collection::vec(
        prop_oneof![
            4 => prop::sample::select(b"#=();,'\"./*$ \nAB1E+-\\X2".to_vec()),
            1 => any::<u8>(),
        ],
        0..300,
    )) {
        let mut bytes = HEADER.as_bytes().to_vec();
        bytes.extend_from_slice(&tail);
        if let Ok(file) = StepFile::parse(bytes) {
            for id in file.ids() {
                if let Err(d) = file.instance(id) {
                    prop_assert_eq!(d.id, Some(id));
                    prop_assert!(d.line >= 8);
                }
            }
        }
    }
}
