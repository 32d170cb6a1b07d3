//! X-ray pass: the meshes drawn see-through over the background, before the edges.

use super::common::{
    PipelineSpec, blended, colour_pass, draw_meshes, entries, layouts, mesh_vertex_layout,
    pipeline, shader, wgsl,
};
use super::visibility::{DEPTH, VisibilityTargets};
use crate::frame_buffers::BindCache;
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, FrameUniform, GpuStruct, Material};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};

/// Bind group 0: frame, materials (group 1: the instances).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Material::WGSL_NAME),
];

/// The pass's whole WGSL: the shared declarations and its own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, include_str!("xray.wgsl")])
}

/// The pass's pipeline and bind group layout.
pub(crate) struct XrayPass {
    pipeline: wgpu::RenderPipeline,
    /// See-through parts of an opaque view: lit, blended, hidden behind the opaque depth.
    transparent: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl XrayPass {
    /// Builds the pipeline for a `colour` target of that format.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
    ) -> XrayPass {
        let module = shader(device, "xray", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "xray", &entries(BINDINGS, stages), Some(instances));
        let buffers = [Some(mesh_vertex_layout())];
        let targets = [Some(blended(colour))];
        let spec = |label, fragment, depth| PipelineSpec {
            label,
            layout: &pipeline_layout,
            module: &module,
            vertex: "vs_main",
            cull: None,
            fragment,
            buffers: &buffers,
            depth,
            targets: &targets,
            constants: &[],
        };
        let xray = pipeline(device, spec("xray", "fs_main", None));
        let transparent = pipeline(
            device,
            spec(
                "transparent",
                "fs_transparent",
                Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(false),
                    // Reverse Z: in front of the opaque surfaces (or on them).
                    depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
            ),
        );
        XrayPass {
            pipeline: xray,
            transparent,
            layout,
        }
    }

    /// Records the pass over `target` (kept, blended onto): every opaque call see-through.
    pub fn record(
        &self,
        recorder: (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
        target: &wgpu::TextureView,
    ) {
        let bind = self.bind(recorder, frame, scene);
        let mut pass = colour_pass(encoder, "xray", target, None);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(&mut pass, scene, &scene.calls);
        draw_meshes(&mut pass, scene, &scene.transparent);
    }

    /// Records the see-through parts of an opaque view over `target`, tested against the
    /// visibility depth (drawn in scene order, not sorted).
    pub fn record_transparent(
        &self,
        recorder: (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
        (visibility, target): (&VisibilityTargets, &wgpu::TextureView),
    ) {
        if scene.transparent.is_empty() {
            return;
        }
        let bind = self.bind(recorder, frame, scene);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("transparent"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &visibility.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.transparent);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(&mut pass, scene, &scene.transparent);
    }

    fn bind(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
    ) -> wgpu::BindGroup {
        binds.get(
            device,
            "xray",
            &self.layout,
            &[
                frame.as_entire_binding(),
                scene.materials.as_entire_binding(),
            ],
        )
    }
}
