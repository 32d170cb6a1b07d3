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
    /// Trim trees (cadre-trim) of every STEP file of a folder against its static meshes:
    /// prints one JSON line per file with the trees' counts, bytes and build time, the time
    /// and bytes of meshing the same model at the same tolerance and at a tenth of it, and
    /// what the trim back-end adds (faces it draws, the surfaces' bytes).
    Trim {
        /// Folder of STEP files (or a single file).
        path: PathBuf,
        /// Object-space tolerance of the trims, model units (mm).
        #[arg(long, default_value_t = 0.1)]
        tolerance: f64,
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
        /// Display mode (as `cadre render --mode`); shaded-edges is what OCCT's ToPixMap
        /// draws in `scripts/compare_render.py`.
        #[arg(long, default_value = "shaded", value_parser = crate::commands::render::parse_mode)]
        mode: cadre_render::DisplayMode,
        /// How faces are drawn (as `cadre render --method`).
        #[arg(long, default_value = "mesh", value_enum)]
        method: crate::commands::render::Method,
        /// Trimmed edges without their analytic coverage (`cadre render --antialias none`
        /// leaves it out too): what it costs.
        #[arg(long)]
        no_coverage: bool,
        /// The crack pass (as `cadre render --cracks`; `--method trim` only): what it costs
        /// (the GPU time of its stage, `cracks`, after `visibility`) and what it did.
        #[arg(long, default_value = "exact", value_enum)]
        cracks: crate::commands::render::CrackArg,
        /// The crack pass without its silhouette rule (as `cadre render
        /// --no-silhouette-fill`).
        #[arg(long)]
        no_silhouette_fill: bool,
    },
    /// The viewer's frame on the same heavy scene: the scene uploaded once, then each frame
    /// orbits the camera by 2°, draws into a kept viewport (the window's path, no readback)
    /// and waits for the GPU; then picks are timed: a click's (waited for), a hover's ask
    /// (what holds the viewer's frame) and its answer (polled until there).
    /// Prints one JSON object.
    View {
        /// The STEP file.
        file: PathBuf,
        /// Instances per side of the grid.
        #[arg(long, default_value_t = 10)]
        grid: u32,
        /// View size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1920x1080", value_parser = crate::commands::render::parse_size)]
        size: (u32, u32),
        /// Frames timed (after one warm-up frame).
        #[arg(long, default_value_t = 30)]
        frames: u32,
        /// Display mode (as `cadre render --mode`); shaded-edges is the viewer's default,
        /// shaded the same frame without the edges pass.
        #[arg(long, default_value = "shaded-edges", value_parser = crate::commands::render::parse_mode)]
        mode: cadre_render::DisplayMode,
        /// How faces are drawn (as `cadre render --method`).
        #[arg(long, default_value = "mesh", value_enum)]
        method: crate::commands::render::Method,
        /// The trim back-end with a part switched off, to separate its costs: `no-test`
        /// (fragments not trimmed), `least` (one grid cell per span and face),
        /// `vertex-eval` (surfaces evaluated by the vertex shader).
        #[arg(long, default_value = "full", value_enum)]
        trim_variant: TrimVariant,
    },
}

/// `cadre bench view --trim-variant`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum TrimVariant {
    /// As drawn.
    Full,
    /// Fragments not tested against their trees.
    NoTest,
    /// One grid cell per knot span each way.
    Least,
    /// Surfaces evaluated by the vertex shader (six times a cell) instead of once a grid
    /// point in the tessellation pass.
    VertexEval,
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
            mode,
            method,
            no_coverage,
            cracks,
            no_silhouette_fill,
        } => bench_render(
            file,
            (*grid, *method),
            *size,
            *frames,
            (*mode, !*no_coverage, (*cracks, !*no_silhouette_fill)),
        ),
        BenchWhat::View {
            file,
            grid,
            size,
            frames,
            mode,
            method,
            trim_variant,
        } => bench_view(file, (*grid, *method, *trim_variant), *size, *frames, *mode),
        BenchWhat::Trim { path, tolerance } => {
            for file in step_files(path)? {
                println!("{}", bench_trim(&file, *tolerance));
            }
            Ok(())
        }
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

/// One file's line of `cadre bench trim`.
fn bench_trim(file: &Path, tolerance: f64) -> serde_json::Value {
    let name = file.file_name().map(|n| n.to_string_lossy().to_string());
    let model = match cadre_step::syntax::StepFile::read(file) {
        Ok(f) => cadre_step::map_file(&f),
        Err(e) => return json!({"file": name, "error": e.to_string()}),
    };
    let t = Instant::now();
    let trees = cadre_trim::model_trees(&model, tolerance);
    let trim_s = t.elapsed().as_secs_f64();
    let s = &trees.stats;
    // The static meshes the trees replace: at the same tolerance, and at a tenth of it.
    let mesh = |deflection: f64| {
        let params = cadre_mesh::MeshParams {
            deflection,
            ..cadre_mesh::MeshParams::default()
        };
        let t = Instant::now();
        let mesh = cadre_mesh::mesh_model(&model, &params, None);
        let seconds = t.elapsed().as_secs_f64();
        // f32 position and normal a vertex, three u32 indices a triangle.
        let bytes: usize = mesh
            .faces
            .iter()
            .flatten()
            .map(|f| 24 * f.points.len() + 12 * f.triangles.len())
            .sum();
        (seconds, bytes)
    };
    let (mesh_s, mesh_bytes) = mesh(tolerance);
    let (_, fine_bytes) = mesh(0.1 * tolerance);
    // What the trim back-end adds to the trees: a 128-byte record per face it draws and the
    // B-splines' packed knots and control points (built again here: the trees' time above
    // is the figure).
    let scene = cadre_render::TrimScene::build(&model, tolerance);
    // The B-spline faces it draws as the planes, cylinders or spheres they are, and what finding
    // them costs (sampling and fitting each B-spline face; the copy of the model).
    let t = Instant::now();
    let _ = cadre_render::trim_quadrics::closed_form_faces(&model, tolerance);
    let closed_form_s = t.elapsed().as_secs_f64();
    let bspline_faces = model
        .faces
        .iter()
        .filter(|f| {
            matches!(
                model.surfaces[f.surface.index()],
                cadre_geom::Surface::BSpline(_)
            )
        })
        .count();
    let surface_bytes = std::mem::size_of::<cadre_render::layout::TrimSurface>() * scene.drawn()
        + 4 * scene.bspline_data.len();
    let per = |n: usize| {
        if n == 0 {
            0.0
        } else {
            s.bytes as f64 / n as f64
        }
    };
    json!({
        "file": name,
        "faces": s.faces,
        "built": s.built,
        "failed": trees.failures.len(),
        // Nothing dropped silently: each face without a tree, by STEP id, and why.
        "failures": trees.failures,
        "curves": s.curves,
        "pieces": s.pieces,
        "nodes": s.nodes,
        "fallback_faces": s.fallback_faces,
        "fallback_leaves": s.fallback_leaves,
        "capped_leaves": s.capped_leaves,
        "root_only_faces": s.root_only_faces,
        "grid_faces": s.grid_faces,
        "bspline_faces": bspline_faces,
        "closed_form_faces": scene.closed_form_faces.len(),
        "closed_form_seconds": closed_form_s,
        "bytes": s.bytes,
        "bytes_by_buffer": trees
            .buffers
            .bytes_by_buffer()
            .into_iter()
            .map(|(name, bytes)| (name.to_string(), json!(bytes)))
            .collect::<serde_json::Map<_, _>>(),
        "bytes_per_curve": per(s.curves),
        "bytes_per_face": per(s.built),
        "trim_seconds": trim_s,
        "mesh_seconds": mesh_s,
        "mesh_bytes": mesh_bytes,
        "mesh_bytes_tenth": fine_bytes,
        "exact_faces": scene.drawn(),
        "mesh_faces": scene.fallback.len(),
        "surface_bytes": surface_bytes,
    })
}

/// `cadre bench render`: see [`BenchWhat::Render`].
/// FILE meshed at 0.001 × its diagonal and placed `grid` × `grid` times, with its box; with
/// `Method::Trim` or `Method::Raycast`, its faces drawn from their exact surfaces (trims
/// within 10⁻⁵ of the diagonal, `cadre render`'s default). A scene file of quadrics (`.json`)
/// is its objects as they are.
fn grid_scene(
    file: &Path,
    (grid, method): (u32, crate::commands::render::Method),
) -> Result<(cadre_render::RenderScene, glam::DVec3, glam::DVec3)> {
    use cadre_mesh::scene::SceneNode;
    use cadre_mesh::{Deflection, MeshParams, deflection_diagonal, mesh_model};
    use cadre_render::RenderScene;
    use glam::{DAffine3, DVec3};

    if file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        let text =
            std::fs::read_to_string(file).with_context(|| format!("reading {}", file.display()))?;
        let loaded = cadre_render::scene_file::load_scene(&text)
            .with_context(|| format!("reading {}", file.display()))?;
        let scene = RenderScene::default().with_primitives(loaded.primitives);
        let (lo, hi) = scene.bounds().context("the scene has no object")?;
        return Ok((scene, lo, hi));
    }
    let loaded = crate::load::load_step(file)?;
    let model = &loaded.model;
    let params = MeshParams {
        deflection: Deflection::Relative(0.001).resolve(deflection_diagonal(model)),
        ..MeshParams::default()
    };
    let mesh = mesh_model(model, &params, None);
    let mut render_scene = RenderScene::from_model(model, &mesh);
    if method.exact() {
        render_scene = render_scene.with_trims(model, 1e-5 * deflection_diagonal(model));
    }
    let scene = &mut render_scene.assembly;
    let (lo, hi) = cadre_render::scene_bounds(scene).context("the model has no geometry")?;
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
    let (lo, hi) = render_scene.bounds().context("the grid has no geometry")?;
    Ok((render_scene, lo, hi))
}

/// Median of `values` (sorted copy).
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// `cadre bench view`: see [`BenchWhat::View`].
fn bench_view(
    file: &Path,
    (grid, method, variant): (u32, crate::commands::render::Method, TrimVariant),
    (width, height): (u32, u32),
    frames: u32,
    mode: cadre_render::DisplayMode,
) -> Result<()> {
    use cadre_render::{
        Camera, FrameOptions, Gpu, Renderer, ViewPreset, ViewState, Viewport, wgpu,
    };
    use glam::{DQuat, DVec3};

    let (scene, lo, hi) = grid_scene(file, (grid, method))?;
    let aspect = f64::from(width) / f64::from(height);
    let fitted = Camera::fit(lo, hi, ViewPreset::Iso, false, aspect);
    let gpu = Gpu::headless()?;
    let renderer = match variant {
        TrimVariant::Full => method.renderer(&gpu)?,
        TrimVariant::NoTest => Renderer::new(&gpu)?.with_trim_variant(&gpu, (false, 256, true)),
        TrimVariant::Least => Renderer::new(&gpu)?.with_trim_variant(&gpu, (true, 1, true)),
        TrimVariant::VertexEval => Renderer::new(&gpu)?.with_trim_variant(&gpu, (true, 256, false)),
    };
    let t0 = Instant::now();
    let prepared = renderer.prepare(&gpu, &scene);
    let upload_ms = t0.elapsed().as_secs_f64() * 1e3;
    let mut viewport = Viewport::new(&gpu, width, height);
    let target = gpu
        .device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("bench view"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default());
    let options = FrameOptions {
        width,
        height,
        supersample: 1,
        mode,
        ..FrameOptions::default()
    };
    let state = ViewState::default();
    let wait = |gpu: &Gpu| -> Result<()> {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(drop)
            .map_err(|e| anyhow::anyhow!("{e}"))
    };
    let orbit = |k: u32| {
        let q = DQuat::from_axis_angle(DVec3::Z, f64::from(k) * 2f64.to_radians());
        Camera {
            eye: fitted.target + q * (fitted.eye - fitted.target),
            ..fitted
        }
    };
    renderer.draw(
        &gpu,
        &mut viewport,
        &prepared,
        &orbit(0),
        &options,
        &state,
        &target,
    )?;
    wait(&gpu)?;
    let trim_triangles = renderer.last_trim_triangles(&gpu);
    let mut ms = Vec::new();
    for k in 1..=frames.max(1) {
        let t = Instant::now();
        renderer.draw(
            &gpu,
            &mut viewport,
            &prepared,
            &orbit(k),
            &options,
            &state,
            &target,
        )?;
        wait(&gpu)?;
        ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    // A click waits for its pick; a hover asks (the time the viewer's frame is held) and
    // takes the answer on a later frame (the time until it is there, polled).
    let mut pick_ms = Vec::new();
    let mut hover_ask_ms = Vec::new();
    let mut hover_answer_ms = Vec::new();
    for k in 0..10u32 {
        let cursor = (width / 2 + 7 * k, height / 2);
        let t = Instant::now();
        let window = renderer.pick(&gpu, &viewport, &prepared, cursor, 5)?;
        std::hint::black_box(window.nearest(5.0));
        pick_ms.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        let mut pending = renderer.request_pick(&gpu, &viewport, &prepared, cursor, 5)?;
        hover_ask_ms.push(t.elapsed().as_secs_f64() * 1e3);
        let answer = loop {
            if let Some(answer) = pending.poll(&gpu) {
                break answer?;
            }
            std::thread::yield_now();
        };
        hover_answer_ms.push(t.elapsed().as_secs_f64() * 1e3);
        anyhow::ensure!(answer == window, "the hover and the click picks differ");
    }
    println!(
        "{}",
        json!({
            "file": file.display().to_string(),
            "adapter": gpu.info.name,
            "backend": format!("{:?}", gpu.info.backend),
            "instances": prepared.instance_count(),
            "triangles": scene.assembly.instance_triangle_count(),
            "method": format!("{method:?}"),
            "trim_variant": format!("{variant:?}"),
            "trimmed_faces": prepared.trimmed_faces(),
            "trim_triangles": trim_triangles,
            "width": width,
            "height": height,
            "mode": format!("{mode:?}"),
            "upload_ms": upload_ms,
            "frame_ms": ms,
            "median_frame_ms": median(&ms),
            "fps": 1e3 / median(&ms),
            "median_pick_ms": median(&pick_ms),
            "median_hover_ask_ms": median(&hover_ask_ms),
            "median_hover_answer_ms": median(&hover_answer_ms),
        })
    );
    Ok(())
}

/// `cadre bench render`: see [`BenchWhat::Render`].
fn bench_render(
    file: &Path,
    grid: (u32, crate::commands::render::Method),
    (width, height): (u32, u32),
    frames: u32,
    (mode, analytic_coverage, (cracks, silhouette_fill)): (
        cadre_render::DisplayMode,
        bool,
        (crate::commands::render::CrackArg, bool),
    ),
) -> Result<()> {
    use cadre_render::{Camera, FrameOptions, Gpu, ViewPreset, ViewState};

    let (scene, lo, hi) = grid_scene(file, grid)?;
    let camera = Camera::fit(
        lo,
        hi,
        ViewPreset::Iso,
        false,
        f64::from(width) / f64::from(height),
    );
    let gpu = Gpu::headless()?;
    // Each frame's stages timed on the GPU where the adapter writes timestamps (a readback
    // waits for the frame anyway).
    let renderer = grid.1.renderer(&gpu)?.with_pass_timings(&gpu);
    let options = FrameOptions {
        width,
        height,
        supersample: 1,
        background: [1.0; 4],
        mode,
        analytic_coverage,
        cracks: crate::commands::render::CrackArgs {
            cracks,
            inspect_cracks: false,
            gap_tolerance: 0.0,
            crack_depth: 0.0,
            no_silhouette_fill: !silhouette_fill,
        }
        .options(),
        ..FrameOptions::default()
    };
    let trimmed_faces = renderer.prepare(&gpu, &scene).trimmed_faces();
    // An image from the scene, as `cadre render` makes it: upload, frame, readback.
    let render = || {
        let prepared = renderer.prepare(&gpu, &scene);
        renderer.render(&gpu, &prepared, &camera, &options, &ViewState::default())
    };
    render()?;
    let mut ms: Vec<f64> = Vec::new();
    let mut passes: Vec<(&'static str, Vec<f64>)> = Vec::new();
    for _ in 0..frames.max(1) {
        let t0 = Instant::now();
        render()?;
        ms.push(t0.elapsed().as_secs_f64() * 1e3);
        for (stage, t) in renderer.last_pass_timings() {
            match passes.iter_mut().find(|(s, _)| *s == stage) {
                Some((_, times)) => times.push(t),
                None => passes.push((stage, vec![t])),
            }
        }
    }
    let median = |v: &[f64]| {
        let mut sorted = v.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() / 2]
    };
    // GPU milliseconds per stage (median over the frames), empty where the adapter has no
    // timestamps.
    let pass_median: serde_json::Map<String, serde_json::Value> = passes
        .iter()
        .map(|(stage, times)| (stage.to_string(), json!(median(times))))
        .collect();
    println!(
        "{}",
        json!({
            "file": file.display().to_string(),
            "adapter": gpu.info.name,
            "backend": format!("{:?}", gpu.info.backend),
            "instances": scene.assembly.instances().count(),
            "triangles": scene.assembly.instance_triangle_count(),
            "method": format!("{:?}", grid.1),
            "trimmed_faces": trimmed_faces,
            "width": width,
            "height": height,
            "frame_ms": ms,
            "median_ms": median(&ms),
            "pass_median_ms": pass_median,
            "cracks": format!("{:?}", renderer.last_crack_counts(&gpu)),
        })
    );
    Ok(())
}
