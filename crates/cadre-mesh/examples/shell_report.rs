//! Meshes a STEP file and reports, per closed shell, its area and volume, and for those not
//! watertight the faces that hold their boundary (open) edges: `cargo run --release -p
//! cadre-mesh --example shell_report -- FILE [DEFLECTION_REL]`. For finding which faces leave
//! a solid open (the same figures as `cadre mesh --json`'s `open_shells`).

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
        }
    }
    for d in shell_defects(&model, &mesh) {
        println!("{}; open edges per face {:?}", d.describe(), d.open_faces);
    }
}
