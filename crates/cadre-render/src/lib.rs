//! The GPU renderer of cadre, on wgpu.
//!
//! One renderer, several surface back-ends (see `docs/architecture.md`): every back-end writes
//! the same visibility buffer (reverse-Z depth, normal, ids, (u, v)), and the later passes
//! (shading, edges, silhouettes, section caps, picking) read only that buffer. Two back-ends
//! exist: tessellated meshes and analytic primitives ray cast per pixel
//! ([`AnalyticPrimitive`]), both in a [`RenderScene`] built from the model.
//!
//! Rendering is headless first: [`Gpu::headless`] finds a native GPU or Mesa's software
//! drivers (Vulkan lavapipe, GL llvmpipe through EGL); [`Renderer::prepare`] uploads a
//! scene once, [`Renderer::render`] returns an image of it, [`Renderer::render_ids`] its
//! visibility buffer's ids, and [`Renderer::draw`] draws a viewer's frame into a
//! [`Viewport`] and a window's (or the caller's) texture, for [`Renderer::pick`]. Geometry is
//! placed relative to the camera in `f64` before it is sent to the GPU as `f32`, so a part
//! 10⁶ mm from the origin renders like one at the origin. Up to three [`SectionPlane`]s of a
//! [`ViewState`] cut the model; closed solids show hatched caps where they are cut.
//!
//! ```no_run
//! use cadre_render::{Camera, FrameOptions, Gpu, RenderScene, Renderer, ViewPreset, ViewState};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let file = cadre_step::syntax::StepFile::read("part.step".as_ref())?;
//! let model = cadre_step::map_file(&file);
//! let mesh = cadre_mesh::mesh_model(&model, &cadre_mesh::MeshParams::default(), None);
//! let scene = RenderScene::from_model(&model, &mesh);
//!
//! let gpu = Gpu::headless()?;
//! let renderer = Renderer::new(&gpu)?;
//! let prepared = renderer.prepare(&gpu, &scene);
//! let (lo, hi) = scene.bounds().ok_or("nothing to draw")?;
//! let camera = Camera::fit(lo, hi, ViewPreset::Iso, false, 800.0 / 600.0);
//! let image = renderer.render(
//!     &gpu,
//!     &prepared,
//!     &camera,
//!     &FrameOptions::default(),
//!     &ViewState::default(),
//! )?;
//! image.save("part.png")?;
//! # Ok(())
//! # }
//! ```

pub mod analytic;
pub mod backdrop;
mod bounds;
mod camera;
pub mod compare;
mod coverage;
pub mod dimensions;
mod edge_faces;
mod error;
mod feature_edges;
mod frame_buffers;
mod gpu;
mod gpu_scene;
pub mod layout;
mod lights;
pub mod lines;
mod pass_timer;
mod passes;
mod pick;
mod placements;
pub mod pmi;
mod position_key;
pub mod raycast;
mod render_scene;
mod renderer;
pub mod scene_file;
pub mod shadows;
mod smooth;
mod solid;
pub mod text;
pub mod trim_quadrics;
pub mod trim_surfaces;
pub mod trim_sweeps;
mod vertex_cache;
mod view;
mod viewport;

pub use analytic::{AnalyticPrimitive, AnalyticShape, QuadricShape};
pub use backdrop::{Background, GroundGrid};
pub use bounds::scene_bounds;
pub use cadre_text::{Align, Baseline};
pub use camera::{Camera, Frustum, Projection, ViewPreset};
pub use coverage::MAX_IMAGE_COVERAGE;
pub use error::RenderError;
pub use gpu::Gpu;
pub use gpu_scene::{MAX_FRAME_TRIANGLES, PreparedScene};
pub use lights::Light;
pub use lines::{Cap, Hidden, Join, LineSet, LineStyle, LineView, LineWidth, Polyline, Stipple};
pub use passes::cracks::{
    CrackCounts, CrackMode, CrackOptions, MIN_DEPTH_REL as CRACK_MIN_DEPTH_REL,
};
pub use pick::PendingPick;
pub use placements::{FLAT_LIMIT, MAX_LOCALS_PER_NODE};
pub use render_scene::{RenderFace, RenderScene};
pub use renderer::{DisplayMode, FrameOptions, Renderer};
pub use smooth::smooth_edges;
pub use text::{Fill, Label, LabelSet, TextAnchor, TextDepth, TextHeight};
pub use trim_surfaces::TrimScene;
pub use view::{
    CRACK_FILLED, GAP_CLOSED, InstanceStyle, MAX_HIGHLIGHTED, MAX_SECTIONS, Pick, SECTION_CAP,
    SectionPlane, ViewState, section_cap,
};
pub use viewport::{PickHit, PickWindow, Viewport};
/// The wgpu this renderer is built on, for embedders that hand it their window's surface.
pub use wgpu;
