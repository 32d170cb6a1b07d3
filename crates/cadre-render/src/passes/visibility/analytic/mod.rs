//! The analytic back-end of the visibility pass: spheres and rectangles ray cast per pixel
//! ([`crate::AnalyticPrimitive`]), drawn into the pass the mesh back-end drew into, through
//! the same texel writer. Pipelines are built on the first frame that has primitives.

use std::sync::OnceLock;

use super::{TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state};
use crate::layout::{Binding, FrameUniform, GpuStruct, Primitive};
use crate::passes::common::{PipelineSpec, entries, layouts, pipeline, shader, wgsl};

/// Bind group 0: the frame, the frame's primitives.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Primitive::WGSL_NAME),
];

/// Vertices of a primitive's proxy: a bounding cube's 12 triangles (a rectangle uses 2).
const PROXY_VERTICES: u32 = 36;

/// The back-end's whole WGSL: the shared declarations, the texel writer, its own source.
pub(crate) fn source() -> String {
    wgsl(&[TEXEL_WGSL, include_str!("analytic.wgsl")])
}

/// The back-end's pipelines (with and without the (u, v) target; with the proxy's depth for
/// the tests' negative control) and bind group layout.
pub(crate) struct AnalyticBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    layout: wgpu::BindGroupLayout,
    /// Indexed by `with_uv + 2 × proxy_depth`.
    pipelines: [OnceLock<wgpu::RenderPipeline>; 4],
}

/// One frame's primitives on the GPU.
pub(crate) struct FramePrimitives {
    pub buffer: wgpu::Buffer,
    pub count: u32,
}

impl AnalyticBackend {
    /// Compiles the shader; pipelines come on first use.
    pub fn new(device: &wgpu::Device) -> AnalyticBackend {
        let module = shader(device, "visibility analytic", &source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(
            device,
            "visibility analytic",
            &entries(BINDINGS, stages),
            None,
        );
        AnalyticBackend {
            module,
            pipeline_layout,
            layout,
            pipelines: Default::default(),
        }
    }

    /// Draws the frame's primitives into the opened visibility pass; `proxy_depth` writes
    /// the proxy's depth instead of the hit's (only for the tests' negative control).
    pub fn draw(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::Buffer,
        primitives: &FramePrimitives,
        (with_uv, proxy_depth): (bool, bool),
    ) {
        if primitives.count == 0 {
            return;
        }
        let k = usize::from(with_uv) + 2 * usize::from(proxy_depth);
        let pipeline = self.pipelines[k].get_or_init(|| {
            pipeline(
                device,
                PipelineSpec {
                    label: "visibility analytic",
                    layout: &self.pipeline_layout,
                    module: &self.module,
                    vertex: "vs_main",
                    // Both sides: from inside a sphere's cube only its back faces are drawn.
                    cull: None,
                    fragment: "fs_main",
                    buffers: &[],
                    depth: Some(depth_state()),
                    targets: if with_uv { &TARGETS } else { &TARGETS_NO_UV },
                    constants: &[("EXACT_DEPTH", if proxy_depth { 0.0 } else { 1.0 })],
                },
            )
        });
        let bind = binds.get(
            device,
            "visibility analytic",
            &self.layout,
            &[
                frame.as_entire_binding(),
                primitives.buffer.as_entire_binding(),
            ],
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..PROXY_VERTICES, 0..primitives.count);
    }
}
