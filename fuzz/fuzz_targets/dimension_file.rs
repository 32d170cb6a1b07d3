//! Fuzzes the dimension sidecar reader (`cadre_render::dimensions`, `FILE.dimensions.json`
//! beside a model, written by the viewer and read by it and by `cadre render --dimensions`):
//! arbitrary bytes as a dimension file, then every dimension's shape and the overlay drawn
//! from them. Beyond "no panic, no hang, no unbounded allocation", it checks that a
//! malformed file's error names a line, and that every shape's lines and arrowheads are
//! finite (a dimension of non-finite points draws nothing).
//!
//!   cargo +nightly fuzz run dimension_file -- -max_len=4096

#![no_main]

use cadre_render::dimensions::{DimensionFile, overlay, shape};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let file = match DimensionFile::parse(text) {
        Ok(file) => file,
        Err(e) => {
            assert!(e.line() >= 1 || text.trim().is_empty(), "{e}");
            return;
        }
    };
    for d in &file.dimensions {
        let drawn = shape::shape(&d.kind, &d.points);
        for line in &drawn.lines {
            assert!(line.iter().all(|p| p.is_finite()), "{d:?}");
        }
        for arrow in &drawn.arrows {
            assert!(arrow.tip.is_finite() && arrow.length.is_finite(), "{d:?}");
        }
    }
    let _ = overlay(&file.dimensions, 14.0, Some(0));
});
