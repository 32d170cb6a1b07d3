//! The interactive desktop viewer of cadre: a winit window drawn by the cadre-render engine,
//! with an egui interface (model tree, properties, measurement, display modes, screenshots)
//! and 3D mouse navigation through spacenavd.
//!
//! [`run`] opens the window; everything it computes that is not drawing is in modules that
//! are tested without one: [`navigation`] (camera gestures), [`document`] (loading a model),
//! [`inspect`] (properties and measurements), [`gizmo`] (the axis gizmo's maths).

mod app;
pub mod document;
pub mod gizmo;
pub mod inspect;
pub mod navigation;
mod session;
mod toolpath_view;
mod ui;

use std::path::PathBuf;

/// What the viewer starts with.
#[derive(Clone, Debug, Default)]
pub struct ViewerOptions {
    /// A STEP file (or a CAM program) to open at start.
    pub file: Option<PathBuf>,
    /// A CAM program (G-code) to open over it at start.
    pub toolpath: Option<PathBuf>,
    /// Initial window size in logical pixels (default 1280 × 800).
    pub size: Option<(u32, u32)>,
    /// Where F12 writes its screenshots (`screenshot-N.png`; default the current folder).
    pub screenshot_dir: Option<PathBuf>,
    /// Print what happens (model loaded, screenshot written, view changed) on stdout, one
    /// line each: what scripts and the end-to-end test wait for.
    pub report: bool,
}

/// What stops the viewer.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    /// No window could be opened (no display, or the windowing system refused).
    #[error("cannot open a window: {0}")]
    Window(String),
    /// No GPU adapter can draw into the window.
    #[error("no GPU adapter can draw into the window: {0}")]
    Adapter(String),
    /// The renderer failed.
    #[error(transparent)]
    Render(#[from] cadre_render::RenderError),
    /// A model did not load.
    #[error("{path}: {message}")]
    Load {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// Opens the viewer window and runs until it is closed.
pub fn run(options: ViewerOptions) -> Result<(), ViewerError> {
    app::run(options)
}
