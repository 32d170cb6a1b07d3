//! `cadre view`: the interactive desktop viewer.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

/// Arguments of `cadre view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// A STEP file (or a CAM program) to open (File → Open and drag-and-drop open others).
    pub file: Option<PathBuf>,
    /// A CAM program (G-code) shown over the model (File → Open takes programs too).
    #[arg(long, value_name = "PROGRAM")]
    pub toolpath: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT in logical pixels.
    #[arg(long, value_parser = crate::commands::render::parse_size)]
    pub size: Option<(u32, u32)>,
    /// Folder where F12 writes screenshot-N.png (default: the current folder).
    #[arg(long)]
    pub screenshot_dir: Option<PathBuf>,
    /// Print one line on stdout for each thing that happens (model loaded, view changed,
    /// screenshot written): for scripts and tests driving the viewer.
    #[arg(long)]
    pub report: bool,
}

/// Opens the viewer and runs until its window closes.
pub fn run(args: &ViewArgs) -> Result<()> {
    if let Some(file) = &args.file
        && !file.is_file()
    {
        anyhow::bail!("{}: no such file", file.display());
    }
    if let Some(program) = &args.toolpath
        && !program.is_file()
    {
        anyhow::bail!("{}: no such file", program.display());
    }
    cadre_viewer::run(cadre_viewer::ViewerOptions {
        file: args.file.clone(),
        toolpath: args.toolpath.clone(),
        size: args.size,
        screenshot_dir: args.screenshot_dir.clone(),
        report: args.report,
    })
    .context("the viewer stopped")
}
