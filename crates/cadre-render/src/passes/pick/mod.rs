//! Pick pass: B-Rep edges and vertices into an id target, for picking with a few pixels of
//! tolerance (faces are picked from the visibility buffer's ids).

use super::common::{
    PipelineSpec, bind_group, colour_pass, draw_segments, entries, layouts, pipeline, shader, wgsl,
};
use super::visibility::VisibilityTargets;
use crate::gpu_scene::{EdgeCall, FrameInstances};
use crate::layout::{Binding, FrameUniform, GpuStruct, PickRegion, Segment};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};

/// Bind group 0: frame (its projection cropped to the pick window), segments, the
/// visibility buffer's ids, where the window lies in them, its depth (group 1: the
/// instances).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Segment::WGSL_NAME),
    Binding::UintTexture,
    Binding::Uniform(PickRegion::WGSL_NAME),
    Binding::FloatTexture,
];

/// The pass's whole WGSL: the shared declarations and its own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, include_str!("pick.wgsl")])
}

/// Edge or vertex id, instance + 1 (0 = nothing), kind (2 edge, 3 vertex), unused.
pub(crate) const PICK: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// The pass's pipelines (edges and vertices; the faces' copy) and bind group layout.
pub(crate) struct PickPass {
    pipeline: wgpu::RenderPipeline,
    faces: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// The buffers a pick pass reads: the frame's uniform (cropped) and the window's place, the
/// instances, the segments.
pub(crate) struct PickInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub region: &'a wgpu::Buffer,
    pub instances: &'a FrameInstances,
    pub segments: &'a wgpu::Buffer,
    /// The segments' quad indices (`PreparedScene::quad_indices`).
    pub quads: &'a wgpu::Buffer,
    pub calls: &'a [EdgeCall],
}

impl PickPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, instances: &InstanceLayout) -> PickPass {
        let module = shader(device, "pick", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "pick", &entries(BINDINGS, stages), Some(instances));
        let lines = pipeline(
            device,
            PipelineSpec {
                label: "pick",
                layout: &pipeline_layout,
                module: &module,
                vertex: "vs_main",
                cull: None,
                fragment: "fs_main",
                buffers: &[],
                depth: None,
                targets: &[Some(PICK.into())],
                constants: &[],
            },
        );
        // The faces' copy binds group 0 alone (no instances).
        let faces_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("pick faces"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let faces = pipeline(
            device,
            PipelineSpec {
                label: "pick faces",
                layout: &faces_layout,
                module: &module,
                vertex: "vs_faces",
                cull: None,
                fragment: "fs_faces",
                buffers: &[],
                depth: None,
                targets: &[Some(PICK.into())],
                constants: &[],
            },
        );
        PickPass {
            pipeline: lines,
            faces,
            layout,
        }
    }

    /// Records the pass: the faces under the window into `faces`, the edges and vertices
    /// into `lines` (both the pick window's size).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        inputs: &PickInputs<'_>,
        (faces, lines): (&wgpu::TextureView, &wgpu::TextureView),
    ) {
        let bind = bind_group(
            device,
            "pick",
            &self.layout,
            &[
                inputs.frame.as_entire_binding(),
                inputs.segments.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.ids),
                inputs.region.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.depth),
            ],
        );
        {
            // Every pixel written: no clear.
            let mut pass = colour_pass(encoder, "pick faces", (faces, None), None);
            pass.set_pipeline(&self.faces);
            pass.set_bind_group(0, &bind, &[]);
            pass.draw(0..3, 0..1);
        }
        let mut pass = colour_pass(
            encoder,
            "pick",
            (lines, Some(wgpu::Color::TRANSPARENT)),
            None,
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_segments(&mut pass, inputs.instances, inputs.calls, inputs.quads);
    }
}
