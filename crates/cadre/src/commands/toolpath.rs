//! `cadre toolpath`: a CAM program (G-code) interpreted into the tool's moves, printed as a
//! summary or as JSON; and the toolpath options `cadre render` shares.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use cadre_gcode::{MoveKind, Program};
use cadre_render::lines::toolpath::{
    ColourBy, ToolpathStyle, pixel_tolerance, tool_marker, toolpath_lines,
};
use cadre_render::{Camera, LineView, RenderScene};
use glam::DVec3;

/// Warnings printed before "… and N more".
const MAX_PRINTED_WARNINGS: usize = 20;

/// `cadre toolpath` arguments.
#[derive(clap::Args, Debug)]
pub struct ToolpathArgs {
    /// The program: ISO 6983 / RS-274 G-code (`.ngc`, `.nc`, `.gcode`, `.tap`, …).
    program: PathBuf,
    /// Print the interpreted moves in program order as JSON: `{"units": "mm", "moves":
    /// [{"kind", "line", "end", "centre", "turns", …}], "warnings": [...]}`.
    #[arg(long)]
    json: bool,
}

/// The toolpath options of `cadre render`.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ToolpathDrawArgs {
    /// A CAM program (G-code) drawn over the model: rapids dashed, cutting moves coloured.
    #[arg(long, value_name = "PROGRAM")]
    pub toolpath: Option<PathBuf>,
    /// What colours the cutting moves: feed, tool or kind.
    #[arg(long, default_value = "feed", value_parser = parse_colour_by)]
    pub toolpath_colour: ColourByArg,
    /// Show the path only up to this distance along it (mm), with the tool there.
    #[arg(long, value_name = "MM")]
    pub up_to: Option<f64>,
    /// Show the path only inside this box: X0,Y0,Z0,X1,Y1,Z1 (mm).
    #[arg(long, value_parser = parse_box, allow_hyphen_values = true)]
    pub clip_box: Option<(DVec3, DVec3)>,
    /// The tool's diameter (mm) where it is drawn (`--up-to`).
    #[arg(long, default_value_t = 6.0)]
    pub tool_diameter: f64,
}

/// `--toolpath-colour`.
#[derive(Clone, Copy, Debug, Default)]
pub struct ColourByArg(pub ColourBy);

fn parse_colour_by(s: &str) -> Result<ColourByArg, String> {
    match s {
        "feed" => Ok(ColourByArg(ColourBy::Feed)),
        "tool" => Ok(ColourByArg(ColourBy::Tool)),
        "kind" => Ok(ColourByArg(ColourBy::Kind)),
        _ => Err(format!("'{s}': feed, tool or kind")),
    }
}

fn parse_box(s: &str) -> Result<(DVec3, DVec3), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("'{x}': {e}")))
        .collect::<Result<_, _>>()?;
    if v.len() != 6 || v.iter().any(|x| !x.is_finite()) {
        return Err("six finite numbers X0,Y0,Z0,X1,Y1,Z1 expected".into());
    }
    let (a, b) = (DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]));
    Ok((a.min(b), a.max(b)))
}

/// Whether `path` looks like a G-code program (by its extension).
pub fn is_program(path: &Path) -> bool {
    cadre_gcode::is_program_path(path)
}

/// Reads and interprets a program, printing its warnings (the first 20) on stderr.
pub fn load_program(path: &Path, print_warnings: bool) -> Result<Program> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    // G-code is ASCII; anything else is kept as replacement characters, which the lines
    // that hold them warn about.
    let text = String::from_utf8_lossy(&bytes);
    let program = cadre_gcode::interpret(&text);
    if print_warnings {
        for w in program.warnings.iter().take(MAX_PRINTED_WARNINGS) {
            eprintln!("warning: {}:{}: {}", path.display(), w.line, w.message);
        }
        if program.warnings.len() > MAX_PRINTED_WARNINGS {
            eprintln!(
                "warning: {}: … and {} more (cadre toolpath --json lists them all)",
                path.display(),
                program.warnings.len() - MAX_PRINTED_WARNINGS
            );
        }
    }
    Ok(program)
}

/// Runs `cadre toolpath`.
pub fn run(args: &ToolpathArgs) -> Result<()> {
    let program = load_program(&args.program, !args.json)?;
    if args.json {
        let stdout = std::io::stdout();
        let mut out = std::io::BufWriter::new(stdout.lock());
        serde_json::to_writer(&mut out, &program)?;
        use std::io::Write;
        writeln!(out)?;
        return Ok(());
    }
    let count = |k: MoveKind| program.moves.iter().filter(|m| m.kind == k).count();
    let set = toolpath_lines(&program, &ToolpathStyle::default(), 1e-3);
    println!("program: {}", args.program.display());
    println!(
        "units: {} (as written: {})",
        program.units, program.program_units
    );
    println!(
        "moves: {} ({} rapid, {} feed, {} arc)",
        program.moves.len(),
        count(MoveKind::Rapid),
        count(MoveKind::Feed),
        count(MoveKind::Arc)
    );
    let mut tools: Vec<u32> = program.moves.iter().map(|m| m.tool).collect();
    tools.sort_unstable();
    tools.dedup();
    println!("tools: {tools:?}");
    println!("path length: {:.3} mm", set.travel());
    if let Some((lo, hi)) = set.bounds() {
        println!(
            "bounds: [{:.3}, {:.3}, {:.3}] – [{:.3}, {:.3}, {:.3}] mm (machine coordinates)",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        );
    }
    println!("warnings: {}", program.warnings.len());
    Ok(())
}

/// A program's path in the machine's coordinates, sampled coarsely: its box, for fitting the
/// camera before the arcs are sampled to the view.
pub fn program_bounds(program: &Program) -> Option<(DVec3, DVec3)> {
    let coarse = toolpath_lines(program, &ToolpathStyle::default(), 0.05);
    coarse.bounds()
}

/// `scene` with the program's path (arcs sampled to a quarter of the view's pixel) and, with
/// `--up-to`, the tool; and the view of it the options ask for.
pub fn with_toolpath(
    scene: RenderScene,
    program: &Program,
    args: &ToolpathDrawArgs,
    (camera, rows): (&Camera, u32),
) -> Result<(RenderScene, LineView)> {
    let style = ToolpathStyle {
        colour_by: args.toolpath_colour.0,
        ..ToolpathStyle::default()
    };
    let lines = toolpath_lines(program, &style, pixel_tolerance(camera.view_height(), rows));
    if let Some(d) = args.up_to
        && !(d.is_finite() && d >= 0.0)
    {
        bail!("--up-to must be a distance ≥ 0 mm, got {d}");
    }
    let tool = args.up_to.and_then(|d| lines.point_at_travel(d));
    let mut scene = scene.with_lines(lines);
    if let Some(marker) = tool.and_then(|tip| tool_marker(tip, args.tool_diameter)) {
        scene.primitives.push(marker);
    }
    Ok((
        scene,
        LineView {
            up_to: args.up_to,
            clip_box: args.clip_box,
        },
    ))
}
