//! Fuzzes the STEP mapper: parse arbitrary bytes, map whatever parses onto a model, then
//! count its entities and compute its bounding box.
//!
//! Beyond the syntax layer this exercises product structure, topology, geometry, units and
//! styles mapping and the model's bounds: no panic, no hang, no unbounded allocation.

#![no_main]

use cadre_step::syntax::StepFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(file) = StepFile::parse(data.to_vec()) else {
        return;
    };
    let model = cadre_step::map_file(&file);
    let _ = model.counts();
    let _ = model.bbox(cadre_geom::Accuracy::default());
});
