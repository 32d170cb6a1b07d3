//! The `cadre` command line: inspect, convert and render CAD models.

mod commands;
mod load;
mod output;
mod progress;
mod report;

use anyhow::Result;
use clap::{Parser, Subcommand};

/// cadre: exact, fast rendering of CAD models.
#[derive(Parser)]
#[command(name = "cadre", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Summarise a STEP file: schema, units, product tree, counts, bounding box, warnings.
    Info(commands::info::InfoArgs),
    /// Tessellate a STEP file into a watertight mesh: .glb/.gltf (assembly tree, shared
    /// instances, materials), .stl or .obj.
    Mesh(commands::mesh::MeshArgs),
    /// Render a STEP file (or a folder of them) to PNG, headless (GPU or Mesa's software
    /// drivers).
    Render(Box<commands::render::RenderArgs>),
    /// Open the interactive viewer (model tree, picking, measurement, screenshots, 3D
    /// mouse) on a STEP file, or empty.
    View(commands::view::ViewArgs),
    /// Time cadre's stages over a folder of files (used by the scripts in `scripts/`).
    Bench(commands::bench::BenchArgs),
    /// Interpret a CAM program (G-code): a summary of its moves, or `--json` the moves
    /// themselves in program order (end points in mm).
    Toolpath(commands::toolpath::ToolpathArgs),
    /// Check a file's face-id images (mesh or exact faces) against the CPU ray caster of the
    /// exact B-Rep, in four views at several magnifications.
    Verify(commands::verify::VerifyArgs),
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // As anyhow's own report, without the backtrace it adds when RUST_BACKTRACE is
            // set (common on developer machines): a user's mistake is not a crash.
            eprintln!("Error: {e}");
            let causes: Vec<String> = e.chain().skip(1).map(|c| c.to_string()).collect();
            if !causes.is_empty() {
                eprintln!("\nCaused by:");
                for c in causes {
                    eprintln!("    {c}");
                }
            }
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> Result<()> {
    quiet_on_broken_pipe();
    quiet_device_selection();
    keep_freed_memory();
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("CADRE_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    match cli.command {
        Command::Info(args) => commands::info::run(&args),
        Command::Mesh(args) => commands::mesh::run(&args),
        Command::Render(args) => commands::render::run(&args),
        Command::View(args) => commands::view::run(&args),
        Command::Bench(args) => commands::bench::run(&args),
        Command::Verify(args) => commands::verify::run(&args),
        Command::Toolpath(args) => commands::toolpath::run(&args),
    }
}

/// Mesa's Vulkan device-selection layer (installed with lavapipe) asks the Wayland compositor
/// for the default GPU, and without `XDG_RUNTIME_DIR` libwayland prints
/// "error: XDG_RUNTIME_DIR is invalid or not set in the environment." twice on every run,
/// which a user of `cadre render` reads as a failure. There is no compositor to ask then, so
/// the layer can do nothing but print: it is turned off (`NODEVICE_SELECT=1`, Mesa's own
/// switch), unless the user set that variable. cadre picks its adapter itself.
fn quiet_device_selection() {
    let runtime_dir_ok =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_absolute());
    if runtime_dir_ok || std::env::var_os("NODEVICE_SELECT").is_some() {
        return;
    }
    // SAFETY: called first thing in `main`, before any thread is started (the tracing
    // subscriber and rayon's pool come later), so nothing reads the environment concurrently.
    #[allow(unsafe_code)]
    unsafe {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// Freed memory above this much at the top of a glibc heap goes back to the system (glibc's
/// default: 128 KiB, adjusted by the allocation sizes it sees).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD: i32 = 64 << 20;

/// lavapipe (Mesa's CPU Vulkan) allocates and frees megabytes of vertex and binning data at
/// every draw; with glibc's default trim threshold each frame's frees were handed back to
/// the kernel and the next frame faulted the pages in again, zeroed: 3,000 page faults a
/// frame for trj4_pm2-ec-214 at 1280×960 (40 k triangles, 8 k edge segments), its frame
/// 29–30 → 21–23 ms with the memory kept (`cadre bench view`; BENCHMARKS.md, issue 15).
/// The process keeps up to [`TRIM_THRESHOLD`] of freed memory per heap for reuse instead.
/// Applications that embed cadre-render choose their own allocator settings.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets one of glibc's allocator parameters; it is called first
    // thing in `main`, before any thread starts.
    #[allow(unsafe_code)]
    unsafe {
        // 0 when glibc refuses the value; the allocator then keeps its defaults, which are
        // slower for software rendering but correct.
        if libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 0 {
            tracing::debug!("glibc kept its default trim threshold");
        }
    }
}

/// `cadre info FILE | head` closes the pipe before the output ends, and `println!` then
/// panics; end quietly instead, with the status a command stopped by SIGPIPE has (141).
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}
