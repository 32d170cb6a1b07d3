//! The window: winit events, the wgpu surface, the frame (the 3D view by cadre-render, the
//! interface by egui over it), background loading, picking, the 3D mouse and screenshots.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use cadre_render::{
    CrackMode, CrackOptions, FrameOptions, Gpu, PendingPick, PickWindow, PreparedScene, Renderer,
    Viewport,
};
use cadre_spacenav::{NavSettings, SpaceEvent, SpaceNav};
use glam::{DVec2, DVec3, DVec4};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop, EventLoopProxy};
use winit::window::{Window, WindowId};

use crate::document::{Document, LoadStage};
use crate::inspect::Picked;
use crate::session::Session;
use crate::ui::{self, Action, ViewInput};
use crate::{ViewerError, ViewerOptions};

/// Cap height of the dimensions' text in the view, pixels.
const DIMENSION_TEXT: f32 = 12.0;

/// The 3D view's background (sRGB): a light grey.
const VIEW_BACKGROUND: [f32; 4] = [0.93, 0.94, 0.96, 1.0];

/// Pixels of tolerance around the cursor for edges and vertices.
const PICK_RADIUS: u32 = 5;

/// Messages from the loading thread.
enum UserEvent {
    Progress(PathBuf, LoadStage),
    Loaded(Box<Result<Document, ViewerError>>),
}

/// The window's GPU side.
struct Gfx {
    window: Arc<Window>,
    surface: cadre_render::wgpu::Surface<'static>,
    config: cadre_render::wgpu::SurfaceConfiguration,
    gpu: Gpu,
    renderer: Renderer,
    egui_renderer: egui_wgpu::Renderer,
    viewport: Option<Viewport>,
    /// The 3D view's texture (the central panel's size), shown by egui as an image.
    view: Option<ViewTexture>,
}

/// The texture the renderer draws the 3D view into, registered with egui.
struct ViewTexture {
    view: cadre_render::wgpu::TextureView,
    id: egui::TextureId,
    size: (u32, u32),
}

/// Format of the 3D view's texture: what the offscreen renderer writes (sRGB-encoded, so
/// egui's sampling decodes it like its own textures).
const VIEW_FORMAT: cadre_render::wgpu::TextureFormat =
    cadre_render::wgpu::TextureFormat::Rgba8UnormSrgb;

/// Tolerance of the trims of exact faces, relative to the model's diagonal (as
/// `cadre render --method trim`'s default).
const TRIM_TOLERANCE_RELATIVE: f64 = 1e-5;

struct App {
    options: ViewerOptions,
    proxy: EventLoopProxy<UserEvent>,
    gfx: Option<Gfx>,
    egui_ctx: egui::Context,
    egui_state: Option<egui_winit::State>,
    session: Session,
    prepared: Option<PreparedScene>,
    /// Whether `prepared` draws faces exactly (`Session::exact_faces` when it was made).
    prepared_exact: bool,
    /// The scene is to be prepared again before the next frame (a model or a toolpath
    /// opened, the faces' method or the tool changed).
    scene_stale: bool,
    /// The toolpath in `prepared`, when one is open.
    drawn_toolpath: Option<crate::toolpath_view::DrawnToolpath>,
    /// Whether PMI is in `prepared`, and which saved view's.
    drawn_pmi: (bool, Option<usize>),
    /// How many dimensions `prepared` draws, and which is selected.
    drawn_dimensions: (usize, Option<usize>),
    /// The labels of `prepared` other than the part callouts (PMI, dimensions).
    scene_labels: cadre_render::LabelSet,
    /// The camera and view size the part callouts were laid out for (`None`: none drawn).
    callouts_for: Option<(cadre_render::Camera, (u32, u32))>,
    /// Orbit pivot of the drag in progress.
    pivot: Option<DVec3>,
    /// The hover pick asked for and not yet answered, with the cursor it is for: answered
    /// on a later frame, so a pointer move never waits for the GPU.
    hover_pick: Option<(egui::Pos2, PendingPick)>,
    /// The cursor position whose answer `session.hover` holds.
    hovered_at: Option<egui::Pos2>,
    /// The camera moved this frame (orbit, pan, an animation): the cracks between faces
    /// drawn from their exact surfaces are closed by the fast fill, and by the exact one
    /// once it stops.
    camera_moving: bool,
    /// The 3D view's rectangle in the window, physical pixels.
    view_rect: egui::Rect,
    last_frame: Instant,
    spacenav: Option<SpaceNav>,
    spacenav_retry: Instant,
    screenshots: usize,
    error: Option<ViewerError>,
}

/// Opens the window and runs the event loop.
pub(crate) fn run(options: ViewerOptions) -> Result<(), ViewerError> {
    let event_loop = EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| ViewerError::Window(e.to_string()))?;
    let mut app = App {
        proxy: event_loop.create_proxy(),
        options,
        gfx: None,
        egui_ctx: egui::Context::default(),
        egui_state: None,
        session: Session::new(),
        prepared: None,
        prepared_exact: false,
        scene_stale: false,
        drawn_toolpath: None,
        drawn_pmi: (false, None),
        drawn_dimensions: (0, None),
        scene_labels: cadre_render::LabelSet::default(),
        callouts_for: None,
        pivot: None,
        hover_pick: None,
        hovered_at: None,
        camera_moving: false,
        view_rect: egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1.0, 1.0)),
        last_frame: Instant::now(),
        spacenav: None,
        spacenav_retry: Instant::now(),
        screenshots: 0,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| ViewerError::Window(e.to_string()))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl App {
    fn report(&self, line: &str) {
        if self.options.report {
            println!("{line}");
        }
        tracing::info!("{line}");
    }

    /// Opens a CAM program over the model, or starts loading a model on a thread of its own.
    fn open(&mut self, path: PathBuf) {
        if crate::session::Toolpath::is_program(&path) {
            match crate::session::Toolpath::load(&path) {
                Ok(toolpath) => {
                    self.report(&format!(
                        "toolpath {} moves {} warnings {}",
                        path.display(),
                        toolpath.program.moves.len(),
                        toolpath.program.warnings.len()
                    ));
                    let aspect = self.aspect();
                    self.session.set_toolpath(toolpath, aspect);
                    self.scene_stale = true;
                }
                Err(e) => self.session.error = Some(e),
            }
            return;
        }
        self.open_model(path);
    }

    /// Starts loading the model `path` on a thread of its own.
    fn open_model(&mut self, path: PathBuf) {
        self.session.loading = Some((path.clone(), LoadStage::Reading));
        let proxy = self.proxy.clone();
        std::thread::spawn(move || {
            let best = std::sync::Mutex::new(0.0f32);
            let progress = |stage: LoadStage| {
                // Faces finish out of order: show progress that only goes forward.
                let mut b = best.lock().unwrap_or_else(|e| e.into_inner());
                if stage.fraction() >= *b {
                    *b = stage.fraction();
                    let _ = proxy.send_event(UserEvent::Progress(path.clone(), stage));
                }
            };
            let result = Document::load(&path, &progress);
            let _ = proxy.send_event(UserEvent::Loaded(Box::new(result)));
        });
    }

    fn create_gfx(&mut self, event_loop: &ActiveEventLoop) -> Result<(), ViewerError> {
        let (w, h) = self.options.size.unwrap_or((1280, 800));
        let attributes = Window::default_attributes()
            .with_title("cadre")
            .with_inner_size(winit::dpi::LogicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| ViewerError::Window(e.to_string()))?,
        );
        let mut desc =
            cadre_render::wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        // As in `Gpu::headless`: no indirect draws, so no indirect-call validation.
        desc.flags
            .remove(cadre_render::wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
        let instance = cadre_render::wgpu::Instance::new(desc);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| ViewerError::Window(e.to_string()))?;
        let adapter = pollster::block_on(instance.request_adapter(
            &cadre_render::wgpu::RequestAdapterOptions {
                power_preference: cadre_render::wgpu::PowerPreference::HighPerformance,
                compatible_surface: Some(&surface),
                force_fallback_adapter: false,
                apply_limit_buckets: false,
            },
        ))
        .map_err(|e| ViewerError::Adapter(e.to_string()))?;
        let gpu = Gpu::from_adapter(&adapter)?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| ViewerError::Adapter("the surface is not supported".into()))?;
        // egui paints in gamma space and prefers a plain (not sRGB) surface; the 3D view
        // reaches it as an sRGB texture, decoded and encoded like egui's own.
        let caps = surface.get_capabilities(&adapter);
        if let Some(f) = caps.formats.iter().find(|f| !f.is_srgb()) {
            config.format = *f;
        }
        config.usage |= cadre_render::wgpu::TextureUsages::RENDER_ATTACHMENT;
        surface.configure(&gpu.device, &config);
        let renderer = Renderer::for_format(&gpu, VIEW_FORMAT)?;
        let egui_renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            config.format,
            egui_wgpu::RendererOptions::default(),
        );
        self.egui_state = Some(egui_winit::State::new(
            self.egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.max_side() as usize),
        ));
        self.report(&format!(
            "adapter {} ({:?})",
            gpu.info.name, gpu.info.backend
        ));
        self.gfx = Some(Gfx {
            window,
            surface,
            config,
            gpu,
            renderer,
            egui_renderer,
            viewport: None,
            view: None,
        });
        Ok(())
    }

    /// The 3D view's size in physical pixels.
    fn view_size(&self) -> (u32, u32) {
        (
            (self.view_rect.width().round() as u32).max(1),
            (self.view_rect.height().round() as u32).max(1),
        )
    }

    /// Width / height of the 3D view.
    fn aspect(&self) -> f64 {
        let (w, h) = self.view_size();
        f64::from(w) / f64::from(h)
    }

    /// One frame: input, interface, 3D view, interface on top.
    fn frame(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = (now - self.last_frame).as_secs_f64();
        self.last_frame = now;
        let mut busy = false;
        if let Some(nav) = &mut self.session.nav {
            let was = nav.animating();
            busy |= nav.tick(dt);
            if was && !nav.animating() {
                self.report("view still");
            }
        }
        let Some(gfx) = &self.gfx else { return };
        let window = gfx.window.clone();
        let Some(state) = &mut self.egui_state else {
            return;
        };
        let raw = state.take_egui_input(&window);
        let aspect = self.aspect();
        let ctx = self.egui_ctx.clone();
        let mut out = (egui::Rect::NOTHING, ViewInput::default(), Vec::new());
        self.session.view_texture = gfx.view.as_ref().map(|v| v.id);
        let mut passes = 0;
        let mut full = ctx.run_ui(raw, |ui| {
            let (rect, input, actions) = ui::draw(ui, &mut self.session, aspect);
            // egui reruns a pass whose layout changed; the frame's events (keys, clicks,
            // drags) were all seen by the first, the layout is the last's.
            if passes == 0 {
                out = (rect, input, actions);
            } else {
                out.0 = rect;
            }
            passes += 1;
        });
        let (rect, input, actions) = out;
        if rect.is_positive() && rect != self.view_rect {
            self.view_rect = rect;
            self.report(&format!(
                "view area {} {} {} {}",
                rect.min.x.round(),
                rect.min.y.round(),
                rect.width().round(),
                rect.height().round()
            ));
        }
        if let Some(state) = &mut self.egui_state {
            state.handle_platform_output(&window, full.platform_output.clone());
        }
        self.apply_input(&input);
        for action in actions {
            self.act(action, event_loop);
        }
        let t0 = Instant::now();
        if let Err(e) = self.draw(&mut full) {
            self.report(&format!("error {e}"));
            self.session.error = Some(e.to_string());
        }
        self.session.frame_ms = t0.elapsed().as_secs_f64() * 1e3;
        let repaint = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.repaint_delay.is_zero());
        // A transition started by this frame's input runs from the next frame on; a hover
        // pick's answer is taken on a later frame.
        busy |= self.session.nav.as_ref().is_some_and(|n| n.animating());
        busy |= self.hover_pick.is_some();
        if busy || repaint || self.session.loading.is_some() {
            window.request_redraw();
        }
    }

    /// Camera gestures, hover picking and clicks.
    fn apply_input(&mut self, input: &ViewInput) {
        let height = f64::from(self.view_size().1);
        let aspect = self.aspect();
        if let Some(p) = input.drag_started {
            self.pivot = self.pick_at(p).map(|h| h.point);
        }
        // Hover picking costs a small pass and a readback: not while the camera moves (the
        // item under a moving cursor changes every frame), except for the zoom's own point,
        // which is waited for.
        let moving = input.orbit != egui::Vec2::ZERO
            || input.pan != egui::Vec2::ZERO
            || self.session.nav.as_ref().is_some_and(|n| n.animating());
        self.camera_moving = moving || input.zoom != 0.0;
        match input.hover {
            Some(p) if input.zoom != 0.0 => {
                self.session.hover = self.pick_at(p);
                self.hovered_at = Some(p);
                self.hover_pick = None;
            }
            Some(p) if !moving => {
                let asked = self.hover_pick.as_ref().map(|(q, _)| *q);
                if self.hovered_at != Some(p) && asked != Some(p) {
                    self.hover_pick = self.request_pick_at(p).map(|pending| (p, pending));
                }
            }
            _ => {
                self.session.hover = None;
                self.hovered_at = None;
                self.hover_pick = None;
            }
        }
        self.take_hover_answer();
        // A click on a dimension's label selects the dimension (Delete removes it).
        let on_dimension = match (input.click, &self.session.nav) {
            (Some((p, _)), Some(nav)) if self.session.tool.is_none() => {
                let local = p - self.view_rect.min;
                cadre_render::dimensions::hit(
                    &self.session.dimensions(),
                    &nav.camera(),
                    (
                        (self.view_rect.width().round() as u32).max(1),
                        (self.view_rect.height().round() as u32).max(1),
                    ),
                    DIMENSION_TEXT,
                    glam::Vec2::new(local.x, local.y),
                )
            }
            _ => None,
        };
        if let Some(k) = on_dimension {
            self.session.selected_dimension = Some(k);
            self.session.selection.clear();
            self.report(&format!("selected dimension {k}"));
        } else if let Some((p, add)) = input.click {
            self.session.selected_dimension = None;
            let mut picked = self.pick_at(p);
            // Alt + click: the part the item belongs to.
            if input.part
                && let Some(p) = &mut picked
            {
                p.pick = cadre_render::Pick::Part {
                    instance: p.pick.instance(),
                };
            }
            let measured = self.session.measurements.len();
            self.session.clicked(picked, add);
            match picked {
                Some(p) => self.report(&format!("selected {:?}", p.pick)),
                None => self.report("selected nothing"),
            }
            if let Some(m) = self.session.measurements.get(measured) {
                self.report(&format!("measured {}", m.text));
            }
        }
        let Some(nav) = &mut self.session.nav else {
            return;
        };
        if input.orbit != egui::Vec2::ZERO {
            let pivot = self.pivot.unwrap_or(nav.target());
            nav.orbit(
                (f64::from(input.orbit.x), f64::from(input.orbit.y)),
                height,
                pivot,
            );
        }
        if input.pan != egui::Vec2::ZERO {
            nav.pan((f64::from(input.pan.x), f64::from(input.pan.y)), height);
        }
        if input.zoom != 0.0 {
            let point = self
                .session
                .hover
                .map(|h| h.point)
                .or_else(|| {
                    input.hover.map(|p| {
                        let width = height * aspect;
                        let p = p - self.view_rect.min.to_vec2();
                        let ndc = DVec2::new(
                            f64::from(p.x) / width * 2.0 - 1.0,
                            1.0 - f64::from(p.y) / height * 2.0,
                        );
                        nav.point_at_target_depth(ndc, aspect)
                    })
                })
                .unwrap_or(nav.target());
            nav.zoom_to(0.85f64.powf(f64::from(input.zoom)), point);
        }
    }

    /// What is under window pixel `p` (physical) of the last frame, with its world point,
    /// waiting for the GPU (clicks, drag pivots, the zoom's point).
    fn pick_at(&self, p: egui::Pos2) -> Option<Picked> {
        let gfx = self.gfx.as_ref()?;
        let window = self.request_pick_at(p)?.wait(&gfx.gpu).ok()?;
        self.picked_in(&window)
    }

    /// Asks the renderer what is under window pixel `p` (physical) of the last frame.
    fn request_pick_at(&self, p: egui::Pos2) -> Option<PendingPick> {
        let gfx = self.gfx.as_ref()?;
        let viewport = gfx.viewport.as_ref()?;
        let prepared = self.prepared.as_ref()?;
        let p = p - self.view_rect.min.to_vec2();
        if p.x < 0.0 || p.y < 0.0 {
            return None;
        }
        let (x, y) = (p.x as u32, p.y as u32);
        gfx.renderer
            .request_pick(&gfx.gpu, viewport, prepared, (x, y), PICK_RADIUS)
            .ok()
    }

    /// Takes the hover pick's answer if the GPU has given it.
    fn take_hover_answer(&mut self) {
        let (Some(gfx), Some((p, pending))) = (&self.gfx, &mut self.hover_pick) else {
            return;
        };
        let Some(answer) = pending.poll(&gfx.gpu) else {
            return;
        };
        let p = *p;
        self.hover_pick = None;
        self.session.hover = answer.ok().and_then(|w| self.picked_in(&w));
        self.hovered_at = Some(p);
    }

    /// The nearest item of a pick window (vertex, edge, then face) with its world point.
    fn picked_in(&self, window: &PickWindow) -> Option<Picked> {
        let gfx = self.gfx.as_ref()?;
        let viewport = gfx.viewport.as_ref()?;
        let nav = self.session.nav.as_ref()?;
        let hit = window.nearest(PICK_RADIUS as f32)?;
        let camera = nav.camera();
        let (w, h) = (f64::from(viewport.width), f64::from(viewport.height));
        let ndc = DVec2::new(
            (f64::from(hit.pixel.0) + 0.5) / w * 2.0 - 1.0,
            1.0 - (f64::from(hit.pixel.1) + 0.5) / h * 2.0,
        );
        let point = if hit.depth > 0.0 {
            unproject(&camera, w / h, ndc, f64::from(hit.depth))
        } else {
            nav.point_at_target_depth(ndc, w / h)
        };
        let point = self
            .session
            .doc
            .as_ref()
            .and_then(|d| crate::inspect::vertex_position(d, hit.pick))
            .unwrap_or(point);
        Some(Picked {
            pick: hit.pick,
            point,
        })
    }

    fn act(&mut self, action: Action, event_loop: &ActiveEventLoop) {
        let aspect = self.aspect();
        match action {
            Action::Open(path) => self.open(path),
            Action::Quit => event_loop.exit(),
            Action::Preset(preset) => {
                if let Some(nav) = &mut self.session.nav {
                    nav.view_preset(preset, aspect);
                    self.report(&format!("view {preset:?}"));
                }
            }
            Action::FitAll => {
                if let (Some(nav), Some((lo, hi))) = (
                    &mut self.session.nav,
                    self.session.doc.as_ref().and_then(|d| d.bounds),
                ) {
                    nav.fit(lo, hi, aspect);
                }
            }
            Action::FitSelection => {
                let Some(doc) = &self.session.doc else { return };
                let boxes = self.session.selection.iter().filter_map(|p| match p.pick {
                    cadre_render::Pick::Face { instance, face } => doc
                        .face(face)
                        .and_then(|f| doc.face_bounds(instance as usize, f)),
                    other => doc.instance_bounds(other.instance() as usize),
                });
                let bounds = crate::document::bounds_of(boxes.flat_map(|(a, b)| [a, b]));
                if let (Some(nav), Some((lo, hi))) = (&mut self.session.nav, bounds.or(doc.bounds))
                {
                    nav.fit(lo, hi, aspect);
                }
            }
            Action::Screenshot {
                width,
                height,
                path,
            } => {
                let (width, height, path) = if path.as_os_str().is_empty() {
                    // F12: the 3D view's size (or the asked one) and a numbered file.
                    let (w, h) = if width == 0 {
                        self.view_size()
                    } else {
                        (width, height)
                    };
                    self.screenshots += 1;
                    let dir = self.options.screenshot_dir.clone().unwrap_or_default();
                    (
                        w,
                        h,
                        dir.join(format!("screenshot-{}.png", self.screenshots)),
                    )
                } else {
                    (width, height, path)
                };
                match self.screenshot(width, height, &path) {
                    Ok(()) => {
                        self.session.status = format!("wrote {}", path.display());
                        self.report(&format!("screenshot {}", path.display()));
                    }
                    Err(e) => {
                        self.report(&format!("error screenshot: {e}"));
                        self.session.error = Some(format!("screenshot: {e}"));
                    }
                }
            }
        }
    }

    /// Renders the view offscreen at `width` × `height` (any size the GPU allows, larger than
    /// the window too) and writes it as PNG.
    fn screenshot(&self, width: u32, height: u32, path: &Path) -> Result<(), String> {
        let gfx = self.gfx.as_ref().ok_or("no window")?;
        let prepared = self.prepared.as_ref().ok_or("no model")?;
        let nav = self.session.nav.as_ref().ok_or("no model")?;
        let options = FrameOptions {
            width,
            height,
            supersample: if u64::from(width) * u64::from(height) > 16_000_000 {
                1
            } else {
                2
            },
            mode: self.session.mode,
            shadows: self.session.shadows,
            backdrop: self.session.backdrop().0,
            grid: self.session.backdrop().1,
            ..FrameOptions::default()
        };
        // The window's framing at the screenshot's aspect.
        let camera = nav.camera();
        let mut state = self.session.view_state();
        state.hover = None;
        if let (Some(drawn), Some(toolpath)) = (&self.drawn_toolpath, &self.session.toolpath) {
            drawn.show_tool(&mut state, prepared, toolpath.simulate);
        }
        let image = gfx
            .renderer
            .render(&gfx.gpu, prepared, &camera, &options, &state)
            .map_err(|e| e.to_string())?;
        image
            .save(path)
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Draws the 3D view and the interface into the window.
    fn draw(&mut self, full: &mut egui::FullOutput) -> Result<(), ViewerError> {
        let Some(gfx) = &mut self.gfx else {
            full.textures_delta.clear();
            return Ok(());
        };
        // egui's textures first: they must reach the GPU even when no frame is drawn.
        let mut textures = std::mem::take(&mut full.textures_delta);
        for (id, deltas) in &textures.set {
            for delta in deltas {
                gfx.egui_renderer
                    .update_texture(&gfx.gpu.device, &gfx.gpu.queue, *id, delta);
            }
        }
        let frame = match gfx.surface.get_current_texture() {
            cadre_render::wgpu::CurrentSurfaceTexture::Success(f)
            | cadre_render::wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            _ => {
                for id in &textures.free {
                    gfx.egui_renderer.free_texture(id);
                }
                textures.clear();
                gfx.surface.configure(&gfx.gpu.device, &gfx.config);
                return Ok(());
            }
        };
        let view = frame.texture.create_view(&Default::default());
        // The faces' method changed, a model or toolpath opened, or the PMI shown changed:
        // the scene is prepared again, with or without trims, with the toolpath and the PMI.
        if (self.session.show_pmi, self.session.pmi_view) != self.drawn_pmi
            || (
                self.session.measurements.len(),
                self.session.selected_dimension,
            ) != self.drawn_dimensions
        {
            self.scene_stale = true;
        }
        if self.session.exact_faces != self.prepared_exact || self.scene_stale {
            self.scene_stale = false;
            self.prepared_exact = self.session.exact_faces;
            let rows = (self.view_rect.height().round() as u32).max(1);
            let view_height = self
                .session
                .nav
                .as_ref()
                .map_or(1.0, |n| n.camera().view_height());
            let base = match &self.session.doc {
                Some(doc) if self.session.exact_faces => {
                    let tolerance =
                        TRIM_TOLERANCE_RELATIVE * cadre_mesh::deflection_diagonal(&doc.model);
                    doc.scene.clone().with_trims(&doc.model, tolerance)
                }
                Some(doc) => doc.scene.clone(),
                None => cadre_render::RenderScene::default(),
            };
            let mut scene = match &self.session.toolpath {
                Some(toolpath) => {
                    let (scene, drawn) =
                        crate::toolpath_view::add_toolpath(base, toolpath, (view_height, rows));
                    self.drawn_toolpath = Some(drawn);
                    scene
                }
                None => {
                    self.drawn_toolpath = None;
                    base
                }
            };
            // The PMI and the dimensions over it (their lines whole: the toolpath's
            // simulation does not cut them).
            self.drawn_pmi = (self.session.show_pmi, self.session.pmi_view);
            self.drawn_dimensions = (
                self.session.measurements.len(),
                self.session.selected_dimension,
            );
            let mut extra = cadre_render::LineSet::default();
            if let Some(overlay) = self.session.pmi_overlay(VIEW_BACKGROUND) {
                extra.extend(overlay.lines);
                scene.labels.extend(overlay.labels);
            }
            let (lines, labels) = cadre_render::dimensions::overlay(
                &self.session.dimensions(),
                DIMENSION_TEXT,
                self.session.selected_dimension,
            );
            extra.extend(lines);
            scene.labels.extend(labels);
            if let Some(drawn) = &mut self.drawn_toolpath {
                drawn.extra = extra.clone();
            }
            scene.lines.extend(extra);
            self.scene_labels = scene.labels.clone();
            self.callouts_for = None;
            self.prepared = Some(gfx.renderer.prepare(&gfx.gpu, &scene));
            if let Some(trim) = &scene.trim {
                let line = format!(
                    "exact faces {} of {} ({} from their meshes)",
                    trim.drawn(),
                    trim.faces.len(),
                    trim.fallback.len()
                );
                if self.options.report {
                    println!("{line}");
                }
                tracing::info!("{line}");
            }
        }
        // The toolpath follows the zoom, its colours and the simulation.
        if let (Some(drawn), Some(toolpath), Some(prepared), Some(nav)) = (
            &mut self.drawn_toolpath,
            &self.session.toolpath,
            &mut self.prepared,
            &self.session.nav,
        ) {
            if (drawn.diameter - toolpath.tool_diameter.max(1e-3)).abs() > 1e-9 {
                self.scene_stale = true;
            }
            let rows = (self.view_rect.height().round() as u32).max(1);
            drawn.update(
                (&gfx.gpu, &gfx.renderer),
                prepared,
                toolpath,
                (nav.camera().view_height(), rows),
            );
        }
        // The callouts (part names, generated PMI), laid out again when the view has settled
        // somewhere new (while it moves they ride on their points).
        if let (Some(prepared), Some(nav)) = (&mut self.prepared, &self.session.nav) {
            let size = (
                (self.view_rect.width().round() as u32).max(1),
                (self.view_rect.height().round() as u32).max(1),
            );
            let camera = nav.camera();
            let settled = !self.camera_moving && !nav.animating();
            let wanted = self.session.wants_callouts().then_some((camera, size));
            let stale = match (&self.callouts_for, &wanted) {
                (None, None) => false,
                (Some(_), None) => true,
                (None, Some(_)) => settled,
                (Some(old), Some(new)) => settled && old != new,
            };
            if stale {
                let mut labels = self.scene_labels.clone();
                let callouts = self.session.view_callouts(&camera, size);
                if callouts.omitted > 0 {
                    self.session.status = format!(
                        "{} callout(s) left out: no room beside the model at this size",
                        callouts.omitted
                    );
                }
                labels.extend(callouts.labels);
                gfx.renderer.replace_labels(&gfx.gpu, prepared, &labels);
                self.callouts_for = wanted;
            }
        }
        let (w, h) = (gfx.config.width, gfx.config.height);
        let (vw, vh) = (
            (self.view_rect.width().round() as u32).clamp(1, gfx.gpu.max_side()),
            (self.view_rect.height().round() as u32).clamp(1, gfx.gpu.max_side()),
        );
        ensure_view_texture(gfx, (vw, vh));
        let viewport = match gfx.viewport.take() {
            Some(v) => v.resized(&gfx.gpu, vw, vh)?,
            None => Viewport::new(&gfx.gpu, vw, vh),
        };
        let mut viewport = viewport;
        let options = FrameOptions {
            width: vw,
            height: vh,
            supersample: 1,
            mode: self.session.mode,
            background: VIEW_BACKGROUND,
            backdrop: self.session.backdrop().0,
            grid: self.session.backdrop().1,
            cracks: CrackOptions {
                mode: if self.camera_moving {
                    CrackMode::Fast
                } else {
                    CrackMode::Exact
                },
                silhouettes: self.session.silhouette_fill && !self.camera_moving,
                ..CrackOptions::default()
            },
            shadows: self.session.shadows,
            ..FrameOptions::default()
        };
        if let (Some(prepared), Some(nav), Some(target)) =
            (&self.prepared, &self.session.nav, &gfx.view)
        {
            let mut state = self.session.view_state();
            if let (Some(drawn), Some(toolpath)) = (&self.drawn_toolpath, &self.session.toolpath) {
                drawn.show_tool(&mut state, prepared, toolpath.simulate);
            }
            gfx.renderer.draw(
                &gfx.gpu,
                &mut viewport,
                prepared,
                &nav.camera(),
                &options,
                &state,
                &target.view,
            )?;
        }
        gfx.viewport = Some(viewport);
        // The interface, with the 3D view as its central image.
        let device = &gfx.gpu.device;
        let queue = &gfx.gpu.queue;
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [w, h],
            pixels_per_point: full.pixels_per_point,
        };
        let jobs = self
            .egui_ctx
            .tessellate(full.shapes.clone(), full.pixels_per_point);
        let mut encoder = device.create_command_encoder(&Default::default());
        let extra = gfx
            .egui_renderer
            .update_buffers(device, queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&cadre_render::wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(cadre_render::wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: cadre_render::wgpu::Operations {
                        load: cadre_render::wgpu::LoadOp::Clear(cadre_render::wgpu::Color {
                            r: 0.85,
                            g: 0.86,
                            b: 0.88,
                            a: 1.0,
                        }),
                        store: cadre_render::wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
            gfx.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        for id in &textures.free {
            gfx.egui_renderer.free_texture(id);
        }
        textures.clear();
        queue.present(frame);
        Ok(())
    }

    /// Reads the 3D mouse (connecting to spacenavd now and then); `true` when it moved.
    fn poll_spacemouse(&mut self) -> bool {
        if self.spacenav.is_none() && Instant::now() >= self.spacenav_retry {
            self.spacenav_retry = Instant::now() + std::time::Duration::from_secs(5);
            if let Ok(s) = SpaceNav::connect() {
                self.report(&format!("spacemouse {}", s.socket_path().display()));
                self.session.spacemouse = Some("3D mouse".into());
                self.spacenav = Some(s);
            }
        }
        let Some(spacenav) = &mut self.spacenav else {
            return false;
        };
        let events = match spacenav.poll() {
            Ok(e) => e,
            Err(_) => {
                self.spacenav = None;
                self.session.spacemouse = None;
                return false;
            }
        };
        let settings = NavSettings::default();
        let mut moved = false;
        let aspect = self.aspect();
        for event in events {
            match event {
                SpaceEvent::Button {
                    number,
                    pressed: true,
                } => {
                    // Button 0 fits the model, button 1 goes to the iso view (the usual
                    // SpaceMouse "Fit" and "View" buttons).
                    let action = if number == 0 {
                        Action::FitAll
                    } else {
                        Action::Preset(cadre_render::ViewPreset::Iso)
                    };
                    if let Some(nav) = &mut self.session.nav {
                        match action {
                            Action::Preset(p) => nav.view_preset(p, aspect),
                            _ => {
                                if let Some((lo, hi)) =
                                    self.session.doc.as_ref().and_then(|d| d.bounds)
                                {
                                    nav.fit(lo, hi, aspect);
                                }
                            }
                        }
                    }
                    self.report(&format!("spacemouse button {number}"));
                    moved = true;
                }
                other => {
                    if let (Some(delta), Some(nav)) =
                        (other.navigation_delta(&settings), &mut self.session.nav)
                        && !delta.is_zero()
                    {
                        nav.spacemouse(delta.translate, delta.rotate);
                        moved = true;
                    }
                }
            }
        }
        moved
    }
}

/// Makes the 3D view's texture `size` (re-registered with egui under the same id).
fn ensure_view_texture(gfx: &mut Gfx, size: (u32, u32)) {
    if gfx.view.as_ref().is_some_and(|v| v.size == size) {
        return;
    }
    let texture = gfx
        .gpu
        .device
        .create_texture(&cadre_render::wgpu::TextureDescriptor {
            label: Some("3d view"),
            size: cadre_render::wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: cadre_render::wgpu::TextureDimension::D2,
            format: VIEW_FORMAT,
            usage: cadre_render::wgpu::TextureUsages::RENDER_ATTACHMENT
                | cadre_render::wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[cadre_render::wgpu::TextureFormat::Rgba8Unorm],
        });
    let view = texture.create_view(&Default::default());
    // egui reads its textures' bytes as gamma-encoded values: it gets a plain view of the
    // sRGB bytes the renderer wrote (an sRGB view would decode them once too often).
    let egui_view = texture.create_view(&cadre_render::wgpu::TextureViewDescriptor {
        format: Some(cadre_render::wgpu::TextureFormat::Rgba8Unorm),
        ..Default::default()
    });
    let filter = cadre_render::wgpu::FilterMode::Nearest;
    let id = match &gfx.view {
        Some(old) => {
            gfx.egui_renderer.update_egui_texture_from_wgpu_texture(
                &gfx.gpu.device,
                &egui_view,
                filter,
                old.id,
            );
            old.id
        }
        None => gfx
            .egui_renderer
            .register_native_texture(&gfx.gpu.device, &egui_view, filter),
    };
    gfx.view = Some(ViewTexture { view, id, size });
}

/// The world point at normalised device coordinates `ndc` and reverse-Z `depth`.
pub(crate) fn unproject(
    camera: &cadre_render::Camera,
    aspect: f64,
    ndc: DVec2,
    depth: f64,
) -> DVec3 {
    let inverse = (camera.projection_matrix(aspect) * camera.view_rotation()).inverse();
    let p = inverse * DVec4::new(ndc.x, ndc.y, depth, 1.0);
    camera.eye + p.truncate() / p.w
}

impl ApplicationHandler<UserEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        if let Err(e) = self.create_gfx(event_loop) {
            self.error = Some(e);
            event_loop.exit();
            return;
        }
        if let Some(file) = self.options.file.clone() {
            self.open(file);
        }
        if let Some(program) = self.options.toolpath.clone() {
            self.open(program);
        }
    }

    fn user_event(&mut self, _event_loop: &ActiveEventLoop, event: UserEvent) {
        match event {
            UserEvent::Progress(path, stage) => self.session.loading = Some((path, stage)),
            UserEvent::Loaded(result) => {
                self.session.loading = None;
                match *result {
                    Ok(doc) => {
                        // A hover asked of the last model answers about it.
                        self.hover_pick = None;
                        self.hovered_at = None;
                        if let Some(gfx) = &self.gfx {
                            self.scene_stale = true;
                            self.prepared_exact = false;
                            self.session.exact_faces = false;
                            gfx.window.set_title(&format!("{} — cadre", doc.title()));
                        }
                        self.report(&format!(
                            "loaded {} {} instances {} warnings",
                            doc.path.display(),
                            doc.instances.len(),
                            doc.warnings.len()
                        ));
                        let aspect = self.aspect();
                        self.session.set_document(doc, aspect);
                    }
                    Err(e) => {
                        self.report(&format!("error {e}"));
                        self.session.error = Some(e.to_string());
                    }
                }
            }
        }
        if let Some(gfx) = &self.gfx {
            gfx.window.request_redraw();
        }
    }

    /// Between events: the 3D mouse is read every few milliseconds (spacenavd's socket is
    /// not one of winit's event sources), a frame drawn only when it moved.
    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.poll_spacemouse()
            && let Some(gfx) = &self.gfx
        {
            gfx.window.request_redraw();
        }
        let wait = if self.spacenav.is_some() {
            std::time::Duration::from_millis(8)
        } else {
            // Look for a daemon now and then.
            std::time::Duration::from_secs(1)
        };
        event_loop.set_control_flow(winit::event_loop::ControlFlow::WaitUntil(
            Instant::now() + wait,
        ));
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = &self.gfx else { return };
        let window = gfx.window.clone();
        // egui asks a repaint for every redraw too: that would draw forever.
        if let Some(state) = &mut self.egui_state
            && !matches!(event, WindowEvent::RedrawRequested)
        {
            let response = state.on_window_event(&window, &event);
            if response.repaint {
                window.request_redraw();
            }
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(gfx) = &mut self.gfx
                    && size.width > 0
                    && size.height > 0
                {
                    gfx.config.width = size.width;
                    gfx.config.height = size.height;
                    gfx.surface.configure(&gfx.gpu.device, &gfx.config);
                }
                window.request_redraw();
            }
            WindowEvent::DroppedFile(path) => self.open(path),
            WindowEvent::RedrawRequested => self.frame(event_loop),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_render::{Camera, ViewPreset};

    #[test]
    fn unprojecting_a_projected_point_gives_it_back() {
        let cam = Camera::fit(
            DVec3::new(1e6, -2.0, 3.0),
            DVec3::new(1e6 + 10.0, 8.0, 13.0),
            ViewPreset::Iso,
            false,
            1.5,
        );
        let p = DVec3::new(1e6 + 4.0, 3.0, 7.0);
        let m = cam.projection_matrix(1.5) * cam.view_rotation();
        let q = m.project_point3(p - cam.eye);
        let back = unproject(&cam, 1.5, q.truncate(), q.z);
        assert!((back - p).length() < 1e-6, "{back} vs {p}");
    }
}
