//! `cadre render`: STEP file (or folder) to PNG, headless, on the GPU or Mesa's software
//! drivers.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use cadre_mesh::{Deflection, MeshParams, deflection_diagonal, mesh_model};
use cadre_render::{
    Camera, CrackMode, CrackOptions, DisplayMode, FrameOptions, Gpu, RenderScene, Renderer,
    ViewPreset, ViewState,
};
use image::RgbaImage;

use crate::commands::toolpath::{
    ToolpathDrawArgs, is_program, load_program, program_bounds, with_toolpath,
};
use crate::load::load_step;

/// How `cadre render` anti-aliases its images.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Antialias {
    /// Smoothing on a CPU adapter (where supersampling costs four times every pass), 2 × 2
    /// supersampling on a GPU; `--supersample N` alone means supersampling by N.
    Auto,
    /// Supersampling by `--supersample` (2 by default) per side.
    Supersample,
    /// Edge smoothing of a 1× image (FXAA style, after the readback).
    Smooth,
    /// Neither, nor the analytic coverage of trimmed edges (`--method trim` blends their
    /// pixels by their distance to the trim boundary in every other mode).
    None,
}

impl Antialias {
    /// The supersampling factor and whether to smooth, on `gpu`.
    pub fn resolve(self, supersample: Option<u32>, gpu: &Gpu) -> (u32, bool) {
        match (self, supersample) {
            (Antialias::Auto, Some(n)) | (Antialias::Supersample, Some(n)) => (n, false),
            (Antialias::Supersample, None) => (2, false),
            (Antialias::Auto, None) if gpu.is_cpu() => (1, true),
            (Antialias::Auto, None) => (2, false),
            (Antialias::Smooth, n) => (n.unwrap_or(1), true),
            (Antialias::None, _) => (1, false),
        }
    }
}

/// Arguments of `cadre render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// A STEP file, a folder of them (then -o is a folder), a scene file of quadrics cut by
    /// planes (`.json`, docs/scene-format.md), or a CAM program (G-code: `.ngc`, `.nc`,
    /// `.gcode`, `.tap`, …) drawn alone.
    input: PathBuf,
    /// Output PNG file, or folder for a folder input.
    #[arg(short, long)]
    output: PathBuf,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x600", value_parser = parse_size, allow_hyphen_values = true)]
    size: (u32, u32),
    /// View: iso, front, back, top, bottom, left or right.
    #[arg(long, default_value = "iso", value_parser = parse_view)]
    view: ViewPreset,
    /// Display mode: shaded, shaded-edges, wireframe, hidden-line or xray.
    #[arg(long, default_value = "shaded", value_parser = parse_mode)]
    mode: DisplayMode,
    /// Edge width in pixels (modes with edges).
    #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
    edge_width: f32,
    /// Orthographic projection (default perspective).
    #[arg(long)]
    ortho: bool,
    /// Background: a name (white, black, grey, transparent) or #rrggbb.
    #[arg(long, default_value = "white", value_parser = parse_colour)]
    background: [f32; 4],
    /// Anti-aliasing: auto (smoothing on a CPU adapter, supersampling on a GPU), supersample
    /// (`--supersample` samples per side), smooth (edge smoothing of a 1× image) or none.
    #[arg(long, default_value = "auto", value_enum)]
    antialias: Antialias,
    /// Supersampling per side (1 to 4; 2 = four samples per pixel); given alone, it asks for
    /// supersampling whatever the adapter.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4))]
    supersample: Option<u32>,
    /// Tessellation deflection relative to the model's bounding-box diagonal.
    #[arg(long, default_value_t = 0.0005, allow_negative_numbers = true)]
    deflection_rel: f64,
    /// How faces are drawn: `mesh` (the static tessellation) or `trim` (from their exact
    /// surfaces, tessellated on the GPU each frame and trimmed per pixel; faces it cannot draw
    /// keep their mesh, and are counted).
    #[arg(long, default_value = "mesh", value_enum)]
    method: Method,
    /// Tolerance of the trims of `--method trim`, relative to the bounding-box diagonal.
    #[arg(long, default_value_t = 1e-5)]
    trim_tolerance_rel: f64,
    /// Magnification about the model point seen at the image's centre (or nearest it): 10
    /// shows a tenth of the fitted view.
    #[arg(long, default_value_t = 1.0)]
    zoom: f64,
    /// The camera: EYE,TARGET,UP[,FOV] as 9 or 10 comma-separated numbers (model units;
    /// FOV in degrees, 30 by default), instead of `--view`.
    #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
    camera: Option<CameraArg>,
    /// How the cracks between faces of `--method trim` are closed.
    #[command(flatten)]
    cracks: CrackArgs,
    /// The key light (the first) casts shadows, from a shadow map every back-end writes
    /// (scene files may ask for them with `"shadows": true`).
    #[arg(long)]
    shadows: bool,
    /// With a folder: also write every image into one contact sheet (a grid of tiles, row by
    /// row in file-name order; SHEET.txt lists which file each tile is).
    #[arg(long, value_name = "SHEET.png")]
    sheet: Option<PathBuf>,
    /// A toolpath drawn over the model.
    #[command(flatten)]
    toolpath: ToolpathDrawArgs,
    /// A vertical gradient behind the model: TOP,BOTTOM colours (names or #rrggbb), or
    /// `cad` for the usual grey-blue one.
    #[arg(long, value_name = "TOP,BOTTOM", value_parser = parse_gradient)]
    background_gradient: Option<[[f32; 4]; 2]>,
    /// An image (PNG) stretched behind the model.
    #[arg(long, value_name = "IMAGE.png")]
    background_image: Option<PathBuf>,
    /// A ground grid under the model (its spacing follows the zoom unless --grid-spacing).
    #[arg(long)]
    grid: bool,
    /// The ground grid's finest spacing, model units (implies --grid).
    #[arg(long, value_name = "MM")]
    grid_spacing: Option<f64>,
    /// Part names as leader labels (each placed part's name in a box, a leader line from
    /// its surface).
    #[arg(long)]
    labels: bool,
    /// Cap height of the labels' text, pixels.
    #[arg(long, default_value_t = 11.0, value_name = "PX")]
    label_size: f32,
    /// Draw the file's PMI annotations (AP242 graphic PMI: tessellated and polyline
    /// annotations, filled areas, texts) over the model.
    #[arg(long)]
    pmi: bool,
    /// Render a saved view of the file (AP242 camera models; `cadre info --json` lists
    /// them under "pmi"): its direction, up and projection, fitted to the part and the
    /// view's annotations, which are drawn (implies --pmi for that view's annotations).
    #[arg(long, value_name = "NAME", conflicts_with_all = ["camera", "zoom"])]
    saved_view: Option<String>,
    /// Draw the dimensions the viewer kept beside the file (`FILE.dimensions.json`: each
    /// measurement's line, arrowheads and value).
    #[arg(long)]
    dimensions: bool,
}

fn parse_gradient(s: &str) -> Result<[[f32; 4]; 2], String> {
    if s.eq_ignore_ascii_case("cad") {
        return match cadre_render::Background::cad_gradient() {
            cadre_render::Background::Gradient { top, bottom } => Ok([top, bottom]),
            _ => Err("no CAD gradient".into()),
        };
    }
    let (top, bottom) = s
        .split_once(',')
        .ok_or_else(|| format!("{s:?}: TOP,BOTTOM expected (two colours) or cad"))?;
    Ok([parse_colour(top.trim())?, parse_colour(bottom.trim())?])
}

/// The options' background and ground grid.
fn backdrop(
    args: &RenderArgs,
) -> Result<(cadre_render::Background, Option<cadre_render::GroundGrid>)> {
    let background = match (&args.background_image, args.background_gradient) {
        (Some(path), _) => {
            let image = image::open(path)
                .with_context(|| format!("reading the background image {}", path.display()))?
                .to_rgba8();
            cadre_render::Background::Image(std::sync::Arc::new(image))
        }
        (None, Some([top, bottom])) => cadre_render::Background::Gradient { top, bottom },
        (None, None) => cadre_render::Background::Solid,
    };
    if let Some(s) = args.grid_spacing
        && !(s.is_finite() && s > 0.0)
    {
        bail!("--grid-spacing must be a positive length, got {s}");
    }
    let grid = (args.grid || args.grid_spacing.is_some()).then(|| cadre_render::GroundGrid {
        spacing: args.grid_spacing,
        ..cadre_render::GroundGrid::default()
    });
    Ok((background, grid))
}

/// How `cadre render` draws faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// The static tessellation (every viewer's way).
    Mesh,
    /// The exact faces: surfaces tessellated on the GPU to the screen, trimmed per pixel.
    Trim,
    /// The exact faces, the analytic ones (planes, cylinders, cones, spheres, ring tori) ray
    /// cast per pixel against their support surface and trimmed at the hit, the others as
    /// `trim`.
    Raycast,
}

impl Method {
    /// Whether faces are drawn from their exact surfaces (`trim` or `raycast`).
    pub fn exact(self) -> bool {
        self != Method::Mesh
    }

    /// The renderer that draws with this method on `gpu`.
    pub fn renderer(self, gpu: &Gpu) -> Result<Renderer> {
        let renderer = Renderer::new(gpu)?;
        Ok(if self == Method::Raycast {
            renderer.with_ray_cast_faces(gpu, true)
        } else {
            renderer
        })
    }
}

/// The crack pass's options (`cadre render`, `cadre verify`).
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct CrackArgs {
    /// How the cracks between faces drawn by `--method trim` (each tessellated to its own
    /// screen-space error) are closed: `exact` (the exact surface seen at each crack pixel,
    /// trimmed exactly), `fast` (the face most neighbours show) or `off`.
    #[arg(long, default_value = "exact", value_enum)]
    pub cracks: CrackArg,
    /// Inspection view: filled cracks painted magenta, closed gaps orange.
    #[arg(long)]
    pub inspect_cracks: bool,
    /// Close real gaps in the model (faces that do not meet) narrower than this, in model
    /// units (mm); 0 leaves them open. With `--inspect-cracks` they are painted orange.
    #[arg(long, default_value_t = 0.0)]
    pub gap_tolerance: f64,
    /// d_min of the crack detection, model units: how much nearer than a pixel both
    /// neighbours of a pair must be; 0 takes 10⁻³ of the model's diagonal.
    #[arg(long, default_value_t = 0.0)]
    pub crack_depth: f64,
    /// The exact fill leaves the pixels next to a nearer face seen at a grazing angle as
    /// drawn (the seed's rule alone). By default it solves them too, from that face's own
    /// (u, v): a face's grid ends short of its true silhouette there.
    #[arg(long)]
    pub no_silhouette_fill: bool,
}

/// `--cracks`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CrackArg {
    /// Cracks left as drawn.
    Off,
    /// Screen-space fill (the face most neighbours show).
    Fast,
    /// Object-space fill (the exact surface seen there).
    Exact,
}

impl CrackArgs {
    /// The renderer's crack options.
    pub fn options(&self) -> CrackOptions {
        CrackOptions {
            mode: match self.cracks {
                CrackArg::Off => CrackMode::Off,
                CrackArg::Fast => CrackMode::Fast,
                CrackArg::Exact => CrackMode::Exact,
            },
            highlight: self.inspect_cracks,
            min_depth: self.crack_depth.max(0.0),
            gap_tolerance: self.gap_tolerance.max(0.0),
            silhouettes: !self.no_silhouette_fill,
        }
    }
}

/// `--camera`: eye, target, up and the vertical field of view in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraArg {
    eye: glam::DVec3,
    target: glam::DVec3,
    up: glam::DVec3,
    fov_y: f64,
}

/// Parses EYE,TARGET,UP[,FOV].
pub(crate) fn parse_camera(s: &str) -> Result<CameraArg, String> {
    let numbers: Vec<f64> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("expected a number, got {t:?}"))
        })
        .collect::<Result<_, _>>()?;
    if numbers.len() != 9 && numbers.len() != 10 {
        return Err(format!(
            "expected EYE,TARGET,UP[,FOV]: 9 or 10 numbers, got {}",
            numbers.len()
        ));
    }
    let v = |i: usize| glam::DVec3::new(numbers[i], numbers[i + 1], numbers[i + 2]);
    let (eye, target, up) = (v(0), v(3), v(6));
    let fov = numbers.get(9).copied().unwrap_or(30.0);
    if (target - eye).length() <= 0.0 || up.cross(target - eye).length() <= 0.0 {
        return Err("the eye must differ from the target, and up from the view direction".into());
    }
    if !(0.01..179.0).contains(&fov) {
        return Err(format!("field of view {fov}° out of (0.01, 179)"));
    }
    Ok(CameraArg {
        eye,
        target,
        up,
        fov_y: fov.to_radians(),
    })
}

/// Parses WIDTHxHEIGHT.
pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {s:?}"))?;
    let n = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|&v| (1..=16384).contains(&v))
            .ok_or_else(|| format!("expected a size from 1 to 16384, got {t:?}"))
    };
    Ok((n(w)?, n(h)?))
}

pub(crate) fn parse_mode(s: &str) -> Result<DisplayMode, String> {
    DisplayMode::from_name(s).ok_or_else(|| {
        format!("unknown mode {s:?} (shaded, shaded-edges, wireframe, hidden-line, xray)")
    })
}

fn parse_view(s: &str) -> Result<ViewPreset, String> {
    ViewPreset::from_name(s)
        .ok_or_else(|| format!("unknown view {s:?} (iso, front, back, top, bottom, left, right)"))
}

fn parse_colour(s: &str) -> Result<[f32; 4], String> {
    Ok(match s.to_ascii_lowercase().as_str() {
        "white" => [1.0, 1.0, 1.0, 1.0],
        "black" => [0.0, 0.0, 0.0, 1.0],
        "grey" | "gray" => [0.5, 0.5, 0.5, 1.0],
        "transparent" => [1.0, 1.0, 1.0, 0.0],
        hex if hex.len() == 7 && hex.starts_with('#') => {
            let c = |i: usize| {
                u8::from_str_radix(&hex[i..i + 2], 16)
                    .map(|v| f32::from(v) / 255.0)
                    .map_err(|_| format!("bad colour {s:?}"))
            };
            [c(1)?, c(3)?, c(5)?, 1.0]
        }
        _ => {
            return Err(format!(
                "unknown colour {s:?} (white, black, grey, transparent or #rrggbb)"
            ));
        }
    })
}

/// Runs `cadre render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    if !(args.deflection_rel.is_finite() && args.deflection_rel > 0.0) {
        bail!("--deflection-rel must be a positive number");
    }
    if !(args.edge_width.is_finite() && args.edge_width > 0.0) {
        bail!(
            "--edge-width must be a positive number of pixels, got {}",
            args.edge_width
        );
    }
    if !args.input.is_dir() {
        crate::output::check(&args.output, &["png"])?;
    }
    if let Some(sheet) = &args.sheet {
        crate::output::check(sheet, &["png"])?;
    }
    if args.input.is_dir() {
        let (gpu, renderer) = open_gpu(args.method)?;
        return render_folder(&gpu, &renderer, args);
    }
    if is_program(&args.input) {
        let (gpu, renderer) = open_gpu(args.method)?;
        let image = render_program(&gpu, &renderer, args)?;
        save(&image, &args.output)?;
        println!("wrote {} ({})", args.output.display(), gpu.info.name);
        return Ok(());
    }
    if is_scene_file(&args.input) {
        let (gpu, renderer) = open_gpu(args.method)?;
        let image = render_scene_file(&gpu, &renderer, args)?;
        save(&image, &args.output)?;
        println!("wrote {} ({})", args.output.display(), gpu.info.name);
        return Ok(());
    }
    // One file: the device and its pipelines are made while the file loads and meshes, not
    // before (on lavapipe they take about 0.08 s, as long as loading a 6.5 MB file of
    // polyline edges).
    std::thread::scope(|threads| {
        let opening = threads.spawn(|| open_gpu(args.method));
        let meshed = mesh_file(&args.input, args);
        let (gpu, renderer) = opening
            .join()
            .map_err(|_| anyhow::anyhow!("the GPU start-up thread panicked"))??;
        let image = draw_file(&gpu, &renderer, &meshed?, args)?;
        save(&image, &args.output)?;
        println!("wrote {} ({})", args.output.display(), gpu.info.name);
        Ok(())
    })
}

/// The frame options every input shares: size, anti-aliasing, background, backdrop and
/// grid, display mode, edge width, shadows.
fn frame_options(args: &RenderArgs, gpu: &Gpu) -> Result<FrameOptions> {
    let (w, h) = args.size;
    let (supersample, smooth) = args.antialias.resolve(args.supersample, gpu);
    let (background, grid) = backdrop(args)?;
    Ok(FrameOptions {
        width: w,
        height: h,
        supersample,
        smooth,
        background: args.background,
        backdrop: background,
        grid,
        mode: args.mode,
        edge_width: args.edge_width,
        shadows: args.shadows,
        ..FrameOptions::default()
    })
}

/// The camera `--camera` or `--view` asks for, fitted to `lo`–`hi`, before any zoom.
fn fitted_camera(args: &RenderArgs, (lo, hi): (glam::DVec3, glam::DVec3)) -> Camera {
    let (w, h) = args.size;
    match args.camera {
        Some(c) => Camera::looking((c.eye, c.target, c.up), c.fov_y, (lo, hi)),
        None => Camera::fit(lo, hi, args.view, args.ortho, f64::from(w) / f64::from(h)),
    }
}

/// A CAM program drawn alone: its path fitted in the view.
fn render_program(gpu: &Gpu, renderer: &Renderer, args: &RenderArgs) -> Result<RgbaImage> {
    let input = &args.input;
    let program = load_program(input, true)?;
    let Some((lo, hi)) = program_bounds(&program) else {
        bail!("{}: no move to draw; no image written", input.display());
    };
    let fitted = fitted_camera(args, (lo, hi));
    let camera = if args.zoom == 1.0 {
        fitted
    } else {
        fitted.zoomed_at(0.5 * (lo + hi), args.zoom, (lo, hi))
    };
    let toolpath = ToolpathDrawArgs {
        toolpath: Some(input.clone()),
        ..args.toolpath.clone()
    };
    let (scene, lines) = with_toolpath(
        RenderScene::default(),
        &program,
        &toolpath,
        (&camera, args.size.1),
    )?;
    let options = frame_options(args, gpu)?;
    let t0 = Instant::now();
    let prepared = renderer.prepare(gpu, &scene);
    let image = renderer
        .render(
            gpu,
            &prepared,
            &camera,
            &options,
            &ViewState {
                lines,
                ..ViewState::default()
            },
        )
        .with_context(|| format!("{}: nothing was drawn", input.display()))?;
    eprintln!(
        "{}: {} move(s), {} segment(s) drawn in {:.3} s",
        input.display(),
        program.moves.len(),
        scene.lines.segment_count(),
        t0.elapsed().as_secs_f64()
    );
    Ok(image)
}

/// Whether `path` names a scene file of quadric primitives (`.json`, docs/scene-format.md).
fn is_scene_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Renders a scene file of quadric primitives (seed 001): its camera or the fitted view
/// (`--view`, `--ortho`, `--camera`, `--zoom` as for a model), its lights or the CAD rig.
pub(crate) fn render_scene_file(
    gpu: &Gpu,
    renderer: &Renderer,
    args: &RenderArgs,
) -> Result<RgbaImage> {
    let input = &args.input;
    let text =
        std::fs::read_to_string(input).with_context(|| format!("reading {}", input.display()))?;
    let loaded = cadre_render::scene_file::load_scene(&text)
        .with_context(|| format!("reading {}", input.display()))?;
    for w in &loaded.warnings {
        eprintln!("warning: {}: {w}", input.display());
    }
    let objects = loaded.primitives.len();
    let scene = RenderScene::default().with_primitives(loaded.primitives);
    let Some((lo, hi)) = scene.bounds() else {
        bail!(
            "{}: nothing to draw (no object loaded); no image written",
            input.display()
        );
    };
    let (w, h) = args.size;
    let aspect = f64::from(w) / f64::from(h);
    let fitted = match (args.camera, loaded.camera) {
        (Some(c), _) => Camera::looking((c.eye, c.target, c.up), c.fov_y, (lo, hi)),
        (None, Some((eye, target, up, fov))) if !args.ortho => {
            Camera::looking((eye, target, up), fov, (lo, hi))
        }
        _ => Camera::fit(lo, hi, args.view, args.ortho, aspect),
    };
    let camera = if args.zoom == 1.0 {
        fitted
    } else {
        fitted.zoomed_at(0.5 * (lo + hi), args.zoom, (lo, hi))
    };
    let mut options = FrameOptions {
        shadows: args.shadows || loaded.shadows,
        ..frame_options(args, gpu)?
    };
    if !loaded.lights.is_empty() {
        options.lights = loaded.lights;
    }
    let t0 = Instant::now();
    let prepared = renderer.prepare(gpu, &scene);
    let image = renderer
        .render(gpu, &prepared, &camera, &options, &ViewState::default())
        .with_context(|| format!("{}: nothing was drawn", input.display()))?;
    eprintln!(
        "{}: {objects} quadric(s) ray cast in {:.3} s",
        input.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(image)
}

/// The headless device and the renderer's pipelines on it.
fn open_gpu(method: Method) -> Result<(Gpu, Renderer)> {
    let gpu = Gpu::headless()?;
    let renderer = method.renderer(&gpu)?;
    Ok((gpu, renderer))
}

fn save(image: &RgbaImage, path: &Path) -> Result<()> {
    image.save(path).map_err(|e| {
        crate::output::discard(path);
        anyhow::Error::new(e).context(format!("writing {}", path.display()))
    })
}

/// Renders every STEP file of a folder into PNGs of the same names, and the contact sheet.
fn render_folder(gpu: &Gpu, renderer: &Renderer, args: &RenderArgs) -> Result<()> {
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("creating {}", args.output.display()))?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args.input)
        .with_context(|| format!("reading {}", args.input.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "stp" | "step"))
        })
        .collect();
    files.sort();
    let bar = crate::progress::bar(files.len() as u64, "rendering", true);
    let mut tiles: Vec<Option<RgbaImage>> = Vec::with_capacity(files.len());
    let mut seconds: Vec<(f64, &Path)> = Vec::new();
    for f in &files {
        let stem = f
            .file_stem()
            .map_or("model".into(), |s| s.to_string_lossy().into_owned());
        let t0 = Instant::now();
        let result = render_file(gpu, renderer, f, args).and_then(|image| {
            save(&image, &args.output.join(format!("{stem}.png"))).map(|()| image)
        });
        match result {
            Ok(image) => {
                seconds.push((t0.elapsed().as_secs_f64(), f));
                tiles.push(args.sheet.is_some().then_some(image));
            }
            Err(e) => {
                bar.suspend(|| eprintln!("error: {}: {e:#}", f.display()));
                tiles.push(None);
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let done = seconds.len();
    seconds.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = seconds.iter().map(|s| s.0).sum();
    println!(
        "rendered {done} of {} files into {} ({}): {total:.2} s in all, median {:.3} s, slowest {:.3} s ({})",
        files.len(),
        args.output.display(),
        gpu.info.name,
        seconds.get(done / 2).map_or(0.0, |s| s.0),
        seconds.last().map_or(0.0, |s| s.0),
        seconds
            .last()
            .map_or(String::new(), |s| s.1.display().to_string()),
    );
    if let Some(sheet) = &args.sheet {
        write_sheet(sheet, &files, &tiles, args.size)?;
        println!("wrote {}", sheet.display());
    }
    if done < files.len() {
        bail!("{} files could not be rendered", files.len() - done);
    }
    Ok(())
}

/// A grid of the tiles (failed files as pale red tiles) and a text index beside it.
fn write_sheet(
    sheet: &Path,
    files: &[PathBuf],
    tiles: &[Option<RgbaImage>],
    (w, h): (u32, u32),
) -> Result<()> {
    let n = tiles.len().max(1) as u32;
    let cols = (f64::from(n).sqrt().ceil() as u32).max(1);
    let rows = n.div_ceil(cols);
    let gap = 2;
    let mut out = RgbaImage::from_pixel(
        cols * (w + gap) + gap,
        rows * (h + gap) + gap,
        image::Rgba([200, 200, 200, 255]),
    );
    let mut index = String::new();
    for (i, (tile, file)) in tiles.iter().zip(files).enumerate() {
        let (c, r) = (i as u32 % cols, i as u32 / cols);
        let (x, y) = (gap + c * (w + gap), gap + r * (h + gap));
        let failed = RgbaImage::from_pixel(w, h, image::Rgba([255, 200, 200, 255]));
        image::imageops::overlay(
            &mut out,
            tile.as_ref().unwrap_or(&failed),
            i64::from(x),
            i64::from(y),
        );
        index.push_str(&format!(
            "row {} column {}: {}{}\n",
            r + 1,
            c + 1,
            file.display(),
            if tile.is_some() { "" } else { " (failed)" }
        ));
    }
    save(&out, sheet)?;
    std::fs::write(sheet.with_extension("txt"), index)
        .with_context(|| format!("writing the index beside {}", sheet.display()))
}

/// Mesh warnings printed per rendered file; the rest are counted.
const MAX_PRINTED_WARNINGS: usize = 20;

/// Loads, meshes and renders one file.
fn render_file(
    gpu: &Gpu,
    renderer: &Renderer,
    input: &Path,
    args: &RenderArgs,
) -> Result<RgbaImage> {
    draw_file(gpu, renderer, &mesh_file(input, args)?, args)
}

/// A file loaded and its bodies meshed (once per body, not per instance), ready to be
/// placed and drawn.
struct MeshedFile {
    input: PathBuf,
    loaded: crate::load::Loaded,
    mesh: cadre_mesh::ModelMesh,
}

/// Loads and meshes one file, printing what the tessellation lost; needs no GPU.
fn mesh_file(input: &Path, args: &RenderArgs) -> Result<MeshedFile> {
    let loaded = load_step(input)?;
    let model = &loaded.model;
    let params = MeshParams {
        deflection: Deflection::Relative(args.deflection_rel).resolve(deflection_diagonal(model)),
        angle: 0.35,
        ..MeshParams::default()
    };
    let mesh = mesh_model(model, &params, None);
    // What the tessellation lost or repaired, as `cadre mesh` reports it: an image with a
    // face missing must not look like a faithful one.
    let lost = crate::report::MeshReport::new(model, &mesh).warnings(&loaded.file);
    for w in lost.iter().take(MAX_PRINTED_WARNINGS) {
        eprintln!("warning: {}: {w}", input.display());
    }
    if lost.len() > MAX_PRINTED_WARNINGS {
        eprintln!(
            "warning: {}: … and {} more (cadre mesh --json lists them all)",
            input.display(),
            lost.len() - MAX_PRINTED_WARNINGS
        );
    }
    Ok(MeshedFile {
        input: input.to_path_buf(),
        loaded,
        mesh,
    })
}

/// Places a meshed file's instances and renders them.
fn draw_file(
    gpu: &Gpu,
    renderer: &Renderer,
    meshed: &MeshedFile,
    args: &RenderArgs,
) -> Result<RgbaImage> {
    let (input, model) = (meshed.input.as_path(), &meshed.loaded.model);
    let scene = RenderScene::from_model(model, &meshed.mesh);
    if args.labels && !(args.label_size.is_finite() && args.label_size > 0.0) {
        bail!(
            "--label-size must be a positive pixel height, got {}",
            args.label_size
        );
    }
    let (w, h) = args.size;
    let program = match &args.toolpath.toolpath {
        Some(path) => Some(load_program(path, true)?),
        None => None,
    };
    // A model with nothing to draw (no face, mesh or curve: 6 corpus files, OCCT finds nothing
    // in them either) is an error, not a blank image that looks like a result; a folder run
    // reports the file and goes on.
    let Some(model_box) = scene.bounds() else {
        bail!(
            "{}: nothing to draw (no face, mesh or curve placed; {} warning(s) while reading); \
             no image written",
            input.display(),
            model.warnings.len()
        );
    };
    // The view takes in the toolpath and the PMI drawn too.
    let (lo, hi) = match program.as_ref().and_then(program_bounds) {
        Some((a, b)) => (model_box.0.min(a), model_box.1.max(b)),
        None => model_box,
    };
    let saved_view = match &args.saved_view {
        Some(name) => Some(model.pmi.view(name).with_context(|| {
            let names: Vec<&str> = model.pmi.views.iter().map(|v| v.name.as_str()).collect();
            format!(
                "{}: no saved view {name:?} (the file has {})",
                input.display(),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )
        })?),
        None => None,
    };
    let placements = cadre_render::pmi::Placements::of(model);
    let pmi = (args.pmi || saved_view.is_some()).then(|| {
        let overlay =
            cadre_render::pmi::overlay(&model.pmi, saved_view, args.background, &placements);
        if overlay.annotations == 0 {
            eprintln!("{}: no PMI annotation to draw", input.display());
        } else if overlay.recoloured > 0 {
            eprintln!(
                "{}: {} of {} annotation(s) drawn in dark blue: their colour does not show on \
                 the background",
                input.display(),
                overlay.recoloured,
                overlay.annotations
            );
        }
        overlay
    });
    let (lo, hi) = match pmi.as_ref().and_then(cadre_render::pmi::overlay_bounds) {
        Some((a, b)) => (lo.min(a), hi.max(b)),
        None => (lo, hi),
    };
    let scene = match args.method {
        Method::Mesh => scene,
        Method::Trim | Method::Raycast => {
            let relative = view_trim_tolerance(args.trim_tolerance_rel, (w, h), args.zoom);
            with_trims(renderer, scene, model, relative, input)
        }
    };
    let fitted = match saved_view {
        Some(view) => cadre_render::pmi::saved_view_camera(
            view,
            (lo, hi),
            f64::from(w) / f64::from(h),
            &placements,
        ),
        None => fitted_camera(args, (lo, hi)),
    };
    let camera = if args.zoom == 1.0 {
        fitted
    } else {
        let caster = cadre_render::raycast::RayCaster::new(model, 1e-4 * (hi - lo).length());
        let point = centre_point(&caster, &fitted, (lo, hi));
        fitted.zoomed_at(point, args.zoom, (lo, hi))
    };
    let options = FrameOptions {
        // Trimmed edges' analytic coverage comes on top of either (`--method trim`).
        analytic_coverage: args.antialias != Antialias::None,
        cracks: args.cracks.options(),
        ..frame_options(args, gpu)?
    };
    let (scene, lines) = match &program {
        Some(program) => with_toolpath(scene, program, &args.toolpath, (&camera, h))?,
        None => (scene, cadre_render::LineView::default()),
    };
    // A saved view's clipping planes cut the model as section planes.
    let sections = match saved_view {
        Some(view) => {
            if view.front_clip.is_some() || view.back_clip.is_some() {
                eprintln!(
                    "{}: saved view {:?}: its front and back clipping distances are not applied",
                    input.display(),
                    view.name
                );
            }
            cadre_render::pmi::saved_view_sections(view, &placements)
        }
        None => Vec::new(),
    };
    if sections.len() > cadre_render::MAX_SECTIONS {
        eprintln!(
            "{}: the saved view has {} clipping planes; the first {} are applied",
            input.display(),
            sections.len(),
            cadre_render::MAX_SECTIONS
        );
    }
    let state = ViewState {
        lines,
        sections,
        ..ViewState::default()
    };
    let mut scene = scene;
    if args.dimensions {
        let path = cadre_render::dimensions::sidecar_path(input);
        let file = cadre_render::dimensions::DimensionFile::read(&path)?.with_context(|| {
            format!(
                "{}: no dimensions kept beside it ({} not found; measure in `cadre view`)",
                input.display(),
                path.display()
            )
        })?;
        let (lines, labels) =
            cadre_render::dimensions::overlay(&file.dimensions, args.label_size, None);
        scene.lines.extend(lines);
        scene.labels.extend(labels);
    }
    if let Some(overlay) = pmi {
        scene.lines.extend(overlay.lines);
        scene.labels.extend(overlay.labels);
    }
    // Callouts laid out for the view, side by side without overlap: the part names, and the
    // semantic PMI the file does not present (not in saved views, which show what their
    // author placed).
    let mut anchors = Vec::new();
    if args.labels {
        anchors = cadre_render::text::leaders::part_anchors(&scene.assembly);
    }
    if args.pmi && saved_view.is_none() {
        let generated = cadre_render::pmi::semantic_anchors(model, &placements);
        if !generated.is_empty() {
            eprintln!(
                "{}: {} semantic PMI item(s) without a presentation drawn as generated callouts",
                input.display(),
                generated.len()
            );
        }
        anchors.extend(generated);
    }
    if !anchors.is_empty() {
        let callouts = cadre_render::text::leaders::lay_out_callouts(
            &anchors,
            Some(model_box),
            &camera,
            (w, h),
            args.label_size,
        );
        if callouts.omitted > 0 {
            eprintln!(
                "{}: {} of {} callout(s) left out: no room beside the model at {w}×{h} \
                 (a larger --size or a smaller --label-size shows more)",
                input.display(),
                callouts.omitted,
                anchors.len()
            );
        }
        scene.labels.extend(callouts.labels);
    }
    let prepared = renderer.prepare(gpu, &scene);
    let image = renderer
        .render(gpu, &prepared, &camera, &options, &state)
        .with_context(|| format!("{}: nothing was drawn", input.display()))?;
    if args.method.exact() && options.cracks.mode != CrackMode::Off {
        let c = renderer.last_crack_counts(gpu);
        if c.detected > 0 {
            eprintln!(
                "{}: {} crack pixel(s) ({} beside silhouettes): {} filled exactly ({} from \
                 their neighbours' faces, {} face draw(s) again), {} by the fast fill, {} in \
                 gaps closed, {} left open{}",
                input.display(),
                c.detected,
                c.silhouettes,
                c.exact,
                c.settled,
                c.fill_faces,
                c.fast,
                c.gaps,
                c.open,
                if c.overflow > 0 {
                    format!(", {} past the pass's capacity", c.overflow)
                } else {
                    String::new()
                }
            );
        }
    }
    Ok(image)
}

/// The trims' tolerance relative to the diagonal for a `w` × `h` view magnified `zoom` times
/// from the fitted one (which spans about the diagonal): `relative`, or a quarter of the
/// view's pixel where that is finer — at 1000× a 1920-pixel view's pixel is 5·10⁻⁷ of the
/// model, and trims fitted within 10⁻⁵ of it put trimmed edges 20 pixels off — but no finer
/// than 10⁻⁷ (a face's `f32` local coordinates resolve about 6·10⁻⁸ of it).
pub(crate) fn view_trim_tolerance(relative: f64, (w, h): (u32, u32), zoom: f64) -> f64 {
    let pixel = 1.0 / (f64::from(w.max(h).max(1)) * zoom.max(1.0));
    relative.min((0.25 * pixel).max(1e-7))
}

/// `scene` with `model`'s faces drawn from their exact surfaces (trims within `relative` of
/// the diagonal), printing how many keep their meshes and why.
pub(crate) fn with_trims(
    renderer: &Renderer,
    scene: RenderScene,
    model: &cadre_brep::Model,
    relative: f64,
    input: &Path,
) -> RenderScene {
    if !renderer.draws_trims() {
        eprintln!(
            "warning: {}: this adapter runs no compute shaders; every face is drawn from its mesh",
            input.display()
        );
        return scene;
    }
    let tolerance = relative * deflection_diagonal(model);
    let scene = scene.with_trims(model, tolerance);
    if let Some(trim) = &scene.trim {
        let faces = trim.faces.len();
        let closed_forms = match trim.closed_form_faces.len() {
            0 => String::new(),
            n => format!(" ({n} B-splines as the planes, cylinders or spheres they are)"),
        };
        eprintln!(
            "{}: {} of {faces} faces drawn from their exact surfaces{closed_forms}, {} from their meshes",
            input.display(),
            trim.drawn(),
            trim.fallback.len()
        );
        for (id, why) in trim.fallback.iter().take(MAX_PRINTED_WARNINGS) {
            eprintln!("  face #{id}: {why}");
        }
        if trim.fallback.len() > MAX_PRINTED_WARNINGS {
            eprintln!(
                "  … and {} more",
                trim.fallback.len() - MAX_PRINTED_WARNINGS
            );
        }
    }
    scene
}

/// The model's point seen at the centre of `camera`'s image, or the visible one nearest the
/// centre (the box's centre when nothing is seen), by `caster`: where `--zoom` magnifies.
pub(crate) fn centre_point(
    caster: &cadre_render::raycast::RayCaster,
    camera: &Camera,
    (lo, hi): (glam::DVec3, glam::DVec3),
) -> glam::DVec3 {
    let (w, h) = (33u32, 33u32);
    let hits = caster.hits(camera, w, h);
    hits.iter()
        .enumerate()
        .filter_map(|(i, hit)| {
            let (x, y) = ((i as u32 % w) as f64 - 16.0, (i as u32 / w) as f64 - 16.0);
            hit.map(|(_, p)| (x * x + y * y, p))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(0.5 * (lo + hi), |(_, p)| p)
}

#[cfg(test)]
mod tests {
    use super::view_trim_tolerance;

    #[test]
    fn trims_are_fitted_within_a_quarter_pixel_of_the_view() {
        // A fitted 1920-pixel view: the given tolerance (far under its pixel) stands.
        assert_eq!(view_trim_tolerance(1e-5, (1920, 1080), 1.0), 1e-5);
        // At 1000× a pixel is 1 / 1,920,000 of the model: a quarter of it.
        let at_1000 = view_trim_tolerance(1e-5, (1920, 1080), 1000.0);
        assert!((at_1000 - 0.25 / 1.92e6).abs() < 1e-15, "{at_1000}");
        // Never under 10⁻⁷ (what a face's f32 coordinates resolve), nor for a bad zoom.
        assert_eq!(view_trim_tolerance(1e-5, (1920, 1080), 1e9), 1e-7);
        assert_eq!(view_trim_tolerance(1e-5, (160, 120), f64::NAN), 1e-5);
        // Negative control: a coarser tolerance given is what a fitted view keeps.
        assert_eq!(view_trim_tolerance(1e-3, (160, 120), 1.0), 1e-3);
    }
}
