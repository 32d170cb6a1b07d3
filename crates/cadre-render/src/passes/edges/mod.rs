//! Edges pass: wire bodies and B-Rep edges drawn over the shaded image as anti-aliased lines
//! of constant pixel width, visible, hidden-dashed or all, by the display mode.

use super::common::{
    PipelineSpec, blended, colour_pass, draw_segments, entries, layouts, pipeline, shader, wgsl,
};
use super::visibility::VisibilityTargets;
use crate::frame_buffers::BindCache;
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, FrameUniform, GpuStruct, Segment};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};

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

/// The pass's pipeline and bind group layout.
pub(crate) struct EdgesPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl EdgesPass {
    /// Builds the pipeline for a `colour` target of that format.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
    ) -> EdgesPass {
        let module = shader(device, "edges", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "edges", &entries(BINDINGS, stages), Some(instances));
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "edges",
                layout: &pipeline_layout,
                module: &module,
                vertex: "vs_main",
                cull: None,
                fragment: "fs_main",
                buffers: &[],
                depth: None,
                targets: &[Some(blended(colour))],
                constants: &[],
            },
        );
        EdgesPass { pipeline, layout }
    }

    /// Records the pass over `target` (kept, blended onto).
    pub fn record(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        (frame, selection): (&wgpu::Buffer, &wgpu::Buffer),
        scene: &FrameScene<'_>,
        target: &wgpu::TextureView,
    ) {
        if scene.edge_calls.is_empty() {
            return;
        }
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
        let mut pass = colour_pass(encoder, "edges", target, None);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_segments(
            &mut pass,
            &scene.instances,
            &scene.edge_calls,
            &scene.geometry.quad_indices,
        );
    }
}
