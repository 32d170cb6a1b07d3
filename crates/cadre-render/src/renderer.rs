//! A frame: the passes in order, into offscreen targets, read back as an image.

use image::RgbaImage;

use crate::frame_buffers::{BindCache, FrameBuffers};
use crate::gpu_scene::{FrameScene, PreparedScene};
use crate::layout::{
    EDGES_ALL, EDGES_VISIBLE, FrameUniform, LightGpu, LightRig, MAX_LIGHTS,
    PROJECTION_ORTHOGRAPHIC, PROJECTION_PERSPECTIVE,
};
use crate::passes::cracks::{CrackCounts, CrackMode, CrackOptions, CrackPass};
use crate::passes::edges::EdgesPass;
use crate::passes::instances::InstanceLayout;
use crate::passes::lines::{GpuLines, LinesPass};
use crate::passes::pick::PickPass;
use crate::passes::shade::{COLOUR, ShadeInputs, ShadePass, ShadeVariant};
use crate::passes::text::{GpuText, TextPass};
use crate::passes::visibility::{Phase, VisibilityPass, VisibilityTargets};
use crate::view::{MAX_HIGHLIGHTED, MAX_SECTIONS, ViewState};
use crate::viewport::{LastFrame, Viewport};
use crate::{Camera, Gpu, Light, LineView, RenderError, RenderScene};

/// How faces and edges are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DisplayMode {
    /// Shaded faces.
    Shaded,
    /// Shaded faces and their visible B-Rep edges.
    ShadedEdges,
    /// Every B-Rep edge, no faces.
    Wireframe,
    /// Visible edges solid, hidden edges dashed, faces filled with the background.
    HiddenLine,
    /// See-through faces (more opaque seen edge-on) and every edge.
    XRay,
}

impl DisplayMode {
    /// Parses `shaded`, `shaded-edges`, `wireframe`, `hidden-line` or `xray`.
    pub fn from_name(name: &str) -> Option<DisplayMode> {
        Some(match name.to_ascii_lowercase().as_str() {
            "shaded" => DisplayMode::Shaded,
            "shaded-edges" | "shaded_edges" => DisplayMode::ShadedEdges,
            "wireframe" => DisplayMode::Wireframe,
            "hidden-line" | "hidden_line" | "hlr" => DisplayMode::HiddenLine,
            "xray" | "x-ray" => DisplayMode::XRay,
            _ => return None,
        })
    }

    /// Face fill (`FILL_*`) and edge mode (`EDGES_*`, `None` for no edges), the lanes 1 and 2
    /// of [`FrameUniform::modes`].
    fn fill_and_edges(self) -> (u32, Option<u32>) {
        use crate::layout::EDGES_HIDDEN_DASHED;
        use crate::layout::{FILL_BACKGROUND, FILL_NONE, FILL_SHADED};
        match self {
            DisplayMode::Shaded => (FILL_SHADED, None),
            DisplayMode::ShadedEdges => (FILL_SHADED, Some(EDGES_VISIBLE)),
            DisplayMode::Wireframe => (FILL_NONE, Some(EDGES_ALL)),
            DisplayMode::HiddenLine => (FILL_BACKGROUND, Some(EDGES_HIDDEN_DASHED)),
            DisplayMode::XRay => (FILL_NONE, Some(EDGES_ALL)),
        }
    }
}

/// What to render: image size, anti-aliasing, background, display mode, lights.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameOptions {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Supersampling factor per side (1 = none; 2 renders 4 samples per pixel and averages
    /// them in linear light).
    pub supersample: u32,
    /// Smooth the image's jagged edges after the readback (and after downsampling), FXAA
    /// style ([`crate::smooth_edges`]): anti-aliasing at the cost of one pass over the
    /// image on the CPU, for CPU adapters where supersampling multiplies every pass's cost.
    pub smooth: bool,
    /// Anti-alias the edges of faces trimmed per pixel by their analytic coverage (the
    /// distance to the trim boundary in pixels, F / |∇F|): a pixel on such an edge is
    /// blended with what its neighbours across the edge show. Beside supersampling and
    /// smoothing, not instead; off, trimmed edges are as sharp as the trim test.
    pub analytic_coverage: bool,
    /// Background colour, sRGB components in [0, 1] and alpha: the solid background, and
    /// what hidden-line drawings fill faces with.
    pub background: [f32; 4],
    /// The background behind the model: solid (`background`), a gradient or an image.
    pub backdrop: crate::Background,
    /// A ground grid under the model, when asked.
    pub grid: Option<crate::GroundGrid>,
    /// Display mode.
    pub mode: DisplayMode,
    /// Edge width in output pixels.
    pub edge_width: f32,
    /// Lights (ambient light from the environment comes on top); the first
    /// [`crate::layout::MAX_LIGHTS`] are lit, the rest left out with a warning.
    pub lights: Vec<Light>,
    /// How the cracks between faces drawn by the trim back-end are closed (exact by
    /// default; frames without trimmed faces have none).
    pub cracks: CrackOptions,
    /// The first light (the key light) casts shadows, from a shadow map every back-end
    /// writes ([`crate::shadows`]); off by default (CAD views are read without them).
    pub shadows: bool,
}

impl Default for FrameOptions {
    /// 800 × 600, 2× supersampling, white background.
    fn default() -> Self {
        FrameOptions {
            width: 800,
            height: 600,
            supersample: 2,
            smooth: false,
            analytic_coverage: true,
            background: [1.0, 1.0, 1.0, 1.0],
            backdrop: crate::Background::Solid,
            grid: None,
            mode: DisplayMode::Shaded,
            edge_width: 1.5,
            lights: Light::cad_rig(),
            cracks: CrackOptions::default(),
            shadows: false,
        }
    }
}

/// The renderer: pipelines built once, frames rendered on demand.
pub struct Renderer {
    visibility: VisibilityPass,
    shade: ShadePass,
    edges: EdgesPass,
    pub(crate) pick: PickPass,
    /// Bind group 1 of the passes that draw instances.
    pub(crate) instances: InstanceLayout,
    /// Format of the colour target the pipelines write.
    colour: wgpu::TextureFormat,
    /// The analytic back-end writes its proxies' depth, not the hits' (a wrong depth, for
    /// the tests' negative control).
    proxy_depth: bool,
    /// Tessellated surfaces keep their interpolated normals where those face away from the
    /// eye across a silhouette (texel.wgsl's `surface_facing`), and the trim back-end the
    /// faces of closed solids seen from inside (trim.wgsl's `hidden_inside`): for the tests'
    /// negative control.
    raw_silhouettes: bool,
    /// Bind groups kept between frames while their resources stay.
    binds: BindCache,
    /// Per-stage GPU timings of each frame ([`Renderer::with_pass_timings`]).
    timer: Option<crate::pass_timer::PassTimer>,
    /// The crack pass, built on the first frame that closes cracks; `None` inside where the
    /// adapter cannot run it (no compute, or fragment shaders that cannot write storage).
    cracks: std::sync::OnceLock<CrackPass>,
    /// Whether the adapter runs the crack pass (compute shaders, storage written by
    /// fragment shaders), and its exact fill (enough storage buffers a stage).
    crack_support: (bool, bool),
    /// The lines pass, built on the first frame with lines.
    lines: std::sync::OnceLock<LinesPass>,
    /// The text pass, built on the first frame with labels.
    text: std::sync::OnceLock<TextPass>,
    /// The backdrop pass, built on the first frame with a gradient, an image or a grid.
    backdrop: std::sync::OnceLock<crate::passes::backdrop::BackdropPass>,
}

impl Renderer {
    /// Builds the passes' pipelines on `gpu` for offscreen images; an adapter that cannot run
    /// them gives an error, not a panic.
    pub fn new(gpu: &Gpu) -> Result<Renderer, RenderError> {
        Renderer::for_format(gpu, COLOUR)
    }

    /// Builds the pipelines for a colour target of `format` (a window surface's, typically
    /// `Bgra8UnormSrgb`; an sRGB format gives correct output, the shading is linear).
    pub fn for_format(gpu: &Gpu, format: wgpu::TextureFormat) -> Result<Renderer, RenderError> {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let instances = InstanceLayout::new(&gpu.device, gpu.compute);
        let renderer = Renderer {
            visibility: VisibilityPass::new(&gpu.device, format, &instances, gpu.compute),
            shade: ShadePass::new(&gpu.device, format, gpu.read_only_depth),
            edges: EdgesPass::new(gpu, format, &instances),
            pick: PickPass::new(&gpu.device, &instances),
            instances,
            colour: format,
            proxy_depth: false,
            raw_silhouettes: false,
            binds: BindCache::default(),
            timer: None,
            cracks: std::sync::OnceLock::new(),
            crack_support: crack_support(gpu),
            lines: std::sync::OnceLock::new(),
            text: std::sync::OnceLock::new(),
            backdrop: std::sync::OnceLock::new(),
        };
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(RenderError::Gpu(e)),
            None => Ok(renderer),
        }
    }

    /// Uploads `scene`'s geometry (meshes and analytic primitives) once, for any number of
    /// frames ([`Renderer::draw`], [`Renderer::render`], [`Renderer::render_ids`]).
    pub fn prepare(&self, gpu: &Gpu, scene: &RenderScene) -> PreparedScene {
        self.prepare_with_flat_limit(gpu, scene, crate::FLAT_LIMIT)
    }

    /// Replaces the line set of a prepared scene (a toolpath sampled again for a new zoom)
    /// without uploading its surfaces again.
    pub fn replace_lines(&self, gpu: &Gpu, scene: &mut PreparedScene, lines: &crate::LineSet) {
        scene.lines = GpuLines::new(gpu, lines, !gpu.compute);
    }

    /// Replaces the labels of a prepared scene (laid out again) without uploading its
    /// surfaces again.
    pub fn replace_labels(&self, gpu: &Gpu, scene: &mut PreparedScene, labels: &crate::LabelSet) {
        scene.text = GpuText::new(gpu, labels);
    }

    /// This renderer timing each frame's stages on the GPU (timestamps between them, where
    /// the adapter writes them on command encoders; nothing is timed elsewhere): for the
    /// benchmarks, since reading the timings back waits for every frame.
    pub fn with_pass_timings(mut self, gpu: &Gpu) -> Renderer {
        self.timer = crate::pass_timer::PassTimer::new(gpu);
        self
    }

    /// The last frame's GPU time per stage in milliseconds, in the order drawn — `trim
    /// tessellation`, `visibility`, `shade` (edges, shading and overlays) — when
    /// [`Renderer::with_pass_timings`] found timestamps on the adapter; empty otherwise.
    pub fn last_pass_timings(&self) -> Vec<(&'static str, f64)> {
        self.timer.as_ref().map_or_else(Vec::new, |t| t.last())
    }

    /// This renderer with its analytic back-end writing each proxy's depth instead of the
    /// ray's hit: wrong wherever the proxy is not the surface. Only for the tests' negative
    /// control, which must see it disagree with the CPU ray caster.
    #[doc(hidden)]
    pub fn with_proxy_depth(mut self) -> Renderer {
        self.proxy_depth = true;
        self
    }

    /// This renderer with the tessellated surfaces' interpolated normals written as they
    /// are where they face away from the eye while their triangle faces it (across a
    /// silhouette), not mirrored into facing it: such pixels are lit as the far side of
    /// the surface; and with the trim back-end drawing the faces of closed solids seen
    /// from inside where no section asks for them (they show where the grids in front end
    /// short of their true silhouette). Only for the tests' negative control.
    #[doc(hidden)]
    pub fn with_raw_silhouettes(mut self) -> Renderer {
        self.raw_silhouettes = true;
        self
    }

    /// This renderer with the edges hidden behind their own closed solid drawn (`None`, then
    /// dropped by the depth test like any hidden edge) or dropped past another margin than
    /// the default: for the tests that check that dropping them changes no pixel, and its
    /// negative control.
    #[doc(hidden)]
    pub fn with_edge_culling_margin(mut self, margin: Option<f32>) -> Renderer {
        self.edges.set_behind_margin(margin);
        self
    }

    /// This renderer with the trim back-end's faces drawn over their whole (u, v) boxes,
    /// untrimmed: wrong wherever a face's box holds more than the face. Only for the tests'
    /// negative control, which must see it disagree with the CPU ray caster.
    #[doc(hidden)]
    pub fn without_trim_test(self, gpu: &Gpu) -> Renderer {
        self.with_trim_variant(gpu, (false, 256, true))
    }

    /// This renderer with the trim back-end's fragments trimmed or not (`trim_test`), its
    /// grids within `max_level` lines each way (256 by default; 1 leaves the geometry at its
    /// least), its grid points evaluated in compute or by the vertex shader (`grid_points`
    /// off): for the benchmarks that separate the back-end's costs and the tests of each way.
    #[doc(hidden)]
    pub fn with_trim_variant(
        mut self,
        gpu: &Gpu,
        (trim_test, max_level, grid_points): (bool, u32, bool),
    ) -> Renderer {
        let variant = crate::passes::visibility::trim::TrimVariant {
            trim_test,
            max_level,
            grid_points,
            ray_cast: false,
        };
        self.visibility
            .set_trim_variant(&gpu.device, &self.instances, variant);
        self
    }

    /// This renderer with the plane, cylinder, cone, sphere and ring torus faces of trimmed
    /// scenes ([`RenderScene::with_trims`]) ray cast against their support surface and trimmed at
    /// each hit (seed 001 applied to B-Rep faces: exact silhouettes at any zoom, no
    /// tessellation) instead of tessellated; the other faces take the trim back-end's way.
    /// `trim_test` off is the tests' negative control (every face over its whole (u, v) box).
    pub fn with_ray_cast_faces(mut self, gpu: &Gpu, trim_test: bool) -> Renderer {
        let variant = crate::passes::visibility::trim::TrimVariant {
            trim_test,
            ray_cast: true,
            ..Default::default()
        };
        self.visibility
            .set_trim_variant(&gpu.device, &self.instances, variant);
        self
    }

    /// Triangles the trimmed faces of the last frame drawn were tessellated into (every
    /// instance counted; 0 without trims): what the GPU chose for the screen-space error.
    /// Waits for the GPU.
    pub fn last_trim_triangles(&self, gpu: &Gpu) -> u64 {
        self.visibility.last_trim_triangles(&gpu.device, &gpu.queue)
    }

    /// What the last frame's crack pass did (zeros when no frame closed cracks). Waits for
    /// the GPU.
    pub fn last_crack_counts(&self, gpu: &Gpu) -> CrackCounts {
        self.cracks.get().map_or_else(CrackCounts::default, |c| {
            c.last_counts(&gpu.device, &gpu.queue)
        })
    }

    /// The crack mode a frame of `scene` with `options` runs: off where the trim back-end
    /// draws nothing or the adapter cannot run the pass, fast where it cannot run the
    /// exact fill.
    fn crack_mode(&self, scene: &PreparedScene, options: &FrameOptions) -> CrackMode {
        let (pass, exact) = self.crack_support;
        if !pass || !self.draws_trims() || scene.trim.is_none() {
            return CrackMode::Off;
        }
        match options.cracks.mode {
            CrackMode::Exact if !exact => CrackMode::Fast,
            mode => mode,
        }
    }

    /// Whether faces of scenes with trims ([`RenderScene::with_trims`]) are drawn from
    /// their exact surfaces here: the adapter runs compute shaders (otherwise their meshes
    /// draw them).
    pub fn draws_trims(&self) -> bool {
        self.visibility.draws_trims()
    }

    /// This renderer with every edge drawn as a quad (`None`), or with the visible-edges
    /// mode rasterized in compute where the adapter can for frames of at least `from`
    /// segments (by default 16,384): for the tests that compare the two paths.
    #[doc(hidden)]
    pub fn with_edge_raster(mut self, from: Option<u64>) -> Renderer {
        self.edges.set_raster(from);
        self
    }

    /// How many frames this renderer drew whose edges were rasterized in compute (for the
    /// tests that compare the paths).
    #[doc(hidden)]
    pub fn edge_rastered_frames(&self) -> usize {
        self.edges.rastered_frames()
    }

    /// [`Renderer::prepare`] with its placements factored past `flat_limit` instances
    /// instead of [`crate::FLAT_LIMIT`]: for tests that draw one scene both ways.
    #[doc(hidden)]
    pub fn prepare_with_flat_limit(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        flat_limit: usize,
    ) -> PreparedScene {
        let mut prepared = PreparedScene::new(
            &gpu.device,
            scene,
            flat_limit,
            self.visibility.draws_trims(),
        );
        prepared.lines = GpuLines::new(gpu, &scene.lines, !gpu.compute);
        prepared.text = GpuText::new(gpu, &scene.labels);
        prepared
    }

    /// Renders a prepared scene seen by `camera` in a view's state (colours, hidden parts,
    /// highlights, sections) into an sRGB image of the options' size: a thumbnail, an export,
    /// a viewer's screenshot at any size, independent of its window.
    pub fn render(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        camera: &Camera,
        options: &FrameOptions,
        state: &ViewState,
    ) -> Result<RgbaImage, RenderError> {
        let ss = options.supersample.clamp(1, 4);
        let (w, h) = (options.width * ss, options.height * ss);
        let frame = FrameInput {
            scene,
            camera,
            options,
            state,
            size: (w, h),
        };
        let mut pixels = self.run(gpu, &frame, Readback::Colour, None)?;
        if matches!(
            self.colour,
            wgpu::TextureFormat::Bgra8UnormSrgb | wgpu::TextureFormat::Bgra8Unorm
        ) {
            for px in pixels.chunks_exact_mut(4) {
                px.swap(0, 2);
            }
        }
        let got = pixels.len();
        let full = RgbaImage::from_raw(w, h, pixels).ok_or(RenderError::ReadbackSize {
            got,
            want: 4 * w as usize * h as usize,
        })?;
        let image = downsample(&full, ss);
        Ok(if options.smooth {
            crate::smooth::smooth_edges(&image)
        } else {
            image
        })
    }

    /// The bytes of the visibility target `readback` names after a frame of `scene` (no
    /// supersampling), row by row.
    fn read_back(
        &self,
        gpu: &Gpu,
        (scene, camera, options, state): (&PreparedScene, &Camera, &FrameOptions, &ViewState),
        readback: Readback,
    ) -> Result<Vec<u8>, RenderError> {
        let frame = FrameInput {
            scene,
            camera,
            options,
            state,
            size: (options.width, options.height),
        };
        self.run(gpu, &frame, readback, None)
    }

    /// The visibility buffer's ids at every pixel (no supersampling), row by row: face
    /// id, instance + 1 (0 = background), material index, depth (`f32` bits). Section caps
    /// carry [`crate::SECTION_CAP`] and their plane in the material channel
    /// ([`crate::section_cap`]) and the cap's own depth.
    pub fn render_ids(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        camera: &Camera,
        options: &FrameOptions,
        state: &ViewState,
    ) -> Result<Vec<[u32; 4]>, RenderError> {
        let bytes = self.read_back(gpu, (scene, camera, options, state), Readback::Ids)?;
        Ok(words4(&bytes))
    }

    /// The screen arc length (pixels of a `size` target) at every point of the scene's line
    /// set as the frame's scan computes it (on the GPU where the adapter has compute shaders),
    /// in the set's order; empty without lines. Only the first chunk of a set larger than a
    /// storage binding. For the tests that hold it against [`crate::lines::reference`].
    pub fn line_arc_lengths(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        camera: &Camera,
        size: (u32, u32),
    ) -> Result<Vec<f32>, RenderError> {
        let Some(lines) = &scene.lines else {
            return Ok(Vec::new());
        };
        let device = &gpu.device;
        let pass = self.lines.get_or_init(|| LinesPass::new(gpu, self.colour));
        let mut buffers = FrameBuffers::new(device);
        let frame = frame_uniform(
            camera,
            &FrameOptions {
                width: size.0,
                height: size.1,
                ..FrameOptions::default()
            },
            &ViewState::default(),
            size,
        );
        buffers.frame.write(gpu, bytemuck::bytes_of(&frame))?;
        let line_frame = lines.frame(camera, size, 1.0, &LineView::default());
        let mut encoder = device.create_command_encoder(&Default::default());
        pass.record_scan(
            gpu,
            &mut encoder,
            (buffers.frame.buffer(), lines),
            (camera, size, &line_frame),
        );
        let Some((buffer, count)) = LinesPass::copy_arc(device, &mut encoder, lines) else {
            return Ok(Vec::new());
        };
        gpu.queue.submit([encoder.finish()]);
        let bytes = map_read(gpu, &buffer)?;
        Ok(bytemuck::cast_slice(&bytes[..4 * count as usize]).to_vec())
    }

    /// The visibility buffer's (u, v) on the exact surface at every pixel (no supersampling),
    /// row by row; meaningful where [`Renderer::render_ids`] has a face.
    pub fn render_uv(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        camera: &Camera,
        options: &FrameOptions,
        state: &ViewState,
    ) -> Result<Vec<[f32; 2]>, RenderError> {
        let bytes = self.read_back(gpu, (scene, camera, options, state), Readback::Uv)?;
        let float = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        Ok(bytes
            .chunks_exact(8)
            .map(|p| [float(&p[0..4]), float(&p[4..8])])
            .collect())
    }

    /// The visibility buffer's view-space unit normals at every pixel (no supersampling), row
    /// by row, as the shade pass reads them (from their 10-bit octahedral map); meaningful
    /// where [`Renderer::render_ids`] has a face. View space looks down −z.
    pub fn render_normals(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        camera: &Camera,
        options: &FrameOptions,
        state: &ViewState,
    ) -> Result<Vec<[f32; 3]>, RenderError> {
        let bytes = self.read_back(gpu, (scene, camera, options, state), Readback::Normals)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|b| from_octahedral(u32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            .collect())
    }

    /// A viewer's frame: draws the prepared scene in `state` into `target` (a window
    /// surface's texture, or any texture of the caller's, of this renderer's format and of
    /// the viewport's size; no supersampling) and submits the work. The viewport keeps the frame's visibility buffer for
    /// [`Renderer::pick`] and reuses its targets while the size stays.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &self,
        gpu: &Gpu,
        viewport: &mut Viewport,
        scene: &PreparedScene,
        camera: &Camera,
        options: &FrameOptions,
        state: &ViewState,
        target: &wgpu::TextureView,
    ) -> Result<(), RenderError> {
        let frame = FrameInput {
            scene,
            camera,
            options,
            state,
            size: (viewport.width, viewport.height),
        };
        self.run(gpu, &frame, Readback::Into(target), Some(viewport))
            .map(drop)
    }

    /// Records and runs the passes and reads back the asked target; with a viewport, into
    /// its targets, which keep the frame for picking.
    fn run(
        &self,
        gpu: &Gpu,
        input: &FrameInput<'_>,
        readback: Readback<'_>,
        viewport: Option<&mut Viewport>,
    ) -> Result<Vec<u8>, RenderError> {
        let FrameInput {
            options,
            size: (w, h),
            ..
        } = *input;
        let max = gpu.max_side();
        if options.width == 0 || options.height == 0 || w == 0 || h == 0 || w > max || h > max {
            return Err(RenderError::Size {
                width: options.width,
                height: options.height,
                max: max * options.width.max(1) / w.max(1),
            });
        }
        // Validation errors become a RenderError instead of wgpu's default panic.
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = self.record_and_run(gpu, input, readback, viewport);
        // Bind groups this frame did not use go (one frame's worth is kept).
        self.binds.end_frame();
        let error = pollster::block_on(scope.pop());
        let bytes = result?;
        match error {
            Some(e) => Err(RenderError::Gpu(e)),
            None => Ok(bytes),
        }
    }

    /// [`Renderer::run`] inside its error scope.
    fn record_and_run(
        &self,
        gpu: &Gpu,
        input: &FrameInput<'_>,
        readback: Readback<'_>,
        mut viewport: Option<&mut Viewport>,
    ) -> Result<Vec<u8>, RenderError> {
        let FrameInput {
            scene,
            camera,
            options,
            state,
            size: (w, h),
        } = *input;
        let device = &gpu.device;
        // A viewer's frame writes into its viewport's kept buffers and draws into its kept
        // targets; an image, or a frame that reads the (u, v) back (which a viewport has no
        // target for), into fresh ones.
        // The exact crack fill's seeds are read from the (u, v) target.
        let crack_mode = self.crack_mode(scene, options);
        let seeds = crack_mode == CrackMode::Exact;
        let with_uv = matches!(readback, Readback::Uv) || seeds;
        let (mut fresh_buffers, fresh_targets);
        let (kept_targets, buffers) = match viewport.as_deref_mut() {
            Some(v) => {
                // A viewport keeps a (u, v) target from its first frame that seeds the
                // exact crack fill's solves.
                if seeds && v.targets.uv.is_none() {
                    v.targets = VisibilityTargets::new(device, (w, h), true);
                }
                (Some(&v.targets), &mut v.buffers)
            }
            None => {
                fresh_buffers = FrameBuffers::new(device);
                (None, &mut fresh_buffers)
            }
        };
        let targets = match kept_targets {
            Some(t) if !matches!(readback, Readback::Uv) => t,
            _ => {
                fresh_targets = VisibilityTargets::new(device, (w, h), with_uv);
                &fresh_targets
            }
        };
        let (_, edge_mode) = options.mode.fill_and_edges();
        let mut frame = frame_uniform(camera, options, state, (w, h));
        [frame.tolerances[2], frame.tolerances[3]] =
            crate::passes::cracks::tolerances(&options.cracks, scene.diagonal());
        frame.forward[3] = if options.cracks.silhouettes { 1.0 } else { 0.0 };
        frame.sky_up[3] = if self.raw_silhouettes { 1.0 } else { 0.0 };
        // Edges carry their coverage only where faces are trimmed per pixel, or quadrics ray
        // cast.
        let coverage = options.analytic_coverage
            && ((scene.trim.is_some() && self.draws_trims()) || scene.has_quadrics());
        frame.counts[3] = u32::from(coverage);
        let shadow = if options.shadows && readback.shaded() {
            self.shadow_map(gpu, scene, (camera, options, state))?
        } else {
            None
        };
        if let Some((_, matrix, params)) = &shadow {
            frame.shadow = *matrix;
            frame.shadow_params = *params;
        }
        buffers.frame.write(gpu, bytemuck::bytes_of(&frame))?;
        let with_edges = edge_mode.is_some() && readback.shaded();
        let frame_scene = FrameScene::new(
            gpu,
            (&self.instances, &self.binds),
            buffers,
            scene,
            (camera, state, f64::from(w) / f64::from(h)),
            with_edges,
        )?;
        let mut selection: Vec<[u32; 4]> = state
            .selection
            .iter()
            .take(MAX_HIGHLIGHTED)
            .map(|p| p.to_gpu())
            .collect();
        if selection.is_empty() {
            // Storage bindings may not be empty; the count stays 0.
            selection.push([0; 4]);
        }
        buffers
            .selection
            .write(gpu, bytemuck::cast_slice(&selection))?;
        let lights = light_rig(options, camera);
        buffers.lights.write(gpu, bytemuck::bytes_of(&lights))?;
        // Wire bodies are drawn in every mode; B-Rep edges only in the modes with edges.
        let draw_lines = readback.shaded() && !frame_scene.edge_calls.is_empty();
        let frame_buffer = buffers.frame.buffer();
        let mut encoder = device.create_command_encoder(&Default::default());
        let timer = self.timer.as_ref();
        if let Some(t) = timer {
            t.start(&mut encoder);
        }
        let sections = frame.counts[2] > 0;
        // The ids are left uncleared where only depth-tested passes and depth-aware picks
        // read them (`VisibilityTargets`' rule: ids count only where the depth is not 0):
        // on a CPU adapter, whose clears are memory traffic, with the read-only depth test
        // (not GL: there the shade pass reads every pixel's ids), and when neither section
        // caps (their outlines read neighbours' ids) nor an id readback need the background.
        let clear_ids =
            !(gpu.is_cpu() && gpu.read_only_depth) || sections || matches!(readback, Readback::Ids);
        self.visibility.record(
            (device, &self.binds),
            &mut encoder,
            targets,
            (
                frame_buffer,
                sections,
                self.proxy_depth,
                clear_ids,
                coverage,
            ),
            &frame_scene,
            timer,
        );
        if crack_mode != CrackMode::Off {
            let recorder = (device, &self.binds);
            let cracks = self.cracks.get_or_init(|| CrackPass::new(device));
            let crack_buffers = cracks.buffers(device, (w, h));
            if let Some(t) = timer {
                t.mark(&mut encoder, "visibility");
            }
            cracks.detect(
                recorder,
                &mut encoder,
                targets,
                frame_buffer,
                &crack_buffers,
            );
            if let Some(t) = timer {
                t.mark(&mut encoder, "crack detection");
            }
            let exact = crack_mode == CrackMode::Exact
                && self.visibility.record_crack_fill(
                    recorder,
                    &mut encoder,
                    (frame_buffer, sections),
                    &frame_scene,
                    &crack_buffers,
                    &mut |encoder| cracks.mask(recorder, encoder, frame_buffer, &crack_buffers),
                );
            if let Some(t) = timer
                && exact
            {
                t.mark(&mut encoder, "crack exact fill");
            }
            cracks.resolve(
                recorder,
                &mut encoder,
                targets,
                frame_buffer,
                &crack_buffers,
                (exact, options.cracks.highlight),
            );
        }
        let visibility_stage = if crack_mode == CrackMode::Off {
            "visibility"
        } else {
            "crack resolve"
        };
        let mark = |encoder: &mut wgpu::CommandEncoder, stage| {
            if let Some(t) = timer {
                t.mark(encoder, stage);
                t.resolve(encoder);
            }
        };
        // The lines' arc lengths for this view, before the passes that draw them.
        let lines = match (&scene.lines, readback.shaded()) {
            (Some(lines), true) => {
                let pass = self.lines.get_or_init(|| LinesPass::new(gpu, self.colour));
                let scale = w as f32 / options.width.max(1) as f32;
                let line_frame = lines.frame(camera, (w, h), scale, &state.lines);
                pass.record_scan(
                    gpu,
                    &mut encoder,
                    (frame_buffer, lines),
                    (camera, (w, h), &line_frame),
                );
                Some((pass, lines))
            }
            _ => None,
        };
        let backdrop = (readback.shaded()
            && (options.backdrop != crate::Background::Solid || options.grid.is_some()))
        .then(|| {
            let pass = self
                .backdrop
                .get_or_init(|| crate::passes::backdrop::BackdropPass::new(gpu, self.colour));
            let floor = scene.bounds().map_or(0.0, |(lo, _)| lo.z);
            let uniform = crate::passes::backdrop::uniform(
                camera,
                f64::from(w) / f64::from(h),
                (&options.backdrop, options.grid.as_ref()),
                floor,
            );
            (pass, uniform)
        });
        let text = match (&scene.text, readback.shaded()) {
            (Some(text), true) => {
                let pass = self.text.get_or_init(|| TextPass::new(gpu, self.colour));
                let scale = w as f32 / options.width.max(1) as f32;
                Some((pass, text, text.frame(camera, (w, h), scale)))
            }
            _ => None,
        };
        let shading = Shading {
            lines,
            text,
            backdrop,
            queue: &gpu.queue,
            device,
            options,
            targets,
            frame: frame_buffer,
            uniform: &frame,
            scene: &frame_scene,
            selection: buffers.selection.buffer(),
            lights: (buffers.lights.buffer(), &lights.lights),
            shadow: shadow.as_ref().map(|(targets, _, _)| &targets.depth),
            draw_lines,
        };
        let bytes = match readback {
            Readback::Ids => {
                mark(&mut encoder, visibility_stage);
                read_region(gpu, encoder, &targets.ids_texture, (0, 0), (w, h), 16)?
            }
            Readback::Uv => {
                mark(&mut encoder, visibility_stage);
                match &targets.uv {
                    Some((_, uv)) => read_region(gpu, encoder, uv, (0, 0), (w, h), 8)?,
                    None => Vec::new(),
                }
            }
            Readback::Normals => {
                mark(&mut encoder, visibility_stage);
                read_region(gpu, encoder, &targets.normal_texture, (0, 0), (w, h), 4)?
            }
            Readback::Into(view) => {
                if let Some(t) = timer {
                    t.mark(&mut encoder, visibility_stage);
                }
                self.shade_into(&shading, &mut encoder, view);
                mark(&mut encoder, "shade");
                gpu.queue.submit([encoder.finish()]);
                Vec::new()
            }
            Readback::Colour => {
                let colour = device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("colour"),
                    size: wgpu::Extent3d {
                        width: w,
                        height: h,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: self.colour,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                });
                let colour_view = colour.create_view(&Default::default());
                if let Some(t) = timer {
                    t.mark(&mut encoder, visibility_stage);
                }
                self.shade_into(&shading, &mut encoder, &colour_view);
                mark(&mut encoder, "shade");
                read_region(gpu, encoder, &colour, (0, 0), (w, h), 4)?
            }
        };
        // The frame has run (a readback waits for it; a viewer's frame is waited for here,
        // only when timed).
        if let Some(t) = timer {
            t.read(gpu);
        }
        if let Some(v) = viewport {
            let aspect = f64::from(w) / f64::from(h);
            v.last = Some(LastFrame {
                frame,
                view_proj: camera.projection_matrix(aspect) * camera.view_rotation(),
                pick_runs: frame_scene.pick_runs,
            });
        }
        Ok(bytes)
    }
}

/// The options' lights as the shade pass reads them (view space); past [`MAX_LIGHTS`] the
/// rest are left out, with a warning.
fn light_rig(options: &FrameOptions, camera: &Camera) -> LightRig {
    if options.lights.len() > MAX_LIGHTS {
        tracing::warn!(
            lights = options.lights.len(),
            lit = MAX_LIGHTS,
            "more lights than the shade pass lights: the first {MAX_LIGHTS} are lit"
        );
    }
    let mut rig = LightRig::default();
    for (gpu, light) in rig.lights.iter_mut().zip(&options.lights) {
        *gpu = light.to_gpu(camera);
    }
    rig
}

/// One frame's inputs.
#[derive(Clone, Copy)]
struct FrameInput<'a> {
    scene: &'a PreparedScene,
    camera: &'a Camera,
    options: &'a FrameOptions,
    state: &'a ViewState,
    /// Target size in pixels (supersampled for images).
    size: (u32, u32),
}

/// The options' background (sRGB colour, straight alpha) in linear light.
fn linear_background(options: &FrameOptions) -> [f32; 4] {
    let [r, g, b, a] = options.background;
    [srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), a]
}

/// The frame's uniform for a `w` × `h` target.
fn frame_uniform(
    camera: &Camera,
    options: &FrameOptions,
    state: &ViewState,
    (w, h): (u32, u32),
) -> FrameUniform {
    let aspect = f64::from(w) / f64::from(h);
    let (fill, edge_mode) = options.mode.fill_and_edges();
    // Output pixels → target pixels (supersampling).
    let scale = w as f32 / options.width.max(1) as f32;
    let rotation = glam::DMat3::from_mat4(camera.view_rotation());
    let (planes, plane_normals) = section_planes(camera, rotation, state);
    // View space looks down −z; the world direction is the rotation's inverse (transpose).
    let forward = rotation.transpose() * glam::DVec3::NEG_Z;
    FrameUniform {
        view_proj: camera.view_projection_f32(aspect).to_cols_array_2d(),
        inv_proj: camera
            .projection_matrix(aspect)
            .inverse()
            .as_mat4()
            .to_cols_array_2d(),
        background: linear_background(options),
        viewport: [
            w as f32,
            h as f32,
            options.edge_width.max(0.1) * scale,
            8.0 * scale,
        ],
        tolerances: [2e-3, 0.02, 0.0, 0.0],
        modes: [
            if camera.is_orthographic() {
                PROJECTION_ORTHOGRAPHIC
            } else {
                PROJECTION_PERSPECTIVE
            },
            fill,
            edge_mode.unwrap_or(EDGES_VISIBLE),
            // Outlines with the visible edges (not in wireframe, which shows edges only).
            u32::from(matches!(edge_mode, Some(m) if m != EDGES_ALL)),
        ],
        edge_colour: if options.mode == DisplayMode::XRay {
            [0.05, 0.07, 0.10, 0.6]
        } else {
            [0.02, 0.02, 0.025, 1.0]
        },
        hidden_colour: [0.25, 0.25, 0.27, 1.0],
        sky_up: (rotation * glam::DVec3::Z).as_vec3().extend(0.0).to_array(),
        counts: [
            options.lights.len().min(MAX_LIGHTS) as u32,
            state.selection.len().min(MAX_HIGHLIGHTED) as u32,
            state.sections.len().min(MAX_SECTIONS) as u32,
            0,
        ],
        hover: state.hover.map_or([0; 4], |p| p.to_gpu()),
        // Hover: a light cyan wash; selection: a stronger orange (the usual CAD pair).
        hover_colour: [0.30, 0.75, 1.0, 0.35],
        selection_colour: [1.0, 0.45, 0.05, 0.55],
        planes,
        plane_normals,
        forward: forward.as_vec3().extend(0.0).to_array(),
        // Hatch lines every 8 output pixels, 1 wide; cap outlines 1 wide.
        section: [8.0 * scale, scale, scale, 0.0],
        // No shadows unless the frame draws a shadow map (`Renderer::shadow_map`).
        shadow: [[0.0; 4]; 4],
        shadow_params: [0.0; 4],
    }
}

/// The first [`MAX_SECTIONS`] section planes of `state` as the shaders read them: relative to
/// the eye (unit normal, offset) and their normals in view space. The offset is moved to the
/// eye in `f64` before it becomes `f32`, so a plane through a part far from the origin stays
/// on it. A plane without a usable normal keeps everything (zero normal, offset 1), so the
/// others keep their indices.
fn section_planes(
    camera: &Camera,
    rotation: glam::DMat3,
    state: &ViewState,
) -> ([[f32; 4]; 3], [[f32; 4]; 3]) {
    let mut planes = [[0.0; 4]; MAX_SECTIONS];
    let mut normals = [[0.0; 4]; MAX_SECTIONS];
    for (i, plane) in state.sections.iter().take(MAX_SECTIONS).enumerate() {
        planes[i] = [0.0, 0.0, 0.0, 1.0];
        if let Some((n, offset)) = plane.normalised() {
            let relative = offset - n.dot(camera.eye);
            planes[i] = [n.x as f32, n.y as f32, n.z as f32, relative as f32];
            normals[i] = (rotation * n).as_vec3().extend(0.0).to_array();
        }
    }
    (planes, normals)
}

/// The unit vector of a normal target texel (`Rgb10a2Unorm`: its octahedral map in the red
/// and green channels), as common.wgsl's `from_octahedral` decodes it.
fn from_octahedral(texel: u32) -> [f32; 3] {
    let channel = |shift: u32| ((texel >> shift) & 0x3ff) as f32 / 1023.0;
    let (fx, fy) = (2.0 * channel(0) - 1.0, 2.0 * channel(10) - 1.0);
    let mut n = glam::Vec3::new(fx, fy, 1.0 - fx.abs() - fy.abs());
    let t = (-n.z).max(0.0);
    n.x += if n.x >= 0.0 { -t } else { t };
    n.y += if n.y >= 0.0 { -t } else { t };
    n.normalize_or_zero().to_array()
}

/// Little-endian `u32` quadruples.
fn words4(bytes: &[u8]) -> Vec<[u32; 4]> {
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    bytes
        .chunks_exact(16)
        .map(|p| {
            [
                word(&p[0..4]),
                word(&p[4..8]),
                word(&p[8..12]),
                word(&p[12..16]),
            ]
        })
        .collect()
}

/// Which target a frame reads back, or the caller's view it draws into.
#[derive(Clone, Copy, Debug)]
enum Readback<'a> {
    Colour,
    Ids,
    Uv,
    Normals,
    Into(&'a wgpu::TextureView),
}

impl Readback<'_> {
    /// Whether the frame is shaded (not only the visibility buffer).
    fn shaded(&self) -> bool {
        matches!(self, Readback::Colour | Readback::Into(_))
    }
}

/// What the shading passes of a frame read.
struct Shading<'a> {
    device: &'a wgpu::Device,
    options: &'a FrameOptions,
    targets: &'a VisibilityTargets,
    frame: &'a wgpu::Buffer,
    /// The frame buffer's content.
    uniform: &'a FrameUniform,
    scene: &'a FrameScene<'a>,
    selection: &'a wgpu::Buffer,
    /// The light buffer and the lights in it (the frame's count of them lit, the rest zero).
    lights: (&'a wgpu::Buffer, &'a [LightGpu]),
    draw_lines: bool,
    /// The lines pass and the scene's line set, when it has one (its scan recorded).
    lines: Option<(&'a LinesPass, &'a GpuLines)>,
    /// The text pass, the scene's laid-out labels and this frame's constants for them.
    text: Option<(&'a TextPass, &'a GpuText, crate::layout::TextFrame)>,
    /// The backdrop pass and its constants, when the frame has a gradient, an image or a
    /// grid; and the queue it uploads with.
    backdrop: Option<(
        &'a crate::passes::backdrop::BackdropPass,
        crate::layout::BackdropUniform,
    )>,
    queue: &'a wgpu::Queue,
    /// The key light's shadow map (its depth), when the frame has shadows.
    shadow: Option<&'a wgpu::TextureView>,
}

impl Renderer {
    /// The key light's shadow map for a frame of `scene` seen by `camera`: the visibility
    /// pass drawn from the light ([`crate::shadows::light_camera`]) into targets of its
    /// own, with buffers of its own, and submitted before the frame (so the frame's passes,
    /// which share the back-ends' per-frame buffers, run after it); its depth target and the
    /// frame's shadow terms. `None` without a light or anything to draw.
    #[allow(clippy::type_complexity)]
    fn shadow_map(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        (camera, options, state): (&Camera, &FrameOptions, &ViewState),
    ) -> Result<Option<(VisibilityTargets, [[f32; 4]; 4], [f32; 4])>, RenderError> {
        use crate::shadows::{SHADOW_MAP_SIZE, light_camera, shadow_terms};
        let (Some(bounds), Some(key)) = (scene.bounds(), options.lights.first()) else {
            return Ok(None);
        };
        let Some(light) = light_camera(key, camera, bounds) else {
            return Ok(None);
        };
        let device = &gpu.device;
        let size = (SHADOW_MAP_SIZE, SHADOW_MAP_SIZE);
        let mut buffers = FrameBuffers::new(device);
        let targets = VisibilityTargets::new(device, size, false);
        let frame = frame_uniform(&light, options, state, size);
        buffers.frame.write(gpu, bytemuck::bytes_of(&frame))?;
        let frame_scene = FrameScene::new(
            gpu,
            (&self.instances, &self.binds),
            &mut buffers,
            scene,
            (&light, state, 1.0),
            false,
        )?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.visibility.record(
            (device, &self.binds),
            &mut encoder,
            &targets,
            (
                buffers.frame.buffer(),
                frame.counts[2] > 0,
                self.proxy_depth,
                true,
                false,
            ),
            &frame_scene,
            None,
        );
        gpu.queue.submit([encoder.finish()]);
        let (matrix, params) = shadow_terms(camera, &light);
        Ok(Some((targets, matrix, params)))
    }

    /// Records the passes after the visibility pass (shade, see-through parts or x-ray,
    /// edges) into `colour_view`.
    fn shade_into(
        &self,
        s: &Shading<'_>,
        encoder: &mut wgpu::CommandEncoder,
        colour_view: &wgpu::TextureView,
    ) {
        let Shading {
            device,
            options,
            targets,
            frame,
            uniform,
            scene,
            selection,
            lights: (light_buffer, lights),
            draw_lines,
            shadow,
            lines,
            text,
            backdrop,
            queue,
        } = *s;
        let inputs = ShadeInputs {
            frame,
            materials: &scene.materials,
            lights: light_buffer,
            selection,
            background: {
                let [r, g, b, a] = linear_background(options).map(f64::from);
                wgpu::Color { r, g, b, a }
            },
            variant: ShadeVariant::of(uniform, lights),
            shadow,
        };
        let recorder = (device, &self.binds);
        self.shade
            .record(recorder, encoder, targets, &inputs, colour_view);
        if let Some((pass, uniform)) = &backdrop {
            pass.record(
                (device, queue),
                encoder,
                targets,
                (frame, uniform, &options.backdrop),
                colour_view,
            );
        }
        let phase = if options.mode == DisplayMode::XRay {
            Phase::XRay
        } else {
            Phase::Transparent
        };
        self.visibility.record_see_through(
            recorder,
            encoder,
            phase,
            (frame, scene),
            (targets, colour_view),
        );
        if draw_lines {
            self.edges.record(
                recorder,
                encoder,
                targets,
                (frame, selection),
                (scene, uniform),
                colour_view,
            );
        }
        if let Some((pass, set)) = lines {
            pass.record_draw(device, encoder, (frame, set), &targets.depth, colour_view);
        }
        if let Some((pass, set, text_frame)) = &text {
            pass.record(
                (device, queue),
                encoder,
                (frame, set, text_frame),
                &targets.depth,
                colour_view,
            );
        }
    }
}

/// Copies the `w` × `h` region of `texture` at `origin` (`bytes_per_pixel` wide texels) to
/// the CPU, rows unpadded.
pub(crate) fn read_region(
    gpu: &Gpu,
    mut encoder: wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    (x, y): (u32, u32),
    (w, h): (u32, u32),
    bytes_per_pixel: u32,
) -> Result<Vec<u8>, RenderError> {
    let row = w * bytes_per_pixel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded) * u64::from(h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x, y, z: 0 },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([encoder.finish()]);
    let mapped = map_read(gpu, &buffer)?;
    let mut out = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        out.extend_from_slice(&mapped[start..start + row as usize]);
    }
    Ok(out)
}

/// The content of a `MAP_READ` buffer once the queue's work on it is done.
fn map_read(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RenderError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer
        .slice(..)
        .map_async(wgpu::MapMode::Read, move |r| drop(tx.send(r)));
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(RenderError::Poll)?;
    rx.recv()
        .map_err(RenderError::ReadbackLost)?
        .map_err(RenderError::Map)?;
    let mapped = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(RenderError::MapRange)?;
    Ok(mapped.to_vec())
}

/// sRGB component → linear.
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear component → sRGB.
pub(crate) fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// A unit value as a byte, rounded and clamped.
pub(crate) fn unit_to_byte(c: f32) -> u8 {
    (c * 255.0).round().clamp(0.0, 255.0) as u8
}

/// [`srgb_to_linear`] of every 8-bit value: a supersampled frame has 4 to 16 samples per
/// output pixel, and a `powf` per sample channel, one row at a time, made the downsampling
/// 66–90 ms of the 0.26 s an 800×600 render takes on llvmpipe (13–29 ms now, same bytes).
pub(crate) static SRGB_TO_LINEAR: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)));

/// Averages `factor` × `factor` blocks in linear light (colour) and linearly (alpha), rows in
/// parallel (the same sums in the same order as one row at a time).
fn downsample(full: &RgbaImage, factor: u32) -> RgbaImage {
    use rayon::prelude::*;
    if factor <= 1 {
        return full.clone();
    }
    let (w, h) = (full.width() / factor, full.height() / factor);
    let n = (factor * factor) as f32;
    let lut = &*SRGB_TO_LINEAR;
    let (fw, f) = (full.width() as usize, factor as usize);
    let src = full.as_raw();
    let mut out = vec![0u8; 4 * w as usize * h as usize];
    out.par_chunks_mut(4 * w as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, px) in row.chunks_exact_mut(4).enumerate() {
                // A block of one colour (most of an image: background, flat faces) is that
                // colour: 8-bit sRGB survives the trip through linear light unchanged
                // (`every_srgb_byte_survives_linear_light`), so it is copied, not averaged.
                let first = 4 * (y * f * fw + x * f);
                let corner = &src[first..first + 4];
                let uniform = (0..f).all(|dy| {
                    let start = first + 4 * dy * fw;
                    src[start..start + 4 * f]
                        .chunks_exact(4)
                        .all(|p| p == corner)
                });
                if uniform {
                    px.copy_from_slice(corner);
                    continue;
                }
                let mut sum = [0.0f32; 4];
                for dy in 0..f {
                    for dx in 0..f {
                        let i = 4 * ((y * f + dy) * fw + x * f + dx);
                        let p = &src[i..i + 4];
                        for c in 0..3 {
                            sum[c] += lut[usize::from(p[c])];
                        }
                        sum[3] += f32::from(p[3]) / 255.0;
                    }
                }
                px[0] = unit_to_byte(linear_to_srgb(sum[0] / n));
                px[1] = unit_to_byte(linear_to_srgb(sum[1] / n));
                px[2] = unit_to_byte(linear_to_srgb(sum[2] / n));
                px[3] = unit_to_byte(sum[3] / n);
            }
        });
    RgbaImage::from_raw(w, h, out).expect("the buffer has w × h pixels")
}

/// Whether `gpu` runs the crack pass (compute shaders, and fragment shaders that write
/// storage buffers: its resolve counts what it did) and its exact fill (whose fragment
/// stage binds [`crate::passes::visibility::trim::CRACK_STORAGE_BUFFERS`] storage buffers).
fn crack_support(gpu: &Gpu) -> (bool, bool) {
    let pass = gpu.compute && gpu.fragment_storage;
    let exact = pass
        && gpu.device.limits().max_storage_buffers_per_shader_stage
            >= crate::passes::visibility::trim::CRACK_STORAGE_BUFFERS;
    (pass, exact)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_light_rig_holds_the_first_lights_and_zeros() {
        let camera = Camera::fit(
            glam::DVec3::ZERO,
            glam::DVec3::ONE,
            crate::ViewPreset::Iso,
            false,
            1.0,
        );
        let rig = light_rig(&FrameOptions::default(), &camera);
        let lit = Light::cad_rig().len();
        assert!(rig.lights[..lit].iter().all(|l| l.colour[0] > 0.0));
        assert!(rig.lights[lit..].iter().all(|l| l.colour == [0.0; 4]));
        // More than the rig holds: the first MAX_LIGHTS, and the frame lights that many.
        let many = FrameOptions {
            lights: (0..MAX_LIGHTS + 3)
                .map(|i| Light::CameraDirectional {
                    direction: glam::DVec3::Z,
                    radiance: [1.0 + i as f32; 3],
                })
                .collect(),
            ..FrameOptions::default()
        };
        let rig = light_rig(&many, &camera);
        assert_eq!(rig.lights[MAX_LIGHTS - 1].colour[0], MAX_LIGHTS as f32);
        let frame = frame_uniform(&camera, &many, &ViewState::default(), (8, 8));
        assert_eq!(frame.counts[0], MAX_LIGHTS as u32);
    }

    #[test]
    fn every_srgb_byte_survives_linear_light() {
        for byte in 0..=255u8 {
            for alpha in [0u8, 128, 255] {
                let full = RgbaImage::from_pixel(3, 3, image::Rgba([byte, byte, byte, alpha]));
                // A uniform block is copied; averaging it would give the same bytes.
                let average = |c: u8| {
                    let l = SRGB_TO_LINEAR[usize::from(c)];
                    (linear_to_srgb(l) * 255.0).round() as u8
                };
                assert_eq!(average(byte), byte, "sRGB byte {byte}");
                assert_eq!(
                    downsample(&full, 3).get_pixel(0, 0).0,
                    [byte, byte, byte, alpha]
                );
            }
        }
    }

    #[test]
    fn a_block_that_differs_in_one_sample_is_averaged() {
        let mut full = RgbaImage::from_pixel(2, 2, image::Rgba([255, 255, 255, 255]));
        full.put_pixel(1, 1, image::Rgba([0, 0, 0, 255]));
        // Three quarters white in linear light: 0.75 → 225 in sRGB.
        assert_eq!(downsample(&full, 2).get_pixel(0, 0).0, [225, 225, 225, 255]);
    }

    #[test]
    fn downsampling_averages_in_linear_light() {
        let full = RgbaImage::from_fn(2, 2, |x, _| {
            if x == 0 {
                image::Rgba([0, 0, 0, 255])
            } else {
                image::Rgba([255, 255, 255, 255])
            }
        });
        let small = downsample(&full, 2);
        // Half black, half white is 0.5 linear = 188 in sRGB, not 128.
        assert_eq!(small.get_pixel(0, 0).0, [188, 188, 188, 255]);
        assert!((srgb_to_linear(linear_to_srgb(0.3)) - 0.3).abs() < 1e-6);
    }
    /// A one-triangle scene: enough for every pass to bind its buffers.
    fn triangle() -> cadre_mesh::scene::Scene {
        use cadre_mesh::scene::{Primitive, Scene, SceneMesh, SceneNode};
        Scene {
            meshes: vec![SceneMesh {
                positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                normals: vec![[0.0, 0.0, 1.0]; 3],
                primitives: vec![Primitive {
                    indices: vec![0, 1, 2],
                    material: None,
                    face_ids: vec![1],
                }],
                ..SceneMesh::default()
            }],
            nodes: vec![SceneNode {
                mesh: Some(0),
                ..SceneNode::default()
            }],
            roots: vec![0],
            ..Scene::default()
        }
    }

    #[test]
    fn a_viewers_frames_reuse_their_buffers_and_bind_groups() {
        let Ok(gpu) = Gpu::headless() else {
            eprintln!("no adapter: skipped");
            return;
        };
        let renderer = Renderer::new(&gpu).expect("pipelines");
        let prepared = renderer.prepare(&gpu, &RenderScene::from_assembly(triangle()));
        let mut viewport = Viewport::new(&gpu, 32, 24);
        let target = gpu
            .device
            .create_texture(&wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d {
                    width: 32,
                    height: 24,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: COLOUR,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let options = FrameOptions {
            width: 32,
            height: 24,
            supersample: 1,
            mode: DisplayMode::ShadedEdges,
            ..FrameOptions::default()
        };
        let camera = |k: f64| {
            Camera::fit(
                glam::DVec3::ZERO,
                glam::DVec3::new(1.0, 1.0, 0.1 * k),
                crate::ViewPreset::Iso,
                false,
                32.0 / 24.0,
            )
        };
        let draw = |viewport: &mut Viewport, k: f64| {
            let state = ViewState::default();
            renderer
                .draw(
                    &gpu,
                    viewport,
                    &prepared,
                    &camera(k),
                    &options,
                    &state,
                    &target,
                )
                .expect("frame");
        };
        draw(&mut viewport, 1.0);
        let (made, frame, draws) = (
            renderer.binds.made(),
            viewport.buffers.frame.buffer().clone(),
            viewport.buffers.draws.buffer().clone(),
        );
        assert!(made >= 3, "{made} bind groups");
        // Another camera: the same buffers, refilled, and no bind group made.
        draw(&mut viewport, 2.0);
        assert_eq!(renderer.binds.made(), made);
        assert_eq!(*viewport.buffers.frame.buffer(), frame);
        assert_eq!(*viewport.buffers.draws.buffer(), draws);
        // Negative control: a new viewport's buffers need bind groups of their own.
        let mut other = Viewport::new(&gpu, 32, 24);
        draw(&mut other, 2.0);
        assert!(renderer.binds.made() > made);
    }
}
