//! X-ray pass: the meshes drawn see-through over the background, before the edges.

use super::common::{
    PipelineSpec, STORAGE, bind_group, blended, buffer_entry, colour_pass, draw_meshes, layouts,
    mesh_vertex_layout, pipeline, shader,
};
use crate::gpu_scene::GpuScene;

/// The pass's pipeline and bind group layout.
pub(crate) struct XrayPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl XrayPass {
    /// Builds the pipeline for a `colour` target of that format.
    pub fn new(device: &wgpu::Device, colour: wgpu::TextureFormat) -> XrayPass {
        let module = shader(device, "xray", include_str!("xray.wgsl"));
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(
            device,
            "xray",
            &[
                buffer_entry(0, wgpu::BufferBindingType::Uniform, stages),
                buffer_entry(1, STORAGE, stages),
                buffer_entry(2, STORAGE, stages),
            ],
        );
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "xray",
                layout: &pipeline_layout,
                module: &module,
                buffers: &[Some(mesh_vertex_layout())],
                depth: None,
                targets: &[Some(blended(colour))],
            },
        );
        XrayPass { pipeline, layout }
    }

    /// Records the pass over `target` (kept, blended onto).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        scene: &GpuScene,
        target: &wgpu::TextureView,
    ) {
        let bind = bind_group(
            device,
            "xray",
            &self.layout,
            &[
                frame.as_entire_binding(),
                scene.draws.as_entire_binding(),
                scene.materials.as_entire_binding(),
            ],
        );
        let mut pass = colour_pass(encoder, "xray", target, None);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(&mut pass, scene);
    }
}
