//! The mesh back-end of the visibility pass: the scene's triangles, instanced over their
//! draw records.

use super::{TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state};
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, FrameUniform, GpuStruct};
use crate::passes::common::{
    PipelineSpec, draw_mesh_call, entries, layouts, mesh_vertex_layout, pipeline, shader, wgsl,
};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use std::sync::OnceLock;

/// Bind group 0: the frame (group 1: the instances, [`crate::layout::INSTANCE_BINDINGS`]).
pub(crate) const BINDINGS: &[Binding] = &[Binding::Uniform(FrameUniform::WGSL_NAME)];

/// The back-end's whole WGSL: the shared declarations, the instances, the texel writer, its
/// own source.
pub(crate) fn source() -> String {
    wgsl(&[INSTANCES_WGSL, TEXEL_WGSL, include_str!("mesh.wgsl")])
}

/// The back-end's pipelines and bind group layout: the plain one (no section plane, no (u, v)
/// target; `vs_plain`/`fs_plain`, every image and viewer frame without sections), and, built
/// on first use, the one with section planes and caps, and the one that also writes the
/// (u, v) target.
pub(crate) struct MeshBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    plain: wgpu::RenderPipeline,
    /// The plain pipeline culling back faces, then front faces (closed solids' calls,
    /// `DrawCall::cull`), built on first use.
    plain_culling: [OnceLock<wgpu::RenderPipeline>; 2],
    sections: OnceLock<wgpu::RenderPipeline>,
    with_uv: OnceLock<wgpu::RenderPipeline>,
    layout: wgpu::BindGroupLayout,
}

/// Which of the back-end's pipelines a frame draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MeshVariant {
    /// No section plane, no (u, v): only the varyings the texel needs.
    Plain,
    /// Section planes (cut fragments, caps), no (u, v).
    Sections,
    /// Sections and the (u, v) target (the exact-surface tests' readback).
    WithUv,
}

impl MeshVariant {
    /// The variant of a frame with `sections` planes that reads the (u, v) back or not.
    pub fn of(sections: bool, with_uv: bool) -> MeshVariant {
        match (sections, with_uv) {
            (_, true) => MeshVariant::WithUv,
            (true, false) => MeshVariant::Sections,
            (false, false) => MeshVariant::Plain,
        }
    }
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
        let plain = mesh_pipeline(
            device,
            (&pipeline_layout, &module),
            (MeshVariant::Plain, None),
        );
        MeshBackend {
            module,
            pipeline_layout,
            plain,
            plain_culling: [OnceLock::new(), OnceLock::new()],
            sections: OnceLock::new(),
            with_uv: OnceLock::new(),
            layout,
        }
    }

    /// Draws every call of `scene` into the opened visibility pass.
    pub fn draw(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
        variant: MeshVariant,
    ) {
        let bind = binds.get(
            device,
            "visibility mesh",
            &self.layout,
            &[frame.as_entire_binding()],
        );
        let parts = (&self.pipeline_layout, &self.module);
        let pipeline = |cull: Option<wgpu::Face>| match (variant, cull) {
            (MeshVariant::Plain, None) => &self.plain,
            (MeshVariant::Plain, Some(face)) => {
                let k = usize::from(face == wgpu::Face::Front);
                self.plain_culling[k].get_or_init(|| mesh_pipeline(device, parts, (variant, cull)))
            }
            // With section planes back faces show the caps: nothing is culled.
            (MeshVariant::Sections, _) => self
                .sections
                .get_or_init(|| mesh_pipeline(device, parts, (variant, None))),
            (MeshVariant::WithUv, _) => self
                .with_uv
                .get_or_init(|| mesh_pipeline(device, parts, (variant, None))),
        };
        pass.set_bind_group(0, &bind, &[]);
        // The pipeline is set again only when the culling changes between calls.
        let mut current: Option<Option<wgpu::Face>> = None;
        for call in &scene.calls {
            if current != Some(call.cull) {
                pass.set_pipeline(pipeline(call.cull));
                current = Some(call.cull);
            }
            draw_mesh_call(pass, scene, call);
        }
    }
}

/// The back-end's pipeline of `variant`, culling `cull`.
fn mesh_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::PipelineLayout, &wgpu::ShaderModule),
    (variant, cull): (MeshVariant, Option<wgpu::Face>),
) -> wgpu::RenderPipeline {
    let (vertex, fragment, sections, targets) = match variant {
        MeshVariant::Plain => ("vs_plain", "fs_plain", 0.0, &TARGETS_NO_UV),
        MeshVariant::Sections => ("vs_main", "fs_main", 1.0, &TARGETS_NO_UV),
        MeshVariant::WithUv => ("vs_main", "fs_main", 1.0, &TARGETS),
    };
    pipeline(
        device,
        PipelineSpec {
            label: "visibility mesh",
            layout,
            module,
            vertex,
            cull,
            fragment,
            buffers: &[Some(mesh_vertex_layout())],
            depth: Some(depth_state()),
            targets,
            constants: &[("SECTIONS", sections)],
        },
    )
}
