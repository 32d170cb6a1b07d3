//! Exactness of `--method trim` on real STEP files: `cadre verify` renders each file's four
//! views at several zooms on the software GPU and compares the face-id image with the CPU
//! ray caster of the exact B-Rep; away from 0.5 px of a true boundary every pixel must agree.
//! The files are corpus files of every kind the trim path draws (planes, cylinders, cones,
//! spheres, tori, B-spline faces, assemblies) that run in seconds at a small image size; the
//! whole corpus is `scripts/verify_corpus.py` (BENCHMARKS.md). Skipped, saying so, where
//! `../shared/corpus` is absent.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The image size: small, so the software GPU and the ray caster take seconds.
const SIZE: &str = "64x48";

/// Files checked at every zoom of [`ZOOMS`].
const FILES: &[&str] = &[
    "OCC22459-TEST2.stp",
    "OCC26308-Face.stp",
    "as1-oc-214-mat.stp",
    "brep_wv1.stp",
    "bug24746_ENI.stp",
    "bug25013_25013face.stp",
    "bug25045_ick_0433.stp",
    "bug25167.stp",
    "bug25415_part_of_hdrv8w64p254_4x2_1016x502h838p.stp",
    "bug28345_30338.stp",
    "PRO10363.stp",
    // Degree-11 B-spline faces (culled by a zero bounding sphere until 2026-12-06).
    "trj7_b1-ec-214.stp",
    // Surfaces of revolution and extrusion (B-spline, rational B-spline, ellipse profiles).
    "trj3_s1-ec-214.stp",
    "trj4_s1-tu-214.stp",
    "trj5_k1-md-203.stp",
];

const ZOOMS: &str = "1,10,100,1000";

fn corpus() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/step");
    dir.is_dir().then_some(dir)
}

/// `cadre verify FILE --json` with `method`, its JSON result.
fn verify(file: &Path, method: &str, zooms: &str) -> serde_json::Value {
    let out = Command::new(env!("CARGO_BIN_EXE_cadre"))
        .arg("verify")
        .arg(file)
        .args([
            "--json", "--method", method, "--zoom", zooms, "--size", SIZE,
        ])
        .output()
        .expect("cadre runs");
    assert!(
        out.status.success(),
        "{}: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().expect("a JSON line");
    serde_json::from_str(last).expect("JSON")
}

/// The views of a `cadre verify` result where some pixel disagrees away from boundaries,
/// as `file view ×zoom: share`.
fn disagreeing(file: &str, result: &serde_json::Value) -> Vec<String> {
    result["views"]
        .as_array()
        .expect("views")
        .iter()
        .filter(|v| v["disagree_share"].as_f64().expect("share") > 0.0)
        .map(|v| {
            format!(
                "{file} {} ×{}: {:.3} % of pixels, silhouette {} px",
                v["view"],
                v["zoom"],
                100.0 * v["disagree_share"].as_f64().unwrap_or(0.0),
                v["silhouette_px"]
            )
        })
        .collect()
}

#[test]
fn trimmed_faces_of_corpus_files_agree_with_the_ray_caster() {
    let Some(dir) = corpus() else {
        eprintln!("skipping: ../shared/corpus not found (the corpus exactness test needs it)");
        return;
    };
    let mut failures = Vec::new();
    let mut views = 0;
    for name in FILES {
        let result = verify(&dir.join(name), "trim", ZOOMS);
        // Every face drawn by the trim path and cast by the ray caster: nothing unverified.
        assert_eq!(result["fallback_faces"], serde_json::json!([]), "{name}");
        assert_eq!(result["uncast_faces"], serde_json::json!([]), "{name}");
        views += result["views"].as_array().map_or(0, Vec::len);
        failures.extend(disagreeing(name, &result));
    }
    assert_eq!(views, FILES.len() * 4 * ZOOMS.split(',').count());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Negative control: the same comparison catches the mesh path's facets on a curved face
/// seen up close.
#[test]
fn the_comparison_catches_a_faceted_mesh_up_close() {
    let Some(dir) = corpus() else {
        eprintln!("skipping: ../shared/corpus not found (the corpus exactness test needs it)");
        return;
    };
    let result = verify(&dir.join("OCC26308-Face.stp"), "mesh", "100");
    let failures = disagreeing("OCC26308-Face.stp", &result);
    assert!(
        failures.iter().any(|f| f.contains("front")),
        "the mesh's facets went unseen: {failures:?}"
    );
}

/// A tessellated item (AP242) has no exact surface to cast: its pixels are reported as
/// unverified and its id as uncast, never as disagreeing.
#[test]
fn tessellated_items_are_reported_unverified_not_wrong() {
    let Some(dir) = corpus() else {
        eprintln!("skipping: ../shared/corpus not found (the corpus exactness test needs it)");
        return;
    };
    let result = verify(&dir.join("bug33410.step"), "trim", "1");
    assert_ne!(result["uncast_faces"], serde_json::json!([]), "{result}");
    assert!(disagreeing("bug33410.step", &result).is_empty(), "{result}");
    let unverified: f64 = result["views"]
        .as_array()
        .expect("views")
        .iter()
        .map(|v| v["unverified_share"].as_f64().unwrap_or(0.0))
        .sum();
    assert!(unverified > 0.0, "{result}");
}
