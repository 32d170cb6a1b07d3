//! Meshes a STEP file and prints one JSON line per B-Rep face: its STEP id, the mesh area
//! and the area-weighted centroid (model units, in the part's own coordinates):
//! `cargo run --release -p cadre-mesh --example face_areas -- FILE [DEFLECTION_REL]`.
//! Compared with OCCT's per-face figures (scripts/face_areas_occt.py) it finds the faces
//! whose mesh is wrong.

#[path = "common/mod.rs"]
mod common;

use cadre_mesh::mesh_model;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: face_areas FILE [DEFLECTION_REL]");
        std::process::exit(2);
    };
    let rel: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.0002);
    let model = common::load(path);
    let params = common::relative_params(&model, rel);
    let mesh = mesh_model(&model, &params, None);
    for (face, m) in model.faces.iter().zip(&mesh.faces) {
        let (mut area, mut c) = (0.0, cadre_geom::Vec3::ZERO);
        if let Some(m) = m {
            for t in &m.triangles {
                let [a, b, d] = t.map(|i| m.points[i as usize].xyz);
                let w = 0.5 * (b - a).cross(d - a).length();
                area += w;
                c += (a + b + d) * (w / 3.0);
            }
        }
        if area > 0.0 {
            c /= area;
        }
        println!(
            "{{\"id\": {}, \"area\": {area}, \"centroid\": [{}, {}, {}], \"meshed\": {}}}",
            face.step_id,
            c.x,
            c.y,
            c.z,
            m.is_some()
        );
    }
}
