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
