//! Tests of the whole syntax layer through [`StepFile`]: structure, index, diagnostics.

use std::borrow::Cow;

use super::*;

const HEAD: &str = "ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('test'),'2;1');
FILE_NAME('t.stp','2024-01-01T00:00:00',('me'),('org'),'pre','sys','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));
ENDSEC;
";

/// A file whose DATA section is `data` (HEAD is 6 lines, `DATA;` is line 7, so the first
/// line of `data` is line 8).
fn file(data: &str) -> String {
    format!("{HEAD}DATA;\n{data}ENDSEC;\nEND-ISO-10303-21;\n")
}

fn parse(text: &str) -> StepFile {
    match StepFile::parse(text.as_bytes().to_vec()) {
        Ok(f) => f,
        Err(e) => panic!("parse failed: {e}\n{text}"),
    }
}

/// Asserts exactly one diagnostic mentions `needle`, with this line and id; returns it.
fn diag<'f>(f: &'f StepFile, needle: &str, line: u32, id: Option<u64>) -> &'f Diagnostic {
    let found: Vec<_> = f
        .diagnostics()
        .iter()
        .filter(|d| d.message.contains(needle))
        .collect();
    assert_eq!(
        found.len(),
        1,
        "diagnostics for {needle:?}: {:#?}",
        f.diagnostics()
    );
    let d = found[0];
    assert_eq!((d.line, d.id), (line, id), "{d}");
    d
}

#[test]
fn minimal_file() {
    let f = parse(&file(
        "#1=CARTESIAN_POINT('',(0.,1.,2.));\n#2=VERTEX_POINT('',#1);\n",
    ));
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    assert_eq!(f.len(), 2);
    assert!(!f.is_empty());
    assert_eq!(f.ids().collect::<Vec<_>>(), [1, 2]);
    assert_eq!(f.line(1), Some(8));
    assert_eq!(f.line(2), Some(9));
    assert_eq!(f.line(3), None);
    let i = f.instance(2).unwrap();
    assert_eq!(i.id, 2);
    assert_eq!(i.line, 9);
    assert_eq!(i.keyword(), "VERTEX_POINT");
    assert!(!i.complex);
    assert_eq!(i.records[0].params[1], Param::Ref(1));
    assert_eq!(f.source(2), Some(&b"#2=VERTEX_POINT('',#1)"[..]));
}

#[test]
fn header_fields() {
    let f = parse(&file("#1=A();\n"));
    let h = f.header();
    assert_eq!(h.description, ["test"]);
    assert_eq!(h.implementation_level, "2;1");
    assert_eq!(h.file_name, "t.stp");
    assert_eq!(h.time_stamp, "2024-01-01T00:00:00");
    assert_eq!(h.author, ["me"]);
    assert_eq!(h.organization, ["org"]);
    assert_eq!(h.preprocessor_version, "pre");
    assert_eq!(h.originating_system, "sys");
    assert_eq!(h.authorization, "");
    assert_eq!(h.schemas, ["AUTOMOTIVE_DESIGN"]);
}

#[test]
fn header_with_wrapped_string_comments_and_unescaped_path() {
    // As written by MSC.Patran: a string wrapped over two lines, a Windows path with single
    // backslashes, and `$` for a string.
    let text = "ISO-10303-21;\nHEADER;\n/* exported */ FILE_DESCRIPTION(('a'),\n'2;1');\n\
        FILE_NAME('D:\\TEMP\\tom\\x.stp','Tue Feb 12 18:14:40 2002\n'\n,(''),(''),$,'MSC','');\n\
        FILE_SCHEMA(('CONFIG_CONTROL_DESIGN'));\nENDSEC;\nDATA;\n#1=A();\nENDSEC;\nEND-ISO-10303-21;\n";
    let f = parse(text);
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    let h = f.header();
    assert_eq!(h.file_name, r"D:\TEMP\tom\x.stp");
    assert_eq!(h.time_stamp, "Tue Feb 12 18:14:40 2002");
    assert_eq!(h.preprocessor_version, "");
    assert_eq!(f.line(1), Some(11));
}

#[test]
fn complex_instances_and_keyword_queries() {
    let f = parse(&file(
        "#1=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#2)) \
         REPRESENTATION_CONTEXT('',''));\n#2=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));\n\
         #3=LENGTH_UNIT();\n",
    ));
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    let names: Vec<_> = f
        .keywords(2)
        .unwrap()
        .iter()
        .map(|&k| f.keyword_name(k))
        .collect();
    assert_eq!(names, ["LENGTH_UNIT", "NAMED_UNIT", "SI_UNIT"]);
    assert!(f.has_keyword(2, "SI_UNIT"));
    assert!(f.has_keyword(2, "si_unit"));
    assert!(!f.has_keyword(2, "REPRESENTATION_CONTEXT"));
    assert!(f.has_keyword(3, "LENGTH_UNIT"));
    assert!(!f.has_keyword(3, "NO_SUCH"));
    assert!(!f.has_keyword(99, "LENGTH_UNIT"));
    assert_eq!(f.ids_with_keyword("LENGTH_UNIT"), [2, 3]);
    assert_eq!(f.ids_with_keyword("NO_SUCH"), Vec::<u64>::new());
    let k = f.keyword("SI_UNIT").unwrap();
    assert!(f.has_keyword_id(2, k));
    assert_eq!(f.keywords(3).unwrap().len(), 1);

    let i = f.instance(2).unwrap();
    assert!(i.complex);
    assert_eq!(i.records.len(), 3);
    assert_eq!(
        i.record("SI_UNIT").unwrap().params,
        [Param::Enum("MILLI"), Param::Enum("METRE")]
    );
    assert_eq!(i.record("NAMED_UNIT").unwrap().params, [Param::Derived]);
}

#[test]
fn lower_case_keywords_are_interned_upper_case() {
    let f = parse(&file(
        "#1=cartesian_point('',(0.));\n#2=(a() b(length_measure(1.)));\n",
    ));
    assert!(f.has_keyword(1, "CARTESIAN_POINT"));
    assert_eq!(f.instance(1).unwrap().keyword(), "CARTESIAN_POINT");
    let i = f.instance(2).unwrap();
    let kws: Vec<_> = i.records.iter().map(|r| r.keyword).collect();
    assert_eq!(kws, ["A", "B"]);
    // A typed parameter keyword that is no entity keyword keeps its spelling.
    assert!(matches!(
        i.records[1].params[0],
        Param::Typed {
            keyword: "length_measure",
            ..
        }
    ));
}

#[test]
fn user_defined_keywords() {
    let f = parse(&file("#1=!MY_THING(1);\n"));
    assert!(f.has_keyword(1, "!MY_THING"));
    assert_eq!(f.instance(1).unwrap().keyword(), "!MY_THING");
}

#[test]
fn comments_and_line_breaks_between_tokens() {
    let f = parse(&file(
        "/* leading ; comment */\n#1\n=\n/* between */ A\n(\n1\n,\n/* x */'s;'\n)\n;\n#2=B(); /* trailing */\n",
    ));
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    assert_eq!(f.line(1), Some(9));
    assert_eq!(f.line(2), Some(18));
    assert_eq!(
        f.instance(1).unwrap().records[0].params,
        [Param::Integer(1), Param::String(Cow::Borrowed("s;"))]
    );
}

#[test]
fn semicolons_inside_strings_do_not_split_instances() {
    let f = parse(&file("#1=A('a;b','it''s;');\n#2=A(';');\n"));
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    assert_eq!(f.len(), 2);
    assert_eq!(
        f.instance(1).unwrap().records[0].params[1],
        Param::String(Cow::Owned("it's;".into()))
    );
}

#[test]
fn several_data_sections_and_data_parameters() {
    let text = format!(
        "{HEAD}DATA('first',('AP214'));\n#1=A();\nENDSEC;\nDATA;\n#2=B(#1);\nENDSEC;\nEND-ISO-10303-21;\n"
    );
    let f = parse(&text);
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    assert_eq!(f.ids().collect::<Vec<_>>(), [1, 2]);
    assert_eq!(f.line(2), Some(11));
}

#[test]
fn forward_references_are_fine() {
    let f = parse(&file("#1=A(#5);\n#5=B();\n"));
    assert_eq!(f.instance(1).unwrap().records[0].params, [Param::Ref(5)]);
}

#[test]
fn byte_order_mark_and_leading_comment() {
    let text = format!("\u{feff}/* hi */ {}", file("#1=A();\n"));
    assert_eq!(parse(&text).len(), 1);
}

#[test]
fn non_utf8_strings_decode_lossily() {
    // Windows-1251 bytes as written by a Russian exporter.
    let mut bytes = file("#1=A('X');\n").into_bytes();
    let at = bytes.windows(3).position(|w| w == b"'X'").unwrap() + 1;
    bytes.splice(at..at + 1, b"\xcf\xf0\xe8\xe2\xe5\xf2".iter().copied());
    let f = StepFile::parse(bytes).unwrap();
    let i = f.instance(1).unwrap();
    assert_eq!(
        i.records[0].params[0].as_str().map(|s| s.chars().count()),
        Some(6)
    );
}

#[test]
fn ids_may_be_sparse_and_huge() {
    let f = parse(&file(
        "#18446744073709551615=A();\n#7=B();\n#100000000000=C();\n",
    ));
    assert!(f.diagnostics().is_empty(), "{:?}", f.diagnostics());
    assert_eq!(f.ids().collect::<Vec<_>>(), [u64::MAX, 7, 100_000_000_000]);
    assert!(f.has_keyword(u64::MAX, "A"));
    assert!(f.has_keyword(100_000_000_000, "C"));
    assert_eq!(f.line(7), Some(9));
    assert!(f.instance(8).is_err());
}

// ---------------------------------------------------------------------------------------
// Bad input: one test per kind, each checking that the diagnostic names line and id.
// ---------------------------------------------------------------------------------------

#[test]
fn not_an_exchange_structure() {
    for text in [
        "",
        "hello",
        "\x00\x01",
        "ISO-10303-21 HEADER;",
        "HEADER; DATA; ENDSEC;",
    ] {
        match StepFile::parse(text.as_bytes().to_vec()) {
            Err(ParseError::NotExchangeStructure { line: 1, .. }) => {}
            other => panic!("{text:?}: {other:?}"),
        }
    }
}

#[test]
fn no_data_section() {
    let text = format!("{HEAD}END-ISO-10303-21;\n");
    assert!(matches!(
        StepFile::parse(text.into_bytes()),
        Err(ParseError::NoDataSection { .. })
    ));
}

#[test]
fn truncated_file_keeps_the_rest() {
    let text = format!("{HEAD}DATA;\n#1=A();\n#2=B(1,\n2");
    let f = parse(&text);
    assert_eq!(f.ids().collect::<Vec<_>>(), [1]);
    diag(&f, "not terminated by ';'", 9, Some(2));
    diag(&f, "DATA section not closed by ENDSEC", 10, None);
    diag(&f, "missing END-ISO-10303-21", 10, None);
}

#[test]
fn missing_endsec() {
    let text = format!("{HEAD}DATA;\n#1=A();\nEND-ISO-10303-21;\n");
    let f = parse(&text);
    assert_eq!(f.len(), 1);
    diag(&f, "not closed by ENDSEC", 9, None);
    assert_eq!(f.diagnostics().len(), 1);
}

#[test]
fn missing_end_iso() {
    let text = format!("{HEAD}DATA;\n#1=A();\nENDSEC;\n");
    let f = parse(&text);
    assert_eq!(f.len(), 1);
    diag(&f, "missing END-ISO-10303-21", 10, None);
}

#[test]
fn unknown_keywords_are_fine() {
    let f = parse(&file("#1=NOT_IN_ANY_SCHEMA(1);\n"));
    assert!(f.diagnostics().is_empty());
    assert_eq!(f.instance(1).unwrap().keyword(), "NOT_IN_ANY_SCHEMA");
}

#[test]
fn unbalanced_parentheses() {
    let f = parse(&file("#1=A();\n#2=B((1,\n2);\n#3=C();\n"));
    assert_eq!(f.len(), 3, "indexing only checks boundaries");
    let e = f.instance(2).unwrap_err();
    assert_eq!((e.line, e.id), (10, Some(2)), "{e}");
    assert!(e.message.contains("expected"), "{e}");
    assert!(f.instance(3).is_ok());
    assert_eq!(f.check_all(), [e]);
}

#[test]
fn unterminated_string_resynchronises() {
    let f = parse(&file("#1=A('abc);\n#2=B();\n#3=C('x');\n"));
    diag(&f, "unterminated string", 8, Some(1));
    assert_eq!(f.ids().collect::<Vec<_>>(), [2, 3]);
    assert_eq!(f.line(2), Some(9));
}

#[test]
fn unterminated_string_at_end_of_file() {
    let text = format!("{HEAD}DATA;\n#1=A();\n#2=B('abc);\n");
    let f = parse(&text);
    diag(&f, "unterminated string", 9, Some(2));
    assert_eq!(f.len(), 1);
}

#[test]
fn unterminated_comment() {
    let f = parse(&format!("{HEAD}DATA;\n#1=A();\n#2=B(/* 1);\n#3=C();\n"));
    diag(&f, "unterminated comment", 9, Some(2));
    assert_eq!(f.ids().collect::<Vec<_>>(), [1]);
}

#[test]
fn duplicate_ids_keep_the_first() {
    let f = parse(&file("#1=A();\n#2=B();\n#1=C();\n"));
    let d = diag(&f, "duplicate", 10, Some(1));
    assert!(d.message.contains("line 8"), "{d}");
    assert_eq!(f.ids().collect::<Vec<_>>(), [1, 2]);
    assert!(f.has_keyword(1, "A"));
    assert!(!f.has_keyword(1, "C"));
    assert_eq!(d.to_string(), format!("line 10, #1: {}", d.message));
}

#[test]
fn duplicate_ids_with_sparse_map() {
    let f = parse(&file("#1=A();\n#99999999999=B();\n#99999999999=C();\n"));
    diag(&f, "duplicate", 10, Some(99_999_999_999));
    assert!(f.has_keyword(99_999_999_999, "B"));
    assert_eq!(f.len(), 2);
}

#[test]
fn id_out_of_range() {
    let f = parse(&file("#1=A();\n#99999999999999999999999=B();\n#3=C();\n"));
    let d = diag(&f, "out of range", 9, None);
    assert!(d.message.contains("#99999999999999999999999"), "{d}");
    assert_eq!(f.ids().collect::<Vec<_>>(), [1, 3]);
}

#[test]
fn integer_overflow_in_parameters() {
    let f = parse(&file("#1=A();\n#2=B(\n99999999999999999999);\n"));
    let e = f.instance(2).unwrap_err();
    assert_eq!((e.line, e.id), (10, Some(2)));
    assert!(e.message.contains("integer out of range"), "{e}");
}

#[test]
fn real_overflow_in_parameters() {
    let f = parse(&file("#5=A(1.E999);\n"));
    let e = f.instance(5).unwrap_err();
    assert_eq!((e.line, e.id), (8, Some(5)));
    assert!(e.message.contains("out of range"), "{e}");
}

#[test]
fn deep_nesting() {
    let deep = format!("#4=A({}1{});\n", "(".repeat(200), ")".repeat(200));
    let f = parse(&file(&deep));
    let e = f.instance(4).unwrap_err();
    assert_eq!((e.line, e.id), (8, Some(4)));
    assert!(e.message.contains("nesting"), "{e}");
    // In a complex instance, the index already sees it.
    let deep = format!("#4=(A({}1{}));\n", "(".repeat(200), ")".repeat(200));
    let f = parse(&file(&deep));
    diag(&f, "nesting", 8, Some(4));
    assert!(f.is_empty());
}

#[test]
fn garbage_bytes() {
    let f = parse(&file(
        "#1=A();\n\x01\x02garbage;\n#3=A(\x7f);\n#4=\x00;\n#5=B();\n",
    ));
    diag(&f, "unexpected byte 0x01", 9, None);
    diag(&f, "unexpected byte 0x00", 11, Some(4));
    assert_eq!(f.ids().collect::<Vec<_>>(), [1, 3, 5]);
    let e = f.instance(3).unwrap_err();
    assert_eq!((e.line, e.id), (10, Some(3)));
    assert!(e.message.contains("0x7F"), "{e}");
}

#[test]
fn junk_statement_in_data_section() {
    let f = parse(&file("#1=A();\nB(1);\n#3=C();\n"));
    diag(&f, "expected an instance", 9, None);
    assert_eq!(f.len(), 2);
}

#[test]
fn malformed_heads() {
    let f = parse(&file("#1 A();\n#2=;\n#3=5;\n#4=(1 2);\n#5=A;\n#6=A();\n"));
    diag(&f, "expected '='", 8, Some(1));
    diag(&f, "keyword or '(', found end", 9, Some(2));
    diag(&f, "found integer 5", 10, Some(3));
    diag(&f, "without records", 11, Some(4));
    diag(&f, "expected '(' after A", 12, Some(5));
    assert_eq!(f.ids().collect::<Vec<_>>(), [6]);
}

#[test]
fn missing_header_entities() {
    let text = "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('X'));\nENDSEC;\nDATA;\n#1=A();\nENDSEC;\nEND-ISO-10303-21;\n";
    let f = parse(text);
    diag(&f, "no FILE_DESCRIPTION", 3, None);
    diag(&f, "no FILE_NAME", 3, None);
    assert_eq!(f.header().schemas, ["X"]);
}

#[test]
fn unknown_id_is_an_error() {
    let f = parse(&file("#1=A();\n"));
    let e = f.instance(2).unwrap_err();
    assert_eq!((e.line, e.id), (0, Some(2)));
}

#[test]
fn diagnostic_display() {
    let d = Diagnostic {
        line: 12,
        id: Some(34),
        message: "bad".into(),
    };
    assert_eq!(d.to_string(), "line 12, #34: bad");
    let d = Diagnostic {
        line: 3,
        id: None,
        message: "bad".into(),
    };
    assert_eq!(d.to_string(), "line 3: bad");
}

#[test]
fn diagnostics_are_capped() {
    let junk = "X;\n".repeat(5000);
    let f = parse(&file(&junk));
    assert!(f.diagnostics().len() <= 1001);
    assert!(
        f.diagnostics()
            .last()
            .unwrap()
            .message
            .contains("suppressed")
    );
}

#[test]
fn ed3_sections_are_skipped() {
    let text =
        format!("{HEAD}ANCHOR;\n<a> = #1;\nENDSEC;\nDATA;\n#1=A();\nENDSEC;\nEND-ISO-10303-21;\n");
    let f = parse(&text);
    diag(&f, "ANCHOR section ignored", 7, None);
    assert_eq!(f.len(), 1);
}

/// The parallel index (files over 4 MiB) must agree with a plain sequential reading: ids,
/// keywords and line numbers.
#[test]
fn parallel_index_matches_naive_reading() {
    let mut data = String::new();
    let mut expected = Vec::new();
    let mut line = 8u32;
    let mut id = 1u64;
    while data.len() < 5 << 20 {
        let (text, kw) = match id % 5 {
            0 => (
                format!("#{id}=CARTESIAN_POINT('p;{id}',(1.,2.,3.));\n"),
                "CARTESIAN_POINT",
            ),
            1 => (
                format!("#{id} = DIRECTION('',\n(0.,0.,1.));\n"),
                "DIRECTION",
            ),
            2 => (
                format!("/* c; */#{id}=(NAMED_UNIT(*) SI_UNIT($,.METRE.));\n"),
                "NAMED_UNIT",
            ),
            3 => (
                format!("#{id}=vector('x\n''y''',#{},1.E0);\n", id - 1),
                "VECTOR",
            ),
            _ => (format!("\n\n#{id}=LINE('',#1,#2);\n"), "LINE"),
        };
        let leading = text
            .find('#')
            .map_or(0, |p| text[..p].matches('\n').count());
        expected.push((id, line + leading as u32, kw));
        line += text.matches('\n').count() as u32;
        data.push_str(&text);
        id += 1;
    }
    let f = parse(&file(&data));
    assert!(
        f.diagnostics().is_empty(),
        "{:?}",
        f.diagnostics().iter().take(3).collect::<Vec<_>>()
    );
    assert_eq!(f.len(), expected.len());
    for (id, line, kw) in expected {
        assert_eq!(f.line(id), Some(line), "#{id}");
        assert!(f.has_keyword(id, kw), "#{id} {kw}");
    }
    assert!(f.check_all().is_empty());
    let complex = f.ids().filter(|id| id % 5 == 2).collect::<Vec<_>>();
    assert_eq!(f.ids_with_keyword("SI_UNIT"), complex);
}

#[test]
fn instance_in_header_is_reported() {
    let text = HEAD.replace("ENDSEC;\n", "#9=A();\nENDSEC;\n")
        + "DATA;\n#1=A();\nENDSEC;\nEND-ISO-10303-21;\n";
    let f = parse(&text);
    diag(&f, "instance in the HEADER section", 6, Some(9));
    assert_eq!(f.ids().collect::<Vec<_>>(), [1]);
}
