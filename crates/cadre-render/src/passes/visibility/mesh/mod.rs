//! The mesh back-end of the visibility pass: the scene's triangles, instanced over their
//! draw records.

use super::{TARGETS, TEXEL_WGSL, depth_state};
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, Frame, GpuStruct};
use crate::passes::common::{
    PipelineSpec, bind_group, draw_meshes, entries, layouts, mesh_vertex_layout, pipeline, shader,
    wgsl,
};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};

/// Bind group 0: the frame (group 1: the instances, [`crate::layout::INSTANCE_BINDINGS`]).
pub(crate) const BINDINGS: &[Binding] = &[Binding::Uniform(Frame::WGSL_NAME)];

/// The back-end's whole WGSL: the shared declarations, the instances, the texel writer, its
/// own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, TEXEL_WGSL, include_str!("mesh.wgsl")])
}

/// The back-end's pipeline and bind group layout.
pub(crate) struct MeshBackend {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl MeshBackend {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, instances: &InstanceLayout) -> MeshBackend {
        let module = shader(device, "visibility mesh", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(
            device,
            "visibility mesh",
            &entries(BINDINGS, stages),
            Some(instances),
        );
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "visibility mesh",
                layout: &pipeline_layout,
                module: &module,
                fragment: "fs_main",
                buffers: &[Some(mesh_vertex_layout())],
                depth: Some(depth_state()),
                targets: &TARGETS,
                constants: &[],
            },
        );
        MeshBackend { pipeline, layout }
    }

    /// Draws every call of `scene` into the opened visibility pass.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
    ) {
        let bind = bind_group(
            device,
            "visibility mesh",
            &self.layout,
            &[frame.as_entire_binding()],
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(pass, scene, &scene.calls);
    }
}
