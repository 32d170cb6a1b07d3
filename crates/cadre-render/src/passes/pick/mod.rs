//! Pick pass: B-Rep edges and vertices into an id target, for picking with a few pixels of
//! tolerance (faces are picked from the visibility buffer's ids).

use super::common::{
    PipelineSpec, bind_group, colour_pass, entries, layouts, pipeline, shader, wgsl,
};
use super::visibility::VisibilityTargets;
use crate::gpu_scene::EdgeCall;
use crate::layout::{Binding, Draw, Frame, GpuStruct, Segment};

/// Bind group 0: frame, draw records, segments, the id target.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(Frame::WGSL_NAME),
    Binding::Storage(Draw::WGSL_NAME),
    Binding::Storage(Segment::WGSL_NAME),
    Binding::UintTexture,
];

/// The pass's whole WGSL: the shared declarations and its own source.
pub(crate) fn source() -> String {
    wgsl(&[include_str!("pick.wgsl")])
}

/// STEP id, instance + 1 (0 = nothing), kind (2 edge, 3 vertex), unused.
pub(crate) const PICK: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// The pass's pipeline and bind group layout.
pub(crate) struct PickPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// The buffers a pick pass reads: the frame's uniform and draw records, the segments.
pub(crate) struct PickInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub draws: &'a wgpu::Buffer,
    pub segments: &'a wgpu::Buffer,
    pub calls: &'a [EdgeCall],
}

impl PickPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> PickPass {
        let module = shader(device, "pick", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(device, "pick", &entries(BINDINGS, stages));
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "pick",
                layout: &pipeline_layout,
                module: &module,
                fragment: "fs_main",
                buffers: &[],
                depth: None,
                targets: &[Some(PICK.into())],
            },
        );
        PickPass { pipeline, layout }
    }

    /// Records the pass into `target` (cleared first).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        inputs: &PickInputs<'_>,
        target: &wgpu::TextureView,
    ) {
        let bind = bind_group(
            device,
            "pick",
            &self.layout,
            &[
                inputs.frame.as_entire_binding(),
                inputs.draws.as_entire_binding(),
                inputs.segments.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.ids),
            ],
        );
        let mut pass = colour_pass(encoder, "pick", target, Some(wgpu::Color::TRANSPARENT));
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        for call in inputs.calls {
            pass.draw(
                call.first * 6..(call.first + call.count) * 6,
                call.draw..call.draw + call.instances,
            );
        }
    }
}
