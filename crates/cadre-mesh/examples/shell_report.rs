//! Meshes a STEP file and reports, per closed shell, its area, volume and the faces that hold
//! its boundary (open) edges: `cargo run --release -p cadre-mesh --example shell_report --
//! FILE [DEFLECTION_REL]`. For finding which faces leave a solid open.

use std::collections::HashMap;

use cadre_mesh::weld::WeldedMesh;
#[path = "common/mod.rs"]
mod common;

use cadre_mesh::mesh_model;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: shell_report FILE [DEFLECTION_REL]");
        std::process::exit(2);
    };
    let rel: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.0002);
    let model = common::load(path);
    let params = common::relative_params(&model, rel);
    let mesh = mesh_model(&model, &params, None);
    for f in &mesh.failures {
        println!("face #{} failed: {}", f.step_id, f.reason);
    }
    for solid in &model.solids {
        for shell in solid.shells() {
            let w = WeldedMesh::shell(&model, &mesh, shell);
            let c = w.census();
            // Which faces the boundary edges belong to.
            let mut uses: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
            for (i, t) in w.triangles.iter().enumerate() {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    uses.entry((a.min(b), a.max(b))).or_default().push(i);
                }
            }
            let mut open: HashMap<u64, usize> = HashMap::new();
            for tris in uses.values().filter(|t| t.len() == 1) {
                *open.entry(w.triangle_faces[tris[0]]).or_default() += 1;
            }
            let mut open: Vec<_> = open.into_iter().collect();
            open.sort_by_key(|o| std::cmp::Reverse(o.1));
            println!(
                "shell #{}: {} triangles, area {:.3}, volume {:.3}, boundary {} nonmanifold {} misoriented {}; open faces {:?}",
                model.shells[shell.index()].step_id,
                w.triangles.len(),
                w.area(),
                w.signed_volume(),
                c.boundary,
                c.nonmanifold,
                c.misoriented,
                &open[..open.len().min(8)]
            );
        }
    }
}
