//! Edges pass: wire bodies and B-Rep edges drawn over the shaded image as anti-aliased lines
//! of constant pixel width, visible, hidden-dashed or all, by the display mode.

use super::common::{
    PipelineSpec, blended, colour_pass, draw_segment_call, entries, layouts, pipeline,
    record_instance_layout, shader, wgsl,
};
use super::visibility::{VisibilityTargets, tested_not_written};
use crate::frame_buffers::BindCache;
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, EDGES_VISIBLE, FrameUniform, GpuStruct, Segment};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use std::sync::OnceLock;

/// Bind group 0: frame, segments, the visibility depth, selection (group 1: the instances).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Segment::WGSL_NAME),
    Binding::FloatTexture,
    Binding::Storage("vec4<u32>"),
];

/// The pass's whole WGSL: the shared declarations and its own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, include_str!("edges.wgsl")])
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
}

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
}

impl EdgePipeline {
    /// The kinds there are.
    const COUNT: usize = 8;

    /// Its place in [`EdgesPass::pipelines`].
    fn index(self) -> usize {
        usize::from(self.direct)
            + 2 * usize::from(self.depth_tested)
            + 4 * usize::from(self.sections)
    }
}

impl EdgesPass {
    /// Prepares the pass for a `colour` target of that format; each pipeline is built on
    /// first use. `read_only_depth`: [`crate::Gpu::read_only_depth`].
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
        read_only_depth: bool,
    ) -> EdgesPass {
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
            read_only_depth,
            behind_margin: Some(BACK_MARGIN),
        }
    }

    /// Sets the margin of [`EdgesPass::behind_margin`] (before any frame: the pipelines are
    /// built again).
    pub fn set_behind_margin(&mut self, margin: Option<f32>) {
        self.behind_margin = margin;
        self.pipelines = std::array::from_fn(|_| OnceLock::new());
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
        let bind = binds.get(
            device,
            "edges",
            &self.layout,
            &[
                frame.as_entire_binding(),
                scene.geometry.segments.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.depth),
                selection.as_entire_binding(),
            ],
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
            };
            if current != Some(kind) {
                pass.set_pipeline(self.pipeline(device, kind));
                current = Some(kind);
            }
            draw_segment_call(&mut pass, &scene.instances, call, kind.direct);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::EdgePipeline;

    /// Each kind has its own slot (a shared one would hand a call another's pipeline).
    #[test]
    fn edge_pipelines_have_distinct_slots() {
        let mut seen = std::collections::BTreeSet::new();
        for bits in 0..8u8 {
            let kind = EdgePipeline {
                direct: bits & 1 != 0,
                depth_tested: bits & 2 != 0,
                sections: bits & 4 != 0,
            };
            assert!(kind.index() < EdgePipeline::COUNT, "{kind:?}");
            assert!(seen.insert(kind.index()), "{kind:?}");
        }
    }
}
