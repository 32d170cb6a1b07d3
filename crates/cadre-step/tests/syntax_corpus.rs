//! Parses every file of the shared STEP corpus and decodes every instance.
//!
//! The corpus lives outside the repository (`../shared/corpus/step` next to the workspace);
//! when it is absent the test says so and passes, so that the crate's tests still run on a
//! bare checkout. `CADRE_STEP_CORPUS` overrides the location.

use std::path::PathBuf;

use cadre_step::syntax::{ParseError, StepFile};

fn corpus_dir() -> PathBuf {
    match std::env::var_os("CADRE_STEP_CORPUS") {
        Some(dir) => PathBuf::from(dir),
        None => PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/corpus/step"
        )),
    }
}

/// An independent count of instance definitions: occurrences of `#digits` followed by
/// optional blanks and `=`, anywhere in the file. Deliberately naive (it would also count
/// such text inside a string or comment), so it shares no code or logic with the indexer.
fn naive_instance_count(bytes: &[u8]) -> usize {
    let mut count = 0;
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'#' {
            let mut j = i + 1;
            while j < bytes.len() && bytes[j].is_ascii_digit() {
                j += 1;
            }
            if j > i + 1 {
                while j < bytes.len() && bytes[j].is_ascii_whitespace() {
                    j += 1;
                }
                if bytes.get(j) == Some(&b'=') {
                    count += 1;
                }
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    count
}

#[test]
fn every_corpus_file_parses_and_decodes() {
    let dir = corpus_dir();
    let Ok(listing) = std::fs::read_dir(&dir) else {
        println!("skipping: ../shared/corpus not found ({})", dir.display());
        return;
    };
    let mut paths: Vec<PathBuf> = listing
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    assert!(
        !paths.is_empty(),
        "corpus directory {} is empty",
        dir.display()
    );

    let mut files = 0;
    let mut instances = 0;
    for path in &paths {
        let name = path.display();
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let expected = naive_instance_count(&bytes);
        let looks_like_step = bytes
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .is_some_and(|p| bytes[p..].starts_with(b"ISO-10303-21"));
        let file = match StepFile::parse(bytes) {
            Ok(f) => f,
            Err(ParseError::NotExchangeStructure { .. }) if !looks_like_step => {
                println!("{name}: not a STEP file, skipped");
                continue;
            }
            Err(e) => panic!("{name}: {e}"),
        };
        for d in file.diagnostics() {
            println!("{name}: {d}");
        }
        let failures = file.check_all();
        assert!(
            failures.is_empty(),
            "{name}: {} instances fail to decode, first: {}",
            failures.len(),
            failures[0]
        );
        for id in file.ids() {
            let instance = file.instance(id).unwrap_or_else(|d| panic!("{name}: {d}"));
            assert_eq!(instance.id, id);
            assert_eq!(Some(instance.line), file.line(id));
            let keywords = file.keywords(id).unwrap_or_default();
            assert_eq!(keywords.len(), instance.records.len(), "{name} #{id}");
            for (k, r) in keywords.iter().zip(&instance.records) {
                assert_eq!(file.keyword_name(*k), r.keyword, "{name} #{id}");
            }
        }
        // Duplicated ids (some exporters write them) are dropped with a diagnostic each.
        let duplicates = file
            .diagnostics()
            .iter()
            .filter(|d| d.message.starts_with("duplicate instance"))
            .count();
        assert_eq!(
            file.len() + duplicates,
            expected,
            "{name}: indexed {} instances + {duplicates} duplicates, naive count {expected}",
            file.len()
        );
        assert!(!file.header().schemas.is_empty(), "{name}: no FILE_SCHEMA");
        files += 1;
        instances += file.len();
    }
    println!("{files} files, {instances} instances");
}
