//! Corpus test: every file of `../shared/corpus/step` loads without panicking, and face,
//! shell and solid counts agree with Open CASCADE's reference figures
//! (`../shared/corpus/reference.jsonl`) for at least 98 % of the files OCCT reads.
//!
//! Bounding boxes are compared with OCCT's tight box (`BRepBndLib::AddOptimal`, recorded in
//! `tests/data/occt_bbox_optimal.jsonl` by `scripts/occt_bbox_optimal.py`): the box in
//! `reference.jsonl` comes from `BRepBndLib::Add`, which bounds B-spline geometry by control
//! poles and is up to tens of percent larger than the geometry. Agreement with that loose box
//! is reported, not asserted. Tessellated-only files, for which OCCT has no tight box, are
//! compared with the reference box.
//!
//! Skips with a message when `../shared/corpus` is absent (a clone without the shared data).

use std::path::{Path, PathBuf};

use cadre_geom::Accuracy;
use cadre_step::syntax::StepFile;

/// Files whose counts differ from OCCT's, each with what we know of the difference. Any other
/// file that differs fails the test; a listed file that starts to match should leave the list.
const KNOWN_COUNT_DIFFERENCES: &[(&str, &str)] = &[
    (
        "bug31292.stp",
        "the nut's EDGE_CURVE #69 references a vertex that does not exist: OCCT drops the \
         whole nut solid (8 instances, 18 solids become 10, checked with OCCT's shape tree); \
         cadre drops that edge with a warning and keeps the nut, as the same assembly reads \
         in as1-oc-214-mat.stp (18 solids in OCCT too)",
    ),
    (
        "trj9_ap209-mp.stp",
        "the file repeats one SHAPE_DEFINITION_REPRESENTATION; OCCT loads the representation \
         twice, stacking identical solids; cadre loads it once",
    ),
    (
        "trj4_s1-ai-214.stp",
        "11 next-assembly usages with placements (relationships written parent-first); OCCT \
         does not read the assembly: it returns the 8 distinct part solids unplaced, at their \
         own coordinates (checked with OCCT's shape tree), so its counts and box differ",
    ),
    (
        "bug24595_281390.stp",
        "the file has 20 ADVANCED_FACEs; OCCT's healing splits cylinder face #73, whose two \
         bounds enclose disjoint regions, into two faces (6579.96 + 16.72 mm2; cadre's one \
         face has both regions, 6602.3 mm2)",
    ),
    (
        "trj7_b1-ec-214.stp",
        "the file has 414 ADVANCED_FACEs; OCCT's healing splits one face with disjoint \
         bounds into two",
    ),
];

/// Files whose OCCT box is left out of the box tally: OCCT returns their parts unplaced (see
/// `KNOWN_COUNT_DIFFERENCES`), so its box is not the assembly's.
const OCCT_BOX_UNPLACED: &[&str] = &["trj4_s1-ai-214.stp"];

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    dir.join("reference.jsonl").exists().then_some(dir)
}

struct Outcome {
    file: String,
    counts_ok: bool,
    bbox_ok: Option<bool>,
    loose_ok: Option<bool>,
    detail: String,
}

/// OCCT's tight boxes by file name.
fn optimal_boxes() -> std::collections::HashMap<String, Vec<f64>> {
    let text = include_str!("data/occt_bbox_optimal.jsonl");
    text.lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter_map(|v| {
            let b: Vec<f64> = v["bbox_optimal"]
                .as_array()?
                .iter()
                .filter_map(|x| x.as_f64())
                .collect();
            Some((v["file"].as_str()?.to_string(), b))
        })
        .collect()
}

/// Largest corner difference between two boxes as a fraction of `reference`'s diagonal.
fn box_error(ours: [f64; 6], reference: &[f64]) -> f64 {
    let r = reference;
    let diag = ((r[3] - r[0]).powi(2) + (r[4] - r[1]).powi(2) + (r[5] - r[2]).powi(2)).sqrt();
    let err = ours
        .iter()
        .zip(r)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    err / diag.max(1e-12)
}

fn check(dir: &Path, reference: &serde_json::Value, tight: Option<&Vec<f64>>) -> Outcome {
    let name = reference["file"].as_str().unwrap_or_default().to_string();
    let path = dir.join("step").join(&name);
    let file = match StepFile::read(&path) {
        Ok(f) => f,
        Err(e) => {
            return Outcome {
                file: name,
                counts_ok: false,
                bbox_ok: None,
                loose_ok: None,
                detail: format!("read error: {e}"),
            };
        }
    };
    let model = cadre_step::map_file(&file);
    let c = model.counts();
    let want = |k: &str| reference[k].as_u64().unwrap_or(0);
    let counts_ok =
        c.faces == want("faces") && c.shells == want("shells") && c.solids == want("solids");
    let mut detail = format!(
        "faces {}/{} shells {}/{} solids {}/{}",
        c.faces,
        want("faces"),
        c.shells,
        want("shells"),
        c.solids,
        want("solids")
    );
    let loose: Option<Vec<f64>> = reference["bbox"].as_array().and_then(|r| {
        let r: Vec<f64> = r.iter().filter_map(|v| v.as_f64()).collect();
        // OCCT reports infinite geometry with ±1e100 boxes: nothing to compare.
        (r.len() == 6 && r.iter().all(|v| v.abs() < 1e99)).then_some(r)
    });
    let mut loose_ok = None;
    let bbox_ok = loose.as_ref().map(|loose| {
        let ours = model.bbox(Accuracy::default());
        if ours.is_empty() {
            detail += " bbox empty";
            return false;
        }
        let loose_err = box_error(ours.to_array(), loose);
        loose_ok = Some(loose_err <= 0.01);
        let target = tight.filter(|t| t.len() == 6).unwrap_or(loose);
        let err = box_error(ours.to_array(), target);
        detail += &format!(
            " bbox err {:.3}% of diag vs OCCT tight box ({:.3}% vs reference.jsonl)",
            100.0 * err,
            100.0 * loose_err
        );
        err <= 0.01
    });
    Outcome {
        file: name,
        counts_ok,
        bbox_ok,
        loose_ok,
        detail,
    }
}

#[test]
fn corpus_matches_occt_reference() {
    let Some(dir) = corpus_dir() else {
        eprintln!("skipping: ../shared/corpus not found (clone without the shared data)");
        return;
    };
    let text = std::fs::read_to_string(dir.join("reference.jsonl")).expect("reference.jsonl");
    let refs: Vec<serde_json::Value> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).expect("reference line is JSON"))
        .collect();
    let tight = optimal_boxes();
    let mut outcomes = Vec::new();
    let mut panics = Vec::new();
    for r in &refs {
        let name = r["file"].as_str().unwrap_or_default().to_string();
        match std::panic::catch_unwind(|| check(&dir, r, tight.get(&name))) {
            Ok(o) => outcomes.push(o),
            Err(_) => panics.push(name),
        }
    }
    let total = outcomes.len();
    let counts_ok = outcomes.iter().filter(|o| o.counts_ok).count();
    // OCCT's box of a file whose assembly it does not read is not the model's box.
    let bbox_cmp: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.bbox_ok.is_some() && !OCCT_BOX_UNPLACED.contains(&o.file.as_str()))
        .collect();
    let bbox_ok = bbox_cmp.iter().filter(|o| o.bbox_ok == Some(true)).count();
    for o in &outcomes {
        if !o.counts_ok {
            eprintln!("COUNTS {}: {}", o.file, o.detail);
        } else if o.bbox_ok == Some(false) {
            eprintln!("BBOX {}: {}", o.file, o.detail);
        }
    }
    let loose_ok = outcomes.iter().filter(|o| o.loose_ok == Some(true)).count();
    eprintln!(
        "corpus: {total} files, counts equal OCCT for {counts_ok} ({:.1} %), bbox within 1 % \
         for {bbox_ok}/{} ({:.1} %; {loose_ok} within 1 % of reference.jsonl's loose box), panics {}",
        100.0 * counts_ok as f64 / total.max(1) as f64,
        bbox_cmp.len(),
        100.0 * bbox_ok as f64 / bbox_cmp.len().max(1) as f64,
        panics.len()
    );
    assert!(panics.is_empty(), "panicked on {panics:?}");
    let unexpected: Vec<&str> = outcomes
        .iter()
        .filter(|o| !o.counts_ok && !KNOWN_COUNT_DIFFERENCES.iter().any(|(f, _)| *f == o.file))
        .map(|o| o.file.as_str())
        .collect();
    assert!(
        unexpected.is_empty(),
        "counts differ from OCCT for files not known to differ: {unexpected:?}"
    );
    let fixed: Vec<&str> = KNOWN_COUNT_DIFFERENCES
        .iter()
        .filter(|(f, _)| outcomes.iter().any(|o| o.file == *f && o.counts_ok))
        .map(|(f, _)| *f)
        .collect();
    assert!(
        fixed.is_empty(),
        "now match OCCT, remove from the known list: {fixed:?}"
    );
    // Boxes: a floor that only rises (the target is 98 %; see BENCHMARKS.md).
    assert!(
        bbox_ok as f64 >= 0.98 * bbox_cmp.len() as f64,
        "bbox within 1 % for only {bbox_ok}/{}",
        bbox_cmp.len()
    );
}
