//! `cadre bench`: timings of cadre's own stages over a folder of files, for the comparison
//! scripts in `scripts/` (which time OCCT on the same files in the same run).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::json;

/// Arguments of `cadre bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    what: BenchWhat,
}

#[derive(clap::Subcommand)]
enum BenchWhat {
    /// Import (parse + B-Rep + assembly, no tessellation) every STEP file of a folder; prints
    /// one JSON line per file with the best time over the repeats.
    Import {
        /// Folder of STEP files (or a single file).
        path: PathBuf,
        /// Runs per file; the fastest is reported.
        #[arg(long, default_value_t = 3)]
        repeat: u32,
    },
    /// Frame time of a heavy scene: FILE meshed once (0.001 × diagonal) and placed GRID × GRID
    /// times; prints one JSON object. Each frame uploads the scene, draws and reads the image
    /// back (headless, no supersampling).
    Render {
        /// The STEP file.
        file: PathBuf,
        /// Instances per side of the grid.
        #[arg(long, default_value_t = 10)]
        grid: u32,
        /// Image size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1920x1080", value_parser = crate::commands::render::parse_size)]
        size: (u32, u32),
        /// Frames timed (after one warm-up frame).
        #[arg(long, default_value_t = 5)]
        frames: u32,
    },
}

fn step_files(path: &Path) -> Result<Vec<PathBuf>> {
    if path.is_file() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .with_context(|| format!("listing {}", path.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    Ok(files)
}

/// Runs `cadre bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    match &args.what {
        BenchWhat::Render {
            file,
            grid,
            size,
            frames,
        } => bench_render(file, *grid, *size, *frames),
        BenchWhat::Import { path, repeat } => {
            for file in step_files(path)? {
                let bytes = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
                let mut best = f64::INFINITY;
                let mut faces = 0;
                let mut error = None;
                for _ in 0..(*repeat).max(1) {
                    let t0 = Instant::now();
                    match cadre_step::syntax::StepFile::read(&file) {
                        Ok(f) => {
                            let model = cadre_step::map_file(&f);
                            best = best.min(t0.elapsed().as_secs_f64());
                            faces = model.faces.len();
                        }
                        Err(e) => {
                            error = Some(e.to_string());
                            break;
                        }
                    }
                }
                let name = file.file_name().map(|n| n.to_string_lossy().to_string());
                let line = match error {
                    Some(e) => json!({"file": name, "bytes": bytes, "error": e}),
                    None => json!({"file": name, "bytes": bytes, "seconds": best, "faces": faces}),
                };
                println!("{line}");
            }
            Ok(())
        }
    }
}

/// `cadre bench render`: see [`BenchWhat::Render`].
fn bench_render(file: &Path, grid: u32, (width, height): (u32, u32), frames: u32) -> Result<()> {
    use cadre_mesh::export::SceneNode;
    use cadre_mesh::{Deflection, MeshParams, deflection_diagonal, mesh_model};
    use cadre_render::{Camera, FrameOptions, Gpu, Renderer, ViewPreset, scene_bounds};
    use glam::{DAffine3, DVec3};

    let loaded = crate::load::load_step(file)?;
    let model = &loaded.model;
    let params = MeshParams {
        deflection: Deflection::Relative(0.001).resolve(deflection_diagonal(model)),
        ..MeshParams::default()
    };
    let mesh = mesh_model(model, &params, None);
    let mut scene = cadre_mesh::assemble::build_scene(model, &mesh);
    let (lo, hi) = scene_bounds(&scene).context("the model has no geometry")?;
    let step = (hi - lo).max(DVec3::splat(1e-6)) * 1.2;
    let roots = std::mem::take(&mut scene.roots);
    for i in 0..grid.max(1) {
        for j in 0..grid.max(1) {
            scene.roots.push(scene.nodes.len());
            scene.nodes.push(SceneNode {
                name: format!("grid {i} {j}"),
                transform: DAffine3::from_translation(DVec3::new(
                    f64::from(i) * step.x,
                    f64::from(j) * step.y,
                    0.0,
                )),
                mesh: None,
                children: roots.clone(),
            });
        }
    }
    let (lo, hi) = scene_bounds(&scene).context("the grid has no geometry")?;
    let camera = Camera::fit(
        lo,
        hi,
        ViewPreset::Iso,
        false,
        f64::from(width) / f64::from(height),
    );
    let gpu = Gpu::headless()?;
    let renderer = Renderer::new(&gpu)?;
    let options = FrameOptions {
        width,
        height,
        supersample: 1,
        background: [1.0; 4],
        ..FrameOptions::default()
    };
    renderer.render(&gpu, &scene, &camera, &options)?;
    let mut ms: Vec<f64> = Vec::new();
    for _ in 0..frames.max(1) {
        let t0 = Instant::now();
        renderer.render(&gpu, &scene, &camera, &options)?;
        ms.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    let mut sorted = ms.clone();
    sorted.sort_by(f64::total_cmp);
    println!(
        "{}",
        json!({
            "file": file.display().to_string(),
            "adapter": gpu.info.name,
            "backend": format!("{:?}", gpu.info.backend),
            "instances": scene.instances().count(),
            "triangles": scene.instance_triangle_count(),
            "width": width,
            "height": height,
            "frame_ms": ms,
            "median_ms": sorted[sorted.len() / 2],
        })
    );
    Ok(())
}
