//! Edges pass: wire bodies and B-Rep edges drawn over the shaded image as anti-aliased lines
//! of constant pixel width, visible, hidden-dashed or all, by the display mode. Where the
//! adapter runs compute shaders, the visible-edges mode without section planes rasterizes
//! its segments in compute ([`raster`]) and draws only the highlighted ones as quads.

pub(crate) mod raster;

use super::common::{
    PipelineSpec, blended, colour_pass, draw_segment_call, entries, layouts, pipeline,
    record_instance_layout, shader, wgsl,
};
use super::visibility::{VisibilityTargets, tested_not_written};
use crate::frame_buffers::BindCache;
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, EDGES_VISIBLE, FrameUniform, GpuStruct, Segment};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use raster::EdgeRaster;
use std::sync::OnceLock;

/// What the quads and the compute rasterizer share: bind group 0's segments, depth and
/// selection, the culling behind a segment's own solid, the highlight.
pub(crate) const EDGE_SEGMENTS_WGSL: &str = include_str!("segments.wgsl");

/// Bind group 0: frame, segments, the visibility depth, selection (group 1: the instances).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Segment::WGSL_NAME),
    Binding::FloatTexture,
    Binding::Storage("vec4<u32>"),
];

/// The pass's whole WGSL: the shared declarations and its own source.
pub(crate) fn source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        EDGE_SEGMENTS_WGSL,
        include_str!("edges.wgsl"),
    ])
}

/// The pass's pipelines and bind group layout.
pub(crate) struct EdgesPass {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    colour: wgpu::TextureFormat,
    /// By [`EdgePipeline::index`], each built on first use.
    pipelines: [OnceLock<wgpu::RenderPipeline>; EdgePipeline::COUNT],
    layout: wgpu::BindGroupLayout,
    /// Whether the adapter can test against the depth the shader also reads
    /// ([`crate::Gpu::read_only_depth`]; GL cannot): else the shader alone drops hidden edges.
    read_only_depth: bool,
    /// The margin past edge-on beyond which segments between two faces turned away are
    /// dropped (`BACK_MARGIN`), or `None` to draw them (`CULL_BEHIND` unset).
    behind_margin: Option<f32>,
    /// The instances' layout, for the compute rasterizer's pipeline.
    instances: InstanceLayout,
    /// The compute rasterizer, built on first use; `None` inside where the adapter has no
    /// compute shaders or the renderer was told to draw quads only.
    raster: OnceLock<Option<EdgeRaster>>,
    /// Whether the compute rasterizer may be used ([`crate::Gpu::compute`], and not turned
    /// off by [`EdgesPass::set_raster`]).
    raster_allowed: bool,
    /// The fewest segments (all instances counted) a frame rasterizes in compute
    /// ([`RASTER_FROM`]).
    raster_from: u64,
    /// Frames whose edges were rasterized in compute, for the tests that compare the paths.
    rastered_frames: std::sync::atomic::AtomicUsize,
}

/// The fewest segments a frame rasterizes in compute: below, the compute pass, its clear and
/// its full-screen composite cost more than the quads they save. Measured at 1280×960: on
/// lavapipe (2 cores) the three cost ≈ 6 ms a frame, a quad ≈ 0.43 µs of the submitting
/// thread and a segment rasterized in compute ≈ 0.04 µs, so compute pays from ≈ 15,000
/// segments (trj4_pm2-ec-214, 8,347 segments: 28 → 32 ms in compute, pr2db 23 → 30 ms; the
/// 100× scene, 165,600 segments: 175 → 115 ms). On an H200 the small files' frames went
/// from 1.1–1.4 ms to 1.3–3.0 ms in compute, the 100× scene's from 3.7 to 3.3 ms and the
/// 10 M-triangle scene's (1.5 M segments) from 26.8 to 21.3 ms.
const RASTER_FROM: u64 = 16_384;

/// `BACK_MARGIN` of edges.wgsl, its default.
const BACK_MARGIN: f32 = 0.25;

/// What tells the pass's pipelines apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct EdgePipeline {
    /// The direct calls' records read as instance-step attributes (`vs_main_direct`), else
    /// instances composed through the call slot (`vs_main`).
    direct: bool,
    /// Hidden fragments dropped by a depth test against the visibility depth before they are
    /// shaded (`DEPTH_TESTED`; the visible-edges mode), else by the shader.
    depth_tested: bool,
    /// The frame has section planes (`SECTIONS`).
    sections: bool,
    /// The other segments were rasterized in compute: only the highlighted ones are drawn
    /// (`RASTERED`).
    rastered: bool,
    /// The hidden-line mode: dashes on each edge's arc length (`DASH_ARC`).
    dashed: bool,
}

impl EdgePipeline {
    /// The kinds there are.
    const COUNT: usize = 32;

    /// Its place in [`EdgesPass::pipelines`].
    fn index(self) -> usize {
        usize::from(self.direct)
            + 2 * usize::from(self.depth_tested)
            + 4 * usize::from(self.sections)
            + 8 * usize::from(self.rastered)
            + 16 * usize::from(self.dashed)
    }
}

impl EdgesPass {
    /// Prepares the pass for a `colour` target of that format; each pipeline is built on
    /// first use.
    pub fn new(
        gpu: &crate::Gpu,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
    ) -> EdgesPass {
        let device = &gpu.device;
        let module = shader(device, "edges", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "edges", &entries(BINDINGS, stages), Some(instances));
        EdgesPass {
            module,
            pipeline_layout,
            colour,
            pipelines: std::array::from_fn(|_| OnceLock::new()),
            layout,
            read_only_depth: gpu.read_only_depth,
            behind_margin: Some(BACK_MARGIN),
            instances: instances.clone(),
            raster: OnceLock::new(),
            raster_allowed: gpu.compute,
            raster_from: RASTER_FROM,
            rastered_frames: Default::default(),
        }
    }

    /// Sets the margin of [`EdgesPass::behind_margin`] (before any frame: the pipelines are
    /// built again).
    pub fn set_behind_margin(&mut self, margin: Option<f32>) {
        self.behind_margin = margin;
        self.pipelines = std::array::from_fn(|_| OnceLock::new());
        self.raster = OnceLock::new();
    }

    /// Allows the compute rasterizer (where the adapter has compute shaders) for frames of
    /// at least `from` segments, or draws every segment as a quad (`None`).
    pub fn set_raster(&mut self, from: Option<u64>) {
        self.raster_allowed = from.is_some();
        self.raster_from = from.unwrap_or(u64::MAX);
        self.raster = OnceLock::new();
    }

    /// How many frames rasterized their edges in compute.
    pub fn rastered_frames(&self) -> usize {
        self.rastered_frames
            .load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The compute rasterizer, built on first use, if allowed.
    fn raster(&self, device: &wgpu::Device) -> Option<&EdgeRaster> {
        self.raster
            .get_or_init(|| {
                self.raster_allowed.then(|| {
                    EdgeRaster::new(
                        device,
                        self.colour,
                        &self.instances,
                        (
                            self.behind_margin.is_some(),
                            self.behind_margin.unwrap_or(BACK_MARGIN),
                        ),
                    )
                })
            })
            .as_ref()
    }

    /// The pipeline of `kind`, built on first use.
    fn pipeline(&self, device: &wgpu::Device, kind: EdgePipeline) -> &wgpu::RenderPipeline {
        self.pipelines[kind.index()].get_or_init(|| {
            let records = [Some(record_instance_layout())];
            let flag = |on: bool| if on { 1.0 } else { 0.0 };
            pipeline(
                device,
                PipelineSpec {
                    label: "edges",
                    layout: &self.pipeline_layout,
                    module: &self.module,
                    vertex: if kind.direct {
                        "vs_main_direct"
                    } else {
                        "vs_main"
                    },
                    cull: None,
                    fragment: "fs_main",
                    buffers: if kind.direct { &records } else { &[] },
                    // The shader folds the tolerance into its depth.
                    depth: kind.depth_tested.then(tested_not_written),
                    targets: &[Some(blended(self.colour))],
                    constants: &[
                        ("DEPTH_TESTED", flag(kind.depth_tested)),
                        ("SECTIONS", flag(kind.sections)),
                        ("RASTERED", flag(kind.rastered)),
                        ("DASH_ARC", flag(kind.dashed)),
                        ("CULL_BEHIND", flag(self.behind_margin.is_some())),
                        (
                            "BACK_MARGIN",
                            f64::from(self.behind_margin.unwrap_or(BACK_MARGIN)),
                        ),
                    ],
                },
            )
        })
    }

    /// Records the pass over `target` (kept, blended onto) for the frame `uniform` holds
    /// (its edge mode and section planes pick the pipelines).
    pub fn record(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        (frame, selection): (&wgpu::Buffer, &wgpu::Buffer),
        (scene, uniform): (&FrameScene<'_>, &FrameUniform),
        target: &wgpu::TextureView,
    ) {
        if scene.edge_calls.is_empty() {
            return;
        }
        let visible_only = uniform.modes[2] == EDGES_VISIBLE;
        let depth_tested = visible_only && self.read_only_depth;
        let sections = uniform.counts[2] > 0;
        let size = (uniform.viewport[0] as u32, uniform.viewport[1] as u32);
        let segments: u64 = scene
            .edge_calls
            .iter()
            .map(|c| u64::from(c.count) * u64::from(c.instances))
            .sum();
        let raster = (visible_only && !sections && segments >= self.raster_from)
            .then(|| self.raster(device))
            .flatten()
            .filter(|r| r.fits(size));
        if let Some(raster) = raster {
            raster.record(
                (device, binds),
                encoder,
                visibility,
                (frame, selection),
                scene,
                size,
                target,
            );
            self.rastered_frames
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            // The quads are left only the highlighted segments: none without a selection or
            // a hovered item.
            let highlights = uniform.counts[1] > 0 || uniform.hover[0] != 0;
            if !highlights {
                return;
            }
        }
        let bind = binds.get(
            device,
            "edges",
            &self.layout,
            &segment_bindings(frame, scene, visibility, selection),
        );
        // The visibility depth read only, for the depth-tested pipelines.
        let depth = depth_tested.then_some(&visibility.depth);
        let mut pass = colour_pass(encoder, "edges", (target, None), depth);
        pass.set_bind_group(0, &bind, &[]);
        pass.set_index_buffer(
            scene.geometry.quad_indices.slice(..),
            wgpu::IndexFormat::Uint32,
        );
        // The pipeline is set again only when the way of reading the records changes.
        let mut current = None;
        for call in &scene.edge_calls {
            let kind = EdgePipeline {
                direct: call.direct.is_some(),
                depth_tested,
                sections,
                rastered: raster.is_some(),
                dashed: uniform.modes[2] == crate::layout::EDGES_HIDDEN_DASHED,
            };
            if current != Some(kind) {
                pass.set_pipeline(self.pipeline(device, kind));
                current = Some(kind);
            }
            draw_segment_call(&mut pass, &scene.instances, call, kind.direct);
        }
    }
}

/// The bindings 0–3 that the quads and the compute rasterizer share (`segments.wgsl`): the
/// frame, the segments, the visibility depth, the selection.
fn segment_bindings<'a>(
    frame: &'a wgpu::Buffer,
    scene: &'a FrameScene<'_>,
    visibility: &'a VisibilityTargets,
    selection: &'a wgpu::Buffer,
) -> [wgpu::BindingResource<'a>; 4] {
    [
        frame.as_entire_binding(),
        scene.geometry.segments.as_entire_binding(),
        wgpu::BindingResource::TextureView(&visibility.depth),
        selection.as_entire_binding(),
    ]
}

#[cfg(test)]
mod tests {
    use super::EdgePipeline;

    /// Each kind has its own slot (a shared one would hand a call another's pipeline).
    #[test]
    fn edge_pipelines_have_distinct_slots() {
        let mut seen = std::collections::BTreeSet::new();
        for bits in 0..32u8 {
            let kind = EdgePipeline {
                direct: bits & 1 != 0,
                depth_tested: bits & 2 != 0,
                sections: bits & 4 != 0,
                rastered: bits & 8 != 0,
                dashed: bits & 16 != 0,
            };
            assert!(kind.index() < EdgePipeline::COUNT, "{kind:?}");
            assert!(seen.insert(kind.index()), "{kind:?}");
        }
    }
}
