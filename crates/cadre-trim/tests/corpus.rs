//! Every face of the corpus (`../shared/corpus/step`): its packed trim tree classifies random
//! (u, v) points of its box as the even-odd rule on its trim polygons does (the loops
//! `face_trim` gives, which the tree was fitted to), farther from their boundary than twice
//! the face's (u, v) tolerances (a face smaller than the object-space tolerance, 0.1 mm, is
//! drawn within it, not exactly). Negative control: the polygons of another face agree far less. Skips with a
//! message when the corpus is absent.

mod common;

use std::path::Path;

use cadre_brep::FaceId;
use cadre_brep::trim::{TrimTolerance, face_trim};
use cadre_geom::Accuracy;
use cadre_mesh::MeshParams;
use cadre_mesh::edges::EdgeDiscretisation;
use cadre_trim::{Uv, model_trees};
use common::{even_odd, to_boundary};

const EPS: f64 = 0.1;

#[test]
fn packed_trees_classify_corpus_faces_as_their_trim_polygons() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/step");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("skipping: ../shared/corpus not found (the corpus lives beside the repository)");
        return;
    };
    let mut files: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    let (mut agree, mut total, mut control_agree, mut control_total) = (0u64, 0u64, 0u64, 0u64);
    let mut worst: Vec<(String, u64, u64)> = Vec::new();
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for file in files {
        let Ok(step) = cadre_step::syntax::StepFile::read(&file) else {
            continue;
        };
        let model = cadre_step::map_file(&step);
        let trees = model_trees(&model, EPS);
        // The loops as `model_trees` read them (edges and trims at ε / 2).
        let params = MeshParams {
            deflection: 0.5 * EPS,
            angle: 0.2,
            ..MeshParams::default()
        };
        let edges = EdgeDiscretisation::new(&model, &params, Accuracy::default());
        let tol = TrimTolerance {
            deflection: 0.5 * EPS,
            angle: 0.2,
            accuracy: Accuracy::default(),
            keep_exact: false,
        };
        let polygons: Vec<Option<Vec<Vec<Uv>>>> = (0..model.faces.len())
            .map(|i| {
                face_trim(&model, FaceId(i as u32), &edges, &tol)
                    .ok()
                    .map(|t| {
                        t.loops
                            .iter()
                            .map(|l| l.polygon().iter().map(|p| p.uv).collect())
                            .collect()
                    })
            })
            .collect();
        let (mut file_agree, mut file_total) = (0, 0);
        for (i, index) in trees.face_index.iter().enumerate() {
            let (Some(index), Some(loops)) = (index, &polygons[i]) else {
                continue;
            };
            let (mut lo, mut hi) = (Uv::splat(f64::INFINITY), Uv::splat(f64::NEG_INFINITY));
            for p in loops.iter().flatten() {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
            let t = trees.tolerances[*index as usize];
            let scale = Uv::new(t.u, t.v);
            let other = polygons[(i + 1) % polygons.len()].as_ref();
            for _ in 0..40 {
                let p = lo + Uv::new(random(), random()) * (hi - lo);
                if to_boundary(loops, p, scale) < 2.0 {
                    continue;
                }
                let got = trees.buffers.classify(*index as usize, p);
                file_total += 1;
                file_agree += u64::from(got == even_odd(loops, p));
                if let Some(other) = other.filter(|o| !std::ptr::eq(*o, loops)) {
                    control_total += 1;
                    control_agree += u64::from(got == even_odd(other, p));
                }
            }
        }
        agree += file_agree;
        total += file_total;
        worst.push((
            file.file_name().unwrap().to_string_lossy().to_string(),
            file_total - file_agree,
            file_total,
        ));
    }
    worst.sort_by_key(|w| std::cmp::Reverse(w.1));
    eprintln!(
        "agreement {agree} of {total}; worst files {:?}",
        &worst[..3.min(worst.len())]
    );
    assert!(total > 30_000, "only {total} points checked");
    assert!(
        agree as f64 >= 0.999 * total as f64,
        "the packed trees agree with the trim polygons on {agree} of {total} points; worst {:?}",
        &worst[..3.min(worst.len())]
    );
    // Negative control: another face's polygons.
    assert!(
        (control_agree as f64) < 0.9 * control_total as f64,
        "another face's polygons agree on {control_agree} of {control_total}"
    );
}
