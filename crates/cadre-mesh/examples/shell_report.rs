//! Meshes a STEP file and reports, per closed shell, its area and volume, and for those not
//! watertight the faces that hold their boundary (open) edges: `cargo run --release -p
//! cadre-mesh --example shell_report -- FILE [DEFLECTION_REL] [--edges]`. For finding which
//! faces leave a solid open (the same figures as `cadre mesh --json`'s `open_shells`);
//! `--edges` also lists each open edge: its face, its two weld keys and positions.

#[path = "common/mod.rs"]
mod common;

use cadre_mesh::weld::WeldedMesh;
use cadre_mesh::{mesh_model, shell_defects};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: shell_report FILE [DEFLECTION_REL]");
        std::process::exit(2);
    };
    let rel: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.0002);
    let list_edges = args.iter().any(|a| a == "--edges");
    let model = common::load(path);
    let params = common::relative_params(&model, rel);
    let mesh = mesh_model(&model, &params, None);
    for f in &mesh.failures {
        println!("face #{} failed: {}", f.step_id, f.reason);
    }
    for solid in &model.solids {
        for shell in solid.shells() {
            let w = WeldedMesh::shell(&model, &mesh, shell);
            println!(
                "shell #{}: {} triangles, area {:.3}, volume {:.3}",
                model.shells[shell.index()].step_id,
                w.triangles.len(),
                w.area(),
                w.signed_volume(),
            );
            if list_edges {
                print_open_edges(&model, &mesh, shell);
            }
        }
    }
    for d in shell_defects(&model, &mesh) {
        println!("{}; open edges per face {:?}", d.describe(), d.open_faces);
    }
}

/// Prints every edge of the shell's triangles used once: face, weld keys (`-` for a point
/// without one) and positions.
fn print_open_edges(
    model: &cadre_brep::Model,
    mesh: &cadre_mesh::ModelMesh,
    shell: cadre_brep::ShellId,
) {
    use std::collections::HashMap;
    type End = (Option<u64>, [f64; 3]);
    let mut uses: HashMap<(u64, u64), (usize, u64, End, End)> = HashMap::new();
    let mut unkeyed = u64::MAX;
    for &(face, _) in &model.shells[shell.index()].faces {
        let Some(Some(fm)) = mesh.faces.get(face.index()) else {
            continue;
        };
        let ids: Vec<u64> = fm
            .points
            .iter()
            .map(|p| {
                p.key.unwrap_or_else(|| {
                    unkeyed -= 1;
                    unkeyed
                })
            })
            .collect();
        let step = model.faces[face.index()].step_id;
        for t in &fm.triangles {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if ids[a] == ids[b] {
                    continue;
                }
                let end = |i: usize| (fm.points[i].key, fm.points[i].xyz.to_array());
                let e = uses
                    .entry((ids[a].min(ids[b]), ids[a].max(ids[b])))
                    .or_insert((0, step, end(a), end(b)));
                e.0 += 1;
            }
        }
    }
    let mut open: Vec<_> = uses.values().filter(|u| u.0 == 1).collect();
    open.sort_by_key(|u| u.1);
    for (_, face, a, b) in open {
        let key = |k: Option<u64>| k.map_or("-".to_string(), |k| format!("{k:x}"));
        println!(
            "  open edge of face #{face}: {} {:?} -> {} {:?}",
            key(a.0),
            a.1,
            key(b.0),
            b.1
        );
    }
}
