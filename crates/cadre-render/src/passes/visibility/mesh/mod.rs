//! The mesh back-end of the visibility pass: the scene's triangles, instanced over their
//! draw records.

use super::{TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state};
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, Frame, GpuStruct};
use crate::passes::common::{
    PipelineSpec, bind_group, draw_meshes, entries, layouts, mesh_vertex_layout, pipeline, shader,
    wgsl,
};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use std::sync::OnceLock;

/// Bind group 0: the frame (group 1: the instances, [`crate::layout::INSTANCE_BINDINGS`]).
pub(crate) const BINDINGS: &[Binding] = &[Binding::Uniform(Frame::WGSL_NAME)];

/// The back-end's whole WGSL: the shared declarations, the instances, the texel writer, its
/// own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, TEXEL_WGSL, include_str!("mesh.wgsl")])
}

/// The back-end's pipelines (without the (u, v) target, and with it, built on first use)
/// and bind group layout.
pub(crate) struct MeshBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    pipeline: wgpu::RenderPipeline,
    with_uv: OnceLock<wgpu::RenderPipeline>,
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
        let pipeline = mesh_pipeline(device, (&pipeline_layout, &module), &TARGETS_NO_UV);
        MeshBackend {
            module,
            pipeline_layout,
            pipeline,
            with_uv: OnceLock::new(),
            layout,
        }
    }

    /// Draws every call of `scene` into the opened visibility pass.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
        with_uv: bool,
    ) {
        let bind = bind_group(
            device,
            "visibility mesh",
            &self.layout,
            &[frame.as_entire_binding()],
        );
        let pipeline = if with_uv {
            self.with_uv.get_or_init(|| {
                mesh_pipeline(device, (&self.pipeline_layout, &self.module), &TARGETS)
            })
        } else {
            &self.pipeline
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(pass, scene, &scene.calls);
    }
}

/// The back-end's pipeline writing `targets` (all three, or without the (u, v)).
fn mesh_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::PipelineLayout, &wgpu::ShaderModule),
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    pipeline(
        device,
        PipelineSpec {
            label: "visibility mesh",
            layout,
            module,
            fragment: "fs_main",
            buffers: &[Some(mesh_vertex_layout())],
            depth: Some(depth_state()),
            targets,
            constants: &[],
        },
    )
}
