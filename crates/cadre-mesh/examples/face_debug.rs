//! Meshes one face of a STEP file and prints its figures: `cargo run --release -p cadre-mesh
//! --example face_debug -- FILE STEP_ID [DEFLECTION [ANGLE]]`. For diagnosing faces that mesh badly.

#[path = "common/mod.rs"]
mod common;

use cadre_brep::FaceId;
use cadre_brep::trim::TrimTolerance;
use cadre_geom::Accuracy;
use cadre_mesh::edges::EdgeDiscretisation;
use cadre_mesh::{MeshParams, mesh_face};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(path), Some(id)) = (args.get(1), args.get(2).and_then(|s| s.parse::<u64>().ok()))
    else {
        eprintln!("usage: face_debug FILE STEP_ID [DEFLECTION [ANGLE]]");
        std::process::exit(2);
    };
    let deflection = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.1);
    let model = common::load(path);
    let Some(index) = model.faces.iter().position(|f| f.step_id == id) else {
        eprintln!("no face #{id}");
        std::process::exit(1);
    };
    let mut params = MeshParams {
        deflection,
        ..MeshParams::default()
    };
    if let Some(angle) = args.get(4).and_then(|s| s.parse().ok()) {
        params.angle = angle;
    }
    let acc = Accuracy::default();
    let edges = EdgeDiscretisation::new(&model, &params, acc);
    let tol = TrimTolerance {
        deflection,
        angle: params.angle,
        accuracy: acc,
        keep_exact: false,
    };
    let started = std::time::Instant::now();
    match mesh_face(&model, FaceId(index as u32), &edges, &tol, &params) {
        Ok(m) => {
            let area: f64 = m
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| m.points[i as usize].xyz);
                    0.5 * (b - a).cross(c - a).length()
                })
                .sum();
            let folded = m
                .triangles
                .iter()
                .filter(|t| {
                    let [a, b, c] = t.map(|i| m.points[i as usize]);
                    let nt = (b.xyz - a.xyz).cross(c.xyz - a.xyz);
                    nt.dot(a.normal + b.normal + c.normal) < 0.0
                })
                .count();
            let (mut lo, mut hi) = (
                cadre_geom::Vec2::splat(f64::INFINITY),
                cadre_geom::Vec2::splat(f64::NEG_INFINITY),
            );
            for p in &m.points {
                lo = lo.min(p.uv);
                hi = hi.max(p.uv);
            }
            let surface = &model.surfaces[model.faces[index].surface.index()];
            let worst = m
                .points
                .iter()
                .map(|p| {
                    (
                        (surface.eval(p.uv.x, p.uv.y) - p.xyz).length(),
                        p.key.is_some(),
                        p.uv,
                    )
                })
                .max_by(|a, b| a.0.total_cmp(&b.0));
            let mut big: Vec<(f64, [u32; 3])> = m
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| m.points[i as usize].xyz);
                    (0.5 * (b - a).cross(c - a).length(), *t)
                })
                .collect();
            big.sort_by(|a, b| b.0.total_cmp(&a.0));
            for (area, t) in big.iter().take(3) {
                let uv = t.map(|i| m.points[i as usize].uv);
                let key = t.map(|i| m.points[i as usize].key.is_some());
                println!("big triangle {area:.3}: uv {uv:?} boundary {key:?}");
            }
            println!("largest |S(u, v) - point| (distance, boundary, uv): {worst:?}");
            println!(
                "triangles facing against their normals: {folded}; (u, v) range {lo:?} .. {hi:?}"
            );
            if let Ok(path) = std::env::var("FACE_DEBUG_POINTS") {
                // (u, v, x, y, z, boundary) per point, for plotting where refinement went.
                let rows: Vec<String> = m
                    .points
                    .iter()
                    .map(|p| {
                        format!(
                            "{} {} {} {} {} {}",
                            p.uv.x,
                            p.uv.y,
                            p.xyz.x,
                            p.xyz.y,
                            p.xyz.z,
                            u8::from(p.key.is_some())
                        )
                    })
                    .collect();
                std::fs::write(path, rows.join("\n")).expect("write FACE_DEBUG_POINTS");
            }
            let dev = cadre_mesh::deviation::sampled_deviation(surface, &m);
            let worst_uv = dev.triangle.map(|t| t.map(|i| m.points[i as usize].uv));
            println!(
                "largest sampled deviation {:.6} (deflection {deflection}) in triangle {worst_uv:?}",
                dev.distance
            );
            let own_uv = dev
                .interpolation_triangle
                .map(|t| t.map(|i| (m.points[i as usize].uv, m.points[i as usize].key.is_some())));
            println!(
                "from the surface points of the corners {:.6} in triangle {own_uv:?}; boundary \
                 points lie up to {:.6} off the surface",
                dev.interpolation, dev.boundary_gap
            );
            println!(
                "face #{id}: {} points, {} triangles, area {area:.4}, truncated {}, {:.3} s",
                m.points.len(),
                m.triangles.len(),
                m.truncated,
                started.elapsed().as_secs_f64()
            );
        }
        Err(e) => println!("face #{id}: {e}"),
    }
}
