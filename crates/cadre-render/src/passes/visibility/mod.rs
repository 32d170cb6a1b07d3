//! Visibility pass: the visibility buffer (depth, normal, ids, (u, v)) and the surface
//! back-ends that write it. The pass is opened once per frame (targets cleared) and every
//! back-end draws into it in turn; each back-end's fragments go through the one texel writer
//! of `texel.wgsl` (section caps, id packing), so shading, edges, picking and sections read
//! the same buffer whatever drew it. Back-ends: [`mesh`] (the scene's triangles), then
//! [`trim`] (B-Rep faces from their exact surfaces and trim trees, where the scene has them
//! and the adapter runs compute shaders), then [`analytic`] (spheres and rectangles ray cast
//! per pixel).
//!
//! The later phases that draw surfaces ([`Phase::Transparent`], [`Phase::XRay`]) are opened
//! here too, and every back-end answers each: its see-through surfaces blended over the
//! shaded image behind the visibility depth, or all its surfaces blended in x-ray mode, with
//! the colours of the shared `see_through.wgsl`. Picking needs nothing more of them: faces are
//! picked from the visibility buffer's ids, edges and vertices by the pick pass.

pub(crate) mod analytic;
pub(crate) mod mesh;
pub(crate) mod trim;

use crate::gpu_scene::FrameScene;

/// The WGSL of the shared texel writer, placed before each back-end's own source.
pub(crate) const TEXEL_WGSL: &str = include_str!("texel.wgsl");

/// The WGSL of the shared see-through colours (x-ray, transparent parts).
pub(crate) const SEE_THROUGH_WGSL: &str = include_str!("see_through.wgsl");

/// What a frame asks every surface back-end to draw, in the order it records them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Phase {
    /// The opaque surfaces into the visibility buffer (depth written).
    Visibility,
    /// The see-through surfaces of an opaque view, lit and blended over the shaded image,
    /// hidden behind the visibility depth (not written).
    Transparent,
    /// Every surface blended over the background, no depth (x-ray mode).
    XRay,
}

/// What every back-end reads in a phase.
pub(crate) struct PhaseInputs<'a> {
    /// The frame's uniform.
    pub frame: &'a wgpu::Buffer,
    pub scene: &'a FrameScene<'a>,
    /// The frame has section planes (the visibility phase's cuts and caps).
    pub sections: bool,
    /// The visibility phase writes the (u, v) target.
    pub with_uv: bool,
    /// The analytic back-end writes its proxies' depth (the tests' negative control).
    pub proxy_depth: bool,
    /// The trim back-end writes its trimmed edges' coverage (the frame blends them).
    pub coverage: bool,
}

/// Formats of the visibility buffer.
pub(crate) const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// View-space unit normal, each component mapped from [−1, 1] to [0, 1] (xyz, 10 bits: a
/// step of 0.002, under 0.1°), 1 where a surface is (w). Four bytes a pixel where
/// `Rgba16Float` took eight: on a CPU rasterizer every byte of a target is cleared, converted,
/// stored and read again each frame.
pub(crate) const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgb10a2Unorm;
/// Face id, instance + 1 (0 = background), material, depth (f32 bits).
pub(crate) const IDS: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// (u, v) on the face's exact surface, as f32 bits (float targets of 32 bits are not
/// renderable on GL, integer ones are).
pub(crate) const UV: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// The surface back-ends, drawn in this order into each pass opened for a phase.
pub(crate) struct VisibilityPass {
    mesh: mesh::MeshBackend,
    /// `None` on adapters without compute shaders (their scenes keep every face's mesh).
    trim: Option<LazyTrim>,
    analytic: analytic::AnalyticBackend,
}

/// The trim back-end, built on the first frame that draws trimmed faces: its shaders are the
/// renderer's largest, and compiling them at start cost every process ≈ 40 ms on lavapipe
/// (`cadre render` of pr2db: 0.16 s with them, 0.12 s without), meshes or not.
struct LazyTrim {
    instances: crate::passes::instances::InstanceLayout,
    variant: trim::TrimVariant,
    backend: std::sync::OnceLock<trim::TrimBackend>,
}

impl LazyTrim {
    fn new(
        instances: &crate::passes::instances::InstanceLayout,
        variant: trim::TrimVariant,
    ) -> Self {
        LazyTrim {
            instances: instances.clone(),
            variant,
            backend: std::sync::OnceLock::new(),
        }
    }

    /// The back-end, built now if no frame has needed it yet.
    fn get(&self, device: &wgpu::Device) -> &trim::TrimBackend {
        self.backend
            .get_or_init(|| trim::TrimBackend::new(device, &self.instances, self.variant))
    }
}

/// Depth state of every back-end: reverse Z (nearer is larger), written.
pub(crate) fn depth_state() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Greater),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// Depth state of what is drawn over the visibility buffer without writing its depth (the
/// transparent phase, the edges' depth-tested pipelines): tested against it (reverse Z: in
/// front of the opaque surfaces, or on them).
pub(crate) fn tested_not_written() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
        ..depth_state()
    }
}

/// A visibility target of `format`, written whole, not blended.
const fn written(format: wgpu::TextureFormat) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// Colour targets of every back-end: normal, ids, (u, v); [`TARGETS_NO_UV`] when nothing
/// reads the (u, v).
pub(crate) const TARGETS: [Option<wgpu::ColorTargetState>; 3] =
    [written(NORMAL), written(IDS), written(UV)];

/// [`TARGETS`] without the (u, v) target: only the exact-surface tests read it, and on a CPU
/// rasterizer every target is memory to clear, write and fault in (8 of the 36 bytes a pixel).
pub(crate) const TARGETS_NO_UV: [Option<wgpu::ColorTargetState>; 3] =
    [written(NORMAL), written(IDS), None];

/// The visibility buffer's textures, of one size.
pub(crate) struct VisibilityTargets {
    pub depth: wgpu::TextureView,
    pub normal: wgpu::TextureView,
    /// The normal target itself, for the tests' readback ([`crate::Renderer::render_normals`]).
    pub normal_texture: wgpu::Texture,
    pub ids: wgpu::TextureView,
    pub ids_texture: wgpu::Texture,
    /// The (u, v) target, made only for frames that read it back.
    pub uv: Option<(wgpu::TextureView, wgpu::Texture)>,
}

impl VisibilityTargets {
    /// Targets of `width` × `height`, with the (u, v) one when `with_uv`.
    pub fn new(
        device: &wgpu::Device,
        (width, height): (u32, u32),
        with_uv: bool,
    ) -> VisibilityTargets {
        let make = |label, format, extra: wgpu::TextureUsages| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | extra,
                view_formats: &[],
            })
        };
        let depth = make("depth", DEPTH, wgpu::TextureUsages::empty());
        let normal = make("normal", NORMAL, wgpu::TextureUsages::COPY_SRC);
        let ids = make("ids", IDS, wgpu::TextureUsages::COPY_SRC);
        let uv = with_uv.then(|| {
            let texture = make("uv", UV, wgpu::TextureUsages::COPY_SRC);
            (texture.create_view(&Default::default()), texture)
        });
        VisibilityTargets {
            depth: depth.create_view(&Default::default()),
            normal: normal.create_view(&Default::default()),
            normal_texture: normal,
            ids: ids.create_view(&Default::default()),
            ids_texture: ids,
            uv,
        }
    }
}

impl VisibilityPass {
    /// Builds every back-end's pipelines (the see-through ones for a `colour` target of that
    /// format).
    /// The trim back-end is built only where `compute` (`Gpu::compute`, which `instances`
    /// was made for) and the device binds its storage buffers.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &crate::passes::instances::InstanceLayout,
        compute: bool,
    ) -> VisibilityPass {
        VisibilityPass {
            mesh: mesh::MeshBackend::new(device, colour, instances),
            trim: (compute
                && device.limits().max_storage_buffers_per_shader_stage >= trim::STORAGE_BUFFERS)
                .then(|| LazyTrim::new(instances, trim::TrimVariant::default())),
            analytic: analytic::AnalyticBackend::new(device, colour),
        }
    }

    /// Triangles the trim back-end drew the last frame with (see
    /// [`trim::TrimBackend::last_triangles`]).
    pub fn last_trim_triangles(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> u64 {
        self.trim
            .as_ref()
            .and_then(|t| t.backend.get())
            .map_or(0, |t| t.last_triangles(device, queue))
    }

    /// Whether the trim back-end can draw (the adapter runs compute shaders).
    pub fn draws_trims(&self) -> bool {
        self.trim.is_some()
    }

    /// This pass with the trim back-end drawing `variant` (the tests' negative control, the
    /// benchmarks that separate its costs).
    pub fn set_trim_variant(
        &mut self,
        device: &wgpu::Device,
        instances: &crate::passes::instances::InstanceLayout,
        variant: trim::TrimVariant,
    ) {
        if self.trim.is_some() {
            let lazy = LazyTrim::new(instances, variant);
            // Built now: who asks for a variant draws with it.
            lazy.get(device);
            self.trim = Some(lazy);
        }
    }

    /// Every back-end draws its part of `phase` into `pass`, in order.
    fn draw(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        inputs: &PhaseInputs<'_>,
        phase: Phase,
    ) {
        self.mesh.draw(recorder, pass, inputs, phase);
        // Frames without trimmed faces leave the back-end unbuilt.
        if let Some(trim) = &self.trim
            && inputs.scene.trim.is_some()
        {
            trim.get(recorder.0).draw(recorder, pass, inputs, phase);
        }
        self.analytic.draw(recorder, pass, inputs, phase);
    }

    /// Records the pass: opens it once on `targets` (cleared) and has every back-end draw
    /// `scene` into it; `sections` says whether the frame has section planes;
    /// `proxy_depth` has the analytic back-end write its proxies' depth (the tests' negative
    /// control). `coverage`: the trim back-end writes its trimmed edges' coverage.
    /// `clear_ids`: clear the ids target first; else it keeps the last frame's ids
    /// where nothing is drawn now, and readers must take a pixel's ids only where its depth
    /// is not 0 (see [`open`]). `timer` marks the end of the trim back-end's tessellation.
    pub fn record(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        (frame, sections, proxy_depth, clear_ids, coverage): (
            &wgpu::Buffer,
            bool,
            bool,
            bool,
            bool,
        ),
        scene: &FrameScene<'_>,
        timer: Option<&crate::pass_timer::PassTimer>,
    ) {
        let inputs = PhaseInputs {
            frame,
            scene,
            sections,
            with_uv: targets.uv.is_some(),
            proxy_depth,
            coverage,
        };
        if let Some(trim) = &self.trim
            && inputs.scene.trim.is_some()
        {
            trim.get(recorder.0).tessellate(recorder, encoder, &inputs);
            if let Some(t) = timer {
                t.mark(encoder, "trim tessellation");
            }
        }
        let mut pass = open(encoder, targets, clear_ids);
        self.draw(recorder, &mut pass, &inputs, Phase::Visibility);
    }

    /// Records the trim back-end's exact crack fill into `buffers` when it drew this frame
    /// (`sections`: the frame has section planes): the seeded solves, then `mask` (which
    /// records the crack mask, from what they left), then the faces drawn again; whether it
    /// did.
    pub fn record_crack_fill(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        (frame, sections): (&wgpu::Buffer, bool),
        scene: &FrameScene<'_>,
        buffers: &crate::passes::cracks::CrackBuffers,
        mask: &mut dyn FnMut(&mut wgpu::CommandEncoder),
    ) -> bool {
        let Some(trim) = self.trim.as_ref().filter(|_| scene.trim.is_some()) else {
            return false;
        };
        let inputs = PhaseInputs {
            frame,
            scene,
            sections,
            with_uv: false,
            proxy_depth: false,
            coverage: false,
        };
        trim.get(recorder.0)
            .draw_cracks(recorder, encoder, &inputs, buffers, mask);
        true
    }

    /// Records a see-through `phase` over `colour` (kept, blended onto): x-ray with no
    /// depth, the transparent phase tested against `visibility`'s depth (skipped when the
    /// frame has nothing see-through).
    pub fn record_see_through(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        phase: Phase,
        (frame, scene): (&wgpu::Buffer, &FrameScene<'_>),
        (visibility, colour): (&VisibilityTargets, &wgpu::TextureView),
    ) {
        let depth = match phase {
            Phase::Visibility => return,
            Phase::XRay => None,
            Phase::Transparent => {
                if scene.transparent.is_empty() && scene.primitives.see_through.is_empty() {
                    return;
                }
                Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &visibility.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                })
            }
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(if depth.is_some() {
                "transparent"
            } else {
                "x-ray"
            }),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: colour,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: depth,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let inputs = PhaseInputs {
            frame,
            scene,
            sections: false,
            with_uv: false,
            proxy_depth: false,
            coverage: false,
        };
        self.draw(recorder, &mut pass, &inputs, phase);
    }
}

/// The visibility render pass over `targets`, cleared: depth 0 (far), normal 0, and the ids
/// to 0 (background) when `clear_ids`.
///
/// Every fragment drawn writes depth and ids together, so where the depth is not 0 the ids
/// are this frame's whether cleared or not. On lavapipe clearing the 16-byte ids texel was
/// 4 of a 21 ms frame at 1280×960 (pr2db, `cadre bench view`; BENCHMARKS.md, issue 15), and
/// the shade pass, depth-tested, never reads an uncovered pixel's ids: a frame whose ids
/// nothing else reads leaves them (see `Renderer::run`).
fn open<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    targets: &VisibilityTargets,
    clear_ids: bool,
) -> wgpu::RenderPass<'e> {
    let attach = |view, clear: bool| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: if clear {
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
                } else {
                    wgpu::LoadOp::Load
                },
                store: wgpu::StoreOp::Store,
            },
        })
    };
    let clear = |view| attach(view, true);
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("visibility"),
        color_attachments: &[
            clear(&targets.normal),
            attach(&targets.ids, clear_ids),
            targets.uv.as_ref().and_then(|(uv, _)| clear(uv)),
        ],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &targets.depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(0.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
