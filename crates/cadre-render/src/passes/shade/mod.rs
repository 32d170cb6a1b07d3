//! Shading pass: lights the visibility buffer into the colour target.

use super::common::{PipelineSpec, bind_group, entries, layouts, pipeline, shader, wgsl};
use super::visibility::{DEPTH, VisibilityTargets};
use crate::layout::{Binding, Frame, GpuStruct, LightGpu, Material};

/// Bind group 0: frame, materials, the normal and id targets, lights, selection.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(Frame::WGSL_NAME),
    Binding::Storage(Material::WGSL_NAME),
    Binding::FloatTexture,
    Binding::UintTexture,
    Binding::Storage(LightGpu::WGSL_NAME),
    Binding::Storage("vec4<u32>"),
];

/// The pass's whole WGSL: the shared declarations and its own sources, by job (lighting,
/// outlines, section caps, then the pass's entry points and bindings).
pub(crate) fn source() -> String {
    wgsl(&[
        include_str!("lighting.wgsl"),
        include_str!("outlines.wgsl"),
        include_str!("caps.wgsl"),
        include_str!("shade.wgsl"),
    ])
}

/// Format of the offscreen colour target (linear output, sRGB encoding on write); window
/// surfaces bring theirs (`Renderer::for_format`).
pub(crate) const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The buffers the pass reads besides the visibility buffer.
pub(crate) struct ShadeInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub materials: &'a wgpu::Buffer,
    pub lights: &'a wgpu::Buffer,
    pub selection: &'a wgpu::Buffer,
    /// The frame's background, linear (sRGB targets encode it on store).
    pub background: wgpu::Color,
}

/// The shade pass's depth state: its screen triangle lies on the far plane (depth 0 in reverse
/// Z) and passes only where the visibility pass left something nearer, so background pixels
/// are cleared, never shaded. A CPU rasterizer (llvmpipe) tests depth before it runs the
/// shader and skips blocks that fail whole: the shading cost follows the model's pixels,
/// not the image's.
fn faces_only() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// The pass's pipeline and bind group layout.
pub(crate) struct ShadePass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl ShadePass {
    /// Builds the pipeline for a `colour` target of that format.
    pub fn new(device: &wgpu::Device, colour: wgpu::TextureFormat) -> ShadePass {
        let module = shader(device, "shade", &source());
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "shade", &entries(BINDINGS, fragment), None);
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "shade",
                layout: &pipeline_layout,
                module: &module,
                fragment: "fs_main",
                buffers: &[],
                depth: Some(faces_only()),
                targets: &[Some(colour.into())],
            },
        );
        ShadePass { pipeline, layout }
    }

    /// Records the pass into `target`, cleared to `background` (linear): only the pixels
    /// that a surface covers are shaded.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        inputs: &ShadeInputs<'_>,
        target: &wgpu::TextureView,
    ) {
        let ShadeInputs {
            frame,
            materials,
            lights,
            selection,
            background,
        } = inputs;
        let bind = bind_group(
            device,
            "shade",
            &self.layout,
            &[
                frame.as_entire_binding(),
                materials.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.normal),
                wgpu::BindingResource::TextureView(&visibility.ids),
                lights.as_entire_binding(),
                selection.as_entire_binding(),
            ],
        );
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shade"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(*background),
                    store: wgpu::StoreOp::Store,
                },
            })],
            // Read only: the depth test keeps the shader off the background.
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &visibility.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
