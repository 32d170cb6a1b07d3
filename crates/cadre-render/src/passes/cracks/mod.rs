//! Crack-free rendering (seed 000, Part IV), between the visibility pass and the shading:
//! faces tessellated each to its own screen-space error no longer share their boundary
//! vertices, so the background or a face behind shows through a pixel here and there along
//! their shared edges. Three steps, each its own shader:
//!
//! 1. **Detection** (`detect.wgsl`, two full-screen passes: the flags as the crack mask's
//!    depth, free of side effects; then, at the flagged pixels only, the entries): a pixel is a crack when, for one of its four
//!    pairs of opposite neighbours, both are nearer than it by at least d_min and neither
//!    shows its face (silhouettes are never taken: past one, a neighbour shows the same face
//!    or nothing). Each crack gets an entry (its pixel, the fast fill), capped at
//!    [`ENTRY_CAPACITY`] a frame (the rest are counted, [`CrackCounts::overflow`]).
//! 2. **Exact fill** (`visibility/trim/crack.wgsl`, [`CrackMode::Exact`]): first each crack
//!    pixel's seeds — the texels of its pair's two neighbours in the visibility buffer —
//!    solved on their own faces in compute, from their (u, v) (beyond the seed, which
//!    draws faces again for every crack: trj3_s1-ec-214 at 1080p on lavapipe, 550 → 252 ms);
//!    then, for the cracks no seed closed, the trimmed faces about them
//!    drawn again untrimmed; a fragment next to a crack solves, by Newton's method from its
//!    (u, v), for its exact surface's point seen at the crack pixel's centre, keeps it if the
//!    face's exact trim does, and pushes it on the pixel's list of hits (a mailbox per pixel
//!    so that a face is solved once). The seed keeps the nearest with a 64-bit `atomicMin`
//!    of depth | id (a two-pass 32-bit fallback where the adapter has no 64-bit atomics);
//!    a list per pixel, walked by the resolve, keeps it in one pass on every adapter
//!    (WebGPU included) with 32-bit atomics only, and its lists are short (a crack is seen
//!    by the two or three faces about it).
//! 3. **Resolve** (`resolve.wgsl`, a full-screen triangle): each crack pixel gets its texel
//!    (normal, ids, (u, v), depth): the nearest hit; without one (a gap in the model
//!    itself, or Newton's method failing) the fast fill where a face's trim passed within
//!    half the gap tolerance of the pixel's ray, else the pixel is left as it is; with
//!    [`CrackMode::Fast`] the fast fill (the face most neighbours show, at their mean
//!    depth). With [`CrackOptions::highlight`] filled cracks and closed gaps are marked for
//!    the shade pass, which paints them (the inspection view).

use crate::frame_buffers::BindCache;
use crate::layout::{Binding, FrameUniform, GpuStruct};
use crate::passes::common::{PipelineSpec, entries, layouts, pipeline, shader, wgsl};
use crate::passes::visibility::{DEPTH, TARGETS, TARGETS_NO_UV, VisibilityTargets};
use std::sync::{Mutex, OnceLock};

/// How a frame closes the cracks between faces drawn by the trim back-end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CrackMode {
    /// Not at all (what the trim back-end draws is what is shown).
    Off,
    /// In screen space: a crack pixel takes the face most of its neighbours show (for a
    /// moving camera).
    Fast,
    /// In object space: a crack pixel takes the exact surface seen there, trimmed exactly
    /// (Newton's method from the neighbouring faces' fragments).
    #[default]
    Exact,
}

/// The crack pass's settings ([`crate::FrameOptions::cracks`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrackOptions {
    /// Off, fast or exact.
    pub mode: CrackMode,
    /// Paint filled cracks and closed gaps (the inspection view): cracks magenta, gaps
    /// orange.
    pub highlight: bool,
    /// d_min, world units: how much nearer than a pixel both neighbours of a pair must be
    /// for it to be a crack; 0 takes [`MIN_DEPTH_REL`] of the scene's diagonal.
    pub min_depth: f64,
    /// Real gaps in the model (faces that do not meet) narrower than this, world units, are
    /// closed too (and painted as gaps when highlighted); 0 leaves every gap open.
    pub gap_tolerance: f64,
    /// The silhouette rule beside the seed's (exact mode): pixels next to a nearer face seen
    /// at a grazing angle, where a grid ends short of its surface's true silhouette, are
    /// solved too, each from that face's (u, v) at the neighbour (`detect.wgsl`,
    /// `crack.wgsl`'s `cs_seeded`). On by default (a few percent of a trim frame on
    /// lavapipe, BENCHMARKS.md); the frame then writes the (u, v) target.
    pub silhouettes: bool,
}

impl Default for CrackOptions {
    fn default() -> Self {
        CrackOptions {
            mode: CrackMode::Exact,
            highlight: false,
            min_depth: 0.0,
            gap_tolerance: 0.0,
            silhouettes: true,
        }
    }
}

/// d_min relative to the scene's bounding-box diagonal when [`CrackOptions::min_depth`] is
/// 0: the seed's 1 mm is 10⁻³ of a 1 m assembly; well above the trim back-end's depth
/// error (its grids keep within 2.5·10⁻⁴ of the diagonal, `DEPTH_REL`), so two adjacent
/// faces' pixels never pass for a crack.
pub const MIN_DEPTH_REL: f64 = 1e-3;

/// Crack pixels a frame can hold (past them, cracks are counted and left).
pub const ENTRY_CAPACITY: u32 = 1 << 16;

/// Exact-fill hits a frame can hold (four a crack).
pub const HIT_CAPACITY: u32 = 4 * ENTRY_CAPACITY;

/// `vec4<u32>` an entry has in [`CrackBuffers::seeds`] (`CRACK_SEED_VEC4S`): two seeds, a
/// neighbour's texel and what the match found each.
pub const SEED_VEC4S: u32 = 4;

/// Where in [`CrackBuffers::args`] the seeded solves' indirect dispatch lies (bytes).
pub(crate) const SEEDED_DISPATCH_OFFSET: u64 = 16;

/// Words of the crack state's header (counters, [`CrackCounts`]), before the entries'.
pub const HEADER: u32 = 16;

/// Atomic words an entry has in the crack state: four mailbox slots (faces solved), the head
/// of its hits, its two least miss distances, one unused.
pub const ENTRY_WORDS: u32 = 8;

/// What the last frame's crack pass did (the first words of its state).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CrackCounts {
    /// Crack pixels detected (those past [`ENTRY_CAPACITY`] included).
    pub detected: u32,
    /// Crack pixels past [`ENTRY_CAPACITY`], left as they are.
    pub overflow: u32,
    /// Exact solutions on trimmed faces found (past [`HIT_CAPACITY`] included).
    pub hits: u32,
    /// Newton solves run (fragments next to a crack that were not turned back by the
    /// mailbox).
    pub solves: u32,
    /// Crack pixels filled by an exact hit.
    pub exact: u32,
    /// Crack pixels filled by the fast fill ([`CrackMode::Fast`]).
    pub fast: u32,
    /// Crack pixels in real gaps narrower than the tolerance, closed by the fast fill.
    pub gaps: u32,
    /// Crack pixels left open: a gap wider than the tolerance, or no solution found.
    pub open: u32,
    /// Tessellation tasks (a face of a mesh call) the exact fill drew again: those whose
    /// projected bounding sphere reaches a crack (`visibility/trim/crack_faces.wgsl`).
    pub fill_faces: u32,
    /// Of the `detected`, pixels flagged beside a silhouette (a face seen at a grazing angle
    /// nearer than what the pixel shows, `detect.wgsl`): filled by an exact hit (counted in
    /// `exact`) or left as drawn, never counted `open` nor filled by the fast fill.
    pub silhouettes: u32,
    /// Of the `detected`, pixels the seeded solves settled (a hit from a seed closed them):
    /// the exact fill drew no face again for them.
    pub settled: u32,
}

/// The detection's bind group 0: frame, the depth, ids and normal targets, the crack map,
/// the entries, the state, the quads' indirect draw (and the seeded solves' dispatch), the
/// (u, v) target, the seeds.
pub(crate) const DETECT_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::FloatTexture,
    Binding::UintTexture,
    Binding::FloatTexture,
    Binding::StorageWrite("u32"),
    Binding::StorageWrite("vec4<u32>"),
    Binding::AtomicStorage,
    Binding::StorageWrite("u32"),
    Binding::UintTexture,
    Binding::StorageWrite("vec4<u32>"),
];

/// The resolve's (and the mask's) bind group 0: frame, the entries, the state, the hits,
/// the seeds.
pub(crate) const RESOLVE_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage("vec4<u32>"),
    Binding::AtomicStorage,
    Binding::Storage("vec4<u32>"),
    Binding::Storage("vec4<u32>"),
];

/// The crack buffers' layout in WGSL (the state's words), placed before each crack shader.
pub(crate) const LAYOUT_WGSL: &str = include_str!("layout.wgsl");

/// The detection's whole WGSL.
pub(crate) fn detect_source() -> String {
    wgsl(&[LAYOUT_WGSL, include_str!("detect.wgsl")])
}

/// The resolve's whole WGSL.
pub(crate) fn resolve_source() -> String {
    wgsl(&[LAYOUT_WGSL, include_str!("resolve.wgsl")])
}

/// `source` with its fragment entry point `entry` testing depth before it runs, when
/// `early_depth` (`@early_depth_test(force)`, `SHADER_EARLY_DEPTH_TEST`): a shader that
/// writes storage is otherwise tested after it ran, so every fragment pays for it.
pub(crate) fn with_early_depth(source: String, entry: &str, early_depth: bool) -> String {
    if early_depth {
        source.replace(
            &format!("@fragment\nfn {entry}"),
            &format!("@fragment @early_depth_test(force)\nfn {entry}"),
        )
    } else {
        source
    }
}

/// A render pass over `depth` alone (the crack mask), cleared to `clear` or loaded, kept.
pub(crate) fn depth_only_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    depth: &wgpu::TextureView,
    clear: Option<f32>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// The crack buffers of one target size, kept between frames while it stays.
#[derive(Clone)]
pub(crate) struct CrackBuffers {
    /// Per pixel, 0 or 1 + its entry.
    pub map: wgpu::Buffer,
    /// Three `vec4<u32>` an entry.
    pub entries: wgpu::Buffer,
    /// Counters, then [`ENTRY_WORDS`] an entry.
    pub state: wgpu::Buffer,
    /// Two `vec4<u32>` a hit.
    pub hits: wgpu::Buffer,
    /// [`SEED_VEC4S`] `vec4<u32>` an entry: its seeds (layout.wgsl).
    pub seeds: wgpu::Buffer,
    /// The indirect draw of the crack quads (mask, resolve): 6 vertices, an instance a
    /// crack; then, at [`SEEDED_DISPATCH_OFFSET`], the seeded solves' indirect dispatch.
    pub args: wgpu::Buffer,
    /// The exact fill's depth mask: 0 about the cracks, 1 elsewhere.
    pub mask: wgpu::TextureView,
    /// The target size they are for.
    size: (u32, u32),
}

impl CrackBuffers {
    fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> CrackBuffers {
        let pixels = u64::from(width) * u64::from(height);
        let make = |label, size: u64, extra: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | extra,
                mapped_at_creation: false,
            })
        };
        let entries = u64::from(ENTRY_CAPACITY);
        CrackBuffers {
            map: make("crack map", 4 * pixels.max(1), wgpu::BufferUsages::COPY_DST),
            entries: make("crack entries", 48 * entries, wgpu::BufferUsages::empty()),
            state: make(
                "crack state",
                4 * (u64::from(HEADER) + u64::from(ENTRY_WORDS) * entries),
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            ),
            hits: make(
                "crack hits",
                32 * u64::from(HIT_CAPACITY),
                wgpu::BufferUsages::empty(),
            ),
            seeds: make(
                "crack seeds",
                16 * u64::from(SEED_VEC4S) * entries,
                wgpu::BufferUsages::empty(),
            ),
            args: make(
                "crack quads",
                32,
                wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC,
            ),
            mask: device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("crack mask"),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: DEPTH,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default()),
            size: (width, height),
        }
    }
}

/// The crack pass: detection and resolve pipelines, and the buffers of the last size.
pub(crate) struct CrackPass {
    /// The flags: a full-screen triangle's fragments writing the crack mask's depth (0 at a
    /// crack, 1 elsewhere).
    flag: wgpu::RenderPipeline,
    /// The entries: a full-screen triangle's fragments at the flagged pixels (tested against
    /// the mask).
    detect: wgpu::RenderPipeline,
    /// The detection's second entry point: the quads' indirect draw from its count.
    args: wgpu::ComputePipeline,
    detect_layout: wgpu::BindGroupLayout,
    /// The exact fill's depth mask (the crack quads' 3 × 3 pixels at depth 0).
    mask: wgpu::RenderPipeline,
    resolve_module: wgpu::ShaderModule,
    resolve_layout: wgpu::BindGroupLayout,
    resolve_pipeline_layout: wgpu::PipelineLayout,
    /// Indexed by `exact + 2 × highlight + 4 × with_uv`.
    resolves: [OnceLock<wgpu::RenderPipeline>; 8],
    buffers: Mutex<Option<CrackBuffers>>,
}

impl CrackPass {
    /// Compiles the detection and the resolve.
    pub fn new(device: &wgpu::Device) -> CrackPass {
        let early = device
            .features()
            .contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST);
        let module = shader(
            device,
            "crack detection",
            &with_early_depth(detect_source(), "fs_detect", early),
        );
        // The detection is two fragment shaders, its count turned into the quads' draw by a
        // compute one.
        let mut group = entries(DETECT_BINDINGS, wgpu::ShaderStages::FRAGMENT);
        for entry in &mut group {
            entry.visibility |= wgpu::ShaderStages::COMPUTE;
        }
        let (detect_layout, detect_pipeline_layout) =
            layouts(device, "crack detection", &group, None);
        let capacity = [("CRACK_ENTRY_CAPACITY", f64::from(ENTRY_CAPACITY))];
        let full_screen = |label, fragment, depth| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&detect_pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_detect"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: Some(depth),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &capacity,
                        ..Default::default()
                    },
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let flag = full_screen("crack flags", "fs_flag", written_always());
        let detect = full_screen(
            "crack detection",
            "fs_detect",
            wgpu::DepthStencilState {
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                ..written_always()
            },
        );
        let args = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("crack quads"),
            layout: Some(&detect_pipeline_layout),
            module: &module,
            entry_point: Some("cs_args"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &capacity,
                ..Default::default()
            },
            cache: None,
        });
        let resolve_module = shader(device, "crack resolve", &resolve_source());
        // The vertex stage reads the entries (where its quad goes); the state, written, is
        // the fragment stage's alone (vertex stages may not write storage).
        let mut group = entries(RESOLVE_BINDINGS, wgpu::ShaderStages::VERTEX_FRAGMENT);
        group[2].visibility = wgpu::ShaderStages::FRAGMENT;
        let (resolve_layout, resolve_pipeline_layout) =
            layouts(device, "crack resolve", &group, None);
        let mask = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("crack mask"),
            layout: Some(&resolve_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &resolve_module,
                entry_point: Some("vs_mask"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(written_always()),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        CrackPass {
            flag,
            detect,
            args,
            detect_layout,
            mask,
            resolve_module,
            resolve_layout,
            resolve_pipeline_layout,
            resolves: Default::default(),
            buffers: Mutex::new(None),
        }
    }

    /// The buffers for a target of `size`: the kept ones, or new ones.
    pub fn buffers(&self, device: &wgpu::Device, size: (u32, u32)) -> CrackBuffers {
        let mut kept = self.buffers.lock().unwrap_or_else(|e| e.into_inner());
        match &*kept {
            Some(b) if b.size == size => b.clone(),
            _ => {
                let b = CrackBuffers::new(device, size);
                *kept = Some(b.clone());
                b
            }
        }
    }

    /// Records the detection over `targets` (the visibility buffer as drawn) into `buffers`.
    pub fn detect(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        frame: &wgpu::Buffer,
        buffers: &CrackBuffers,
    ) {
        encoder.clear_buffer(&buffers.state, 0, Some(4 * u64::from(HEADER)));
        encoder.clear_buffer(&buffers.map, 0, None);
        let bind = binds.get(
            device,
            "crack detection",
            &self.detect_layout,
            &[
                frame.as_entire_binding(),
                wgpu::BindingResource::TextureView(&targets.depth),
                wgpu::BindingResource::TextureView(&targets.ids),
                wgpu::BindingResource::TextureView(&targets.normal),
                buffers.map.as_entire_binding(),
                buffers.entries.as_entire_binding(),
                buffers.state.as_entire_binding(),
                buffers.args.as_entire_binding(),
                // The seeds' (u, v); the ids target stands in (unread) where the frame has no
                // (u, v) target, which it has whenever the exact fill runs.
                wgpu::BindingResource::TextureView(
                    targets.uv.as_ref().map_or(&targets.ids, |(uv, _)| uv),
                ),
                buffers.seeds.as_entire_binding(),
            ],
        );
        {
            let mut pass = depth_only_pass(encoder, "crack detection", &buffers.mask, None);
            pass.set_bind_group(0, &bind, &[]);
            pass.set_pipeline(&self.flag);
            pass.draw(0..3, 0..1);
            pass.set_pipeline(&self.detect);
            pass.draw(0..3, 0..1);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("crack quads"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.args);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// Records the exact fill's depth mask into `buffers.mask`: cleared to 1 (nothing
    /// passes), the 3 × 3 pixels about each crack at 0.
    pub fn mask(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        buffers: &CrackBuffers,
    ) {
        let bind = self.resolve_bind((device, binds), frame, buffers);
        let mut pass = depth_only_pass(encoder, "crack mask", &buffers.mask, Some(1.0));
        pass.set_pipeline(&self.mask);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw_indirect(&buffers.args, 0);
    }

    /// The resolve's (and the mask's) bind group.
    fn resolve_bind(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        frame: &wgpu::Buffer,
        buffers: &CrackBuffers,
    ) -> wgpu::BindGroup {
        binds.get(
            device,
            "crack resolve",
            &self.resolve_layout,
            &[
                frame.as_entire_binding(),
                buffers.entries.as_entire_binding(),
                buffers.state.as_entire_binding(),
                buffers.hits.as_entire_binding(),
                buffers.seeds.as_entire_binding(),
            ],
        )
    }

    /// Records the resolve: the crack pixels' texels written into `targets`; `exact`: the
    /// exact fill ran (else the fast fill only).
    pub fn resolve(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        frame: &wgpu::Buffer,
        buffers: &CrackBuffers,
        (exact, highlight): (bool, bool),
    ) {
        let with_uv = targets.uv.is_some();
        let k = usize::from(exact) + 2 * usize::from(highlight) + 4 * usize::from(with_uv);
        let pipeline = self.resolves[k].get_or_init(|| {
            pipeline(
                device,
                PipelineSpec {
                    label: "crack resolve",
                    layout: &self.resolve_pipeline_layout,
                    module: &self.resolve_module,
                    vertex: "vs_resolve",
                    cull: None,
                    fragment: "fs_resolve",
                    buffers: &[],
                    depth: Some(written_always()),
                    targets: if with_uv { &TARGETS } else { &TARGETS_NO_UV },
                    constants: &[
                        ("EXACT", f64::from(u8::from(exact))),
                        ("HIGHLIGHT", f64::from(u8::from(highlight))),
                    ],
                },
            )
        });
        let bind = self.resolve_bind((device, binds), frame, buffers);
        let mut pass = kept_targets_pass(encoder, "crack resolve", targets);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw_indirect(&buffers.args, 0);
    }

    /// What the last frame's crack pass did (waits for the GPU); zeros before any.
    pub fn last_counts(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> CrackCounts {
        let Some(buffers) = self
            .buffers
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
        else {
            return CrackCounts::default();
        };
        let size = 4 * u64::from(HEADER);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("crack counts readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&buffers.state, 0, &readback, 0, size);
        queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        if device.poll(wgpu::PollType::wait_indefinitely()).is_err() {
            return CrackCounts::default();
        }
        let Ok(view) = slice.get_mapped_range() else {
            return CrackCounts::default();
        };
        let w: &[u32] = bytemuck::cast_slice(&view);
        CrackCounts {
            detected: w[0],
            overflow: w[1],
            hits: w[2],
            solves: w[3],
            exact: w[4],
            fast: w[5],
            gaps: w[6],
            open: w[7],
            fill_faces: w[8],
            silhouettes: w[9],
            settled: w[10],
        }
    }
}

/// Depth state of the resolve: every fragment it keeps writes its depth, whatever was there
/// (the crack pixel showed something farther, or nothing).
fn written_always() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Always),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A render pass over the visibility targets, loaded and kept (the resolve's).
fn kept_targets_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    targets: &VisibilityTargets,
) -> wgpu::RenderPass<'e> {
    let keep = |view| {
        Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })
    };
    let attachments = [
        keep(&targets.normal),
        keep(&targets.ids),
        targets.uv.as_ref().and_then(|(uv, _)| keep(uv)),
    ];
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &attachments,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &targets.depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// The crack pass's settings for a frame over a scene whose bounding-box diagonal is
/// `diagonal`: d_min and the gap tolerance in world units, for the frame uniform's
/// `tolerances.z` and `.w`.
pub(crate) fn tolerances(options: &CrackOptions, diagonal: f64) -> [f32; 2] {
    let min_depth = if options.min_depth > 0.0 {
        options.min_depth
    } else {
        MIN_DEPTH_REL * diagonal
    };
    [min_depth as f32, options.gap_tolerance.max(0.0) as f32]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn d_min_follows_the_scene_unless_given() {
        let derived = tolerances(&CrackOptions::default(), 500.0);
        assert_eq!(derived, [0.5, 0.0]);
        let given = CrackOptions {
            min_depth: 2.0,
            gap_tolerance: 0.1,
            ..CrackOptions::default()
        };
        assert_eq!(tolerances(&given, 500.0), [2.0, 0.1]);
    }
}
