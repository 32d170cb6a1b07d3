//! Fuzzes the STEP syntax layer: parse arbitrary bytes, then decode every instance.
//!
//! Beyond "no panic, no hang, no unbounded allocation", it checks the index's invariants:
//! every listed id has a line and keywords, and a failed decode names its own id.

#![no_main]

use cadre_step::syntax::StepFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(file) = StepFile::parse(data.to_vec()) else {
        return;
    };
    let _ = file.header();
    for d in file.diagnostics() {
        let _ = d.to_string();
    }
    for id in file.ids() {
        assert!(file.line(id).is_some_and(|l| l >= 1));
        let keywords = file.keywords(id).unwrap_or_default();
        assert!(!keywords.is_empty());
        match file.instance(id) {
            Ok(instance) => {
                assert_eq!(instance.id, id);
                assert_eq!(instance.records.len(), keywords.len());
            }
            Err(d) => assert_eq!(d.id, Some(id)),
        }
    }
});
