//! `cadre mesh`: tessellate a STEP file into a watertight mesh and write glTF, STL or OBJ.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use cadre_mesh::{Deflection, MeshParams, deflection_diagonal, mesh_model, mesh_stats};
use serde_json::json;

use crate::load::load_step;

/// Arguments of `cadre mesh`.
#[derive(clap::Args)]
pub struct MeshArgs {
    /// The STEP file.
    file: PathBuf,
    /// Output file: .glb, .gltf, .stl or .obj (omit with --json to only measure).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Linear deflection in mm (largest distance from the exact surface).
    #[arg(long, conflicts_with = "deflection_rel", allow_negative_numbers = true)]
    deflection: Option<f64>,
    /// Linear deflection relative to the model's bounding-box diagonal (default 0.001).
    #[arg(long, allow_negative_numbers = true)]
    deflection_rel: Option<f64>,
    /// Angular deflection in radians (largest angle between normals of a triangle).
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    angle: f64,
    /// Print the trim loops of the face with this STEP id as JSON ((u, v), key per point) and
    /// stop: for diagnosing a face that does not mesh.
    #[arg(long, value_name = "STEP_ID")]
    dump_trim: Option<u64>,
    /// Print one JSON object with the mesh's figures (triangles, area, volume, boundary and
    /// non-manifold edges, seconds, failed faces) instead of the human summary.
    #[arg(long)]
    json: bool,
}

/// Runs `cadre mesh`.
pub fn run(args: &MeshArgs) -> Result<()> {
    if args.output.is_none() && !args.json && args.dump_trim.is_none() {
        bail!("give an output file with -o (or --json to only measure)");
    }
    let deflection = match (args.deflection, args.deflection_rel) {
        (Some(d), _) => Deflection::Absolute(d),
        (None, Some(r)) => Deflection::Relative(r),
        (None, None) => Deflection::Relative(0.001),
    };
    let bad = |x: f64| !(x.is_finite() && x > 0.0);
    match deflection {
        Deflection::Absolute(x) | Deflection::Relative(x) if bad(x) => {
            bail!("the deflection must be a positive number, got {x}")
        }
        _ => {}
    }
    if bad(args.angle) {
        bail!(
            "the angle must be a positive number of radians, got {}",
            args.angle
        );
    }
    if let Some(out) = &args.output {
        crate::output::check(out, &["glb", "gltf", "stl", "obj"])?;
    }
    let t0 = Instant::now();
    let loaded = load_step(&args.file)?;
    let model = &loaded.model;
    let diagonal = deflection_diagonal(model);
    let params = MeshParams {
        deflection: deflection.resolve(diagonal),
        angle: args.angle,
        ..MeshParams::default()
    };
    if let Some(id) = args.dump_trim {
        return dump_trim(model, id, &params);
    }
    // An export expands the assembly into one node per instance: refused before meshing when
    // that is more than a scene holds (an assembly of 6.2·10⁶ instances took 2.45 GB and was
    // cut silently at 4·10⁶ nodes).
    if args.output.is_some() {
        crate::load::check_scene_nodes(
            model,
            &args.file,
            "export holds (one node each)",
            "nothing was meshed or written",
        )?;
    }
    let bar = crate::progress::bar(model.faces.len() as u64, "meshing faces", !args.json);
    let tick = |n: usize| bar.set_position(n as u64);
    let mesh = mesh_model(model, &params, Some(&tick));
    bar.finish_and_clear();
    let mesh_seconds = t0.elapsed().as_secs_f64();
    let stats = mesh_stats(model, &mesh);
    // An output with nothing in it is not written: the run fails, saying why (after the JSON
    // report, which still describes the file).
    let mut empty = false;
    if let Some(out) = &args.output {
        let scene = cadre_mesh::assemble::build_scene(model, &mesh);
        empty = cadre_render::scene_bounds(&scene).is_none();
        if !empty {
            cadre_mesh::export::write_scene(&scene, out)
                .inspect_err(|_| crate::output::discard(out))
                .with_context(|| format!("writing {}", out.display()))?;
        }
    }
    // Import + tessellation, the figure comparable with OCCT's read + BRepMesh.
    let seconds = mesh_seconds;
    let total_seconds = t0.elapsed().as_secs_f64();
    let report = crate::report::MeshReport::new(model, &mesh);
    let lost = report.warnings(&loaded.file);
    if args.json {
        let mut j = json!({
            "file": args.file.display().to_string(),
            "triangles": stats.triangles,
            "unique_triangles": stats.unique_triangles,
            "area": stats.area,
            "volume": stats.volume,
            "solids": stats.solids,
            "boundary_edges": stats.boundary_edges,
            "nonmanifold_edges": stats.nonmanifold_edges,
            "misoriented_edges": stats.misoriented_edges,
            "open_boundary_edges": stats.open_boundary_edges,
            "faces": model.faces.len(),
            "deflection": params.deflection,
            "angle": params.angle,
            "seconds": seconds,
            "total_seconds": total_seconds,
            "load_seconds": loaded.parse_seconds + loaded.map_seconds,
            "warnings": model.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
            "mesh_warnings": lost,
            "empty": empty,
        });
        for (key, value) in report.json() {
            j[key] = value;
        }
        println!("{j}");
    } else {
        println!(
            "{}: {} triangles ({} stored), area {:.6} mm², volume {:.6} mm³ ({} solids)",
            args.file.display(),
            stats.triangles,
            stats.unique_triangles,
            stats.area,
            stats.volume,
            stats.solids
        );
        println!(
            "deflection {:.4} mm, angle {} rad; boundary edges {}, non-manifold {}, misoriented {}; {:.3} s",
            params.deflection,
            params.angle,
            stats.boundary_edges,
            stats.nonmanifold_edges,
            stats.misoriented_edges,
            total_seconds
        );
        for w in &lost {
            eprintln!("warning: {w}");
        }
        if let Some(out) = &args.output
            && !empty
        {
            println!("wrote {}", out.display());
        }
    }
    if empty {
        bail!(
            "{}: nothing to write (no face, mesh or curve placed; {} warning(s) while reading); \
             no file written",
            args.file.display(),
            model.warnings.len()
        );
    }
    Ok(())
}

/// `--dump-trim`: the face's trim as the triangulator receives it.
fn dump_trim(model: &cadre_brep::Model, step_id: u64, params: &MeshParams) -> Result<()> {
    let Some(index) = model.faces.iter().position(|f| f.step_id == step_id) else {
        bail!("no face #{step_id} in the model");
    };
    let face = cadre_brep::FaceId(index as u32);
    let acc = cadre_geom::Accuracy::default();
    let edges = cadre_mesh::edges::EdgeDiscretisation::new(model, params, acc);
    let tol = cadre_brep::trim::TrimTolerance {
        deflection: params.deflection,
        angle: params.angle,
        accuracy: acc,
        keep_exact: true,
    };
    let trim = cadre_brep::trim::face_trim(model, face, &edges, &tol)
        .map_err(|e| anyhow::anyhow!("face #{step_id}: {e}"))?;
    let surface = cadre_brep::trim::face_surface(model, face);
    let loops: Vec<_> = trim
        .loops
        .iter()
        .map(|l| {
            l.polygon()
                .iter()
                .map(|p| {
                    json!([
                        p.uv.x,
                        p.uv.y,
                        p.key,
                        (surface.eval(p.uv.x, p.uv.y) - p.xyz).length()
                    ])
                })
                .collect::<Vec<_>>()
        })
        .collect();
    // Per loop, each segment's source and the kind of its exact (u, v) curve (null when only
    // the polyline is known).
    let segments: Vec<_> = trim
        .loops
        .iter()
        .map(|l| {
            l.segments
                .iter()
                .map(|s| {
                    let exact = s.exact.as_ref().map(|e| {
                        let kind = format!("{:?}", e.curve);
                        kind.split(|c: char| !c.is_alphanumeric())
                            .next()
                            .unwrap_or_default()
                            .to_string()
                    });
                    json!({"source": format!("{:?}", s.source), "exact": exact})
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let j = json!({
        "face": step_id,
        "surface": surface.type_name(),
        "domain": surface.domain(),
        "periods": cadre_brep::trim::periods(surface),
        "reversed": trim.reversed,
        "notes": trim.notes,
        "loops": loops,
        "segments": segments,
    });
    println!("{j}");
    Ok(())
}
