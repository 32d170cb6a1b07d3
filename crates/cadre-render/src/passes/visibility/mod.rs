//! Visibility pass: the mesh back-end's draw into the visibility buffer.

use super::common::{
    PipelineSpec, bind_group, draw_meshes, entries, layouts, mesh_vertex_layout, pipeline, shader,
};
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, Draw, Frame, GpuStruct};

/// Bind group 0: frame, draw records.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(Frame::WGSL_NAME),
    Binding::Storage(Draw::WGSL_NAME),
];

/// Formats of the visibility buffer.
pub(crate) const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// View-space unit normal (xyz), coverage (w).
pub(crate) const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Face id, instance + 1 (0 = background), material, depth (f32 bits).
pub(crate) const IDS: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// (u, v) on the face's exact surface, as f32 bits (float targets of 32 bits are not
/// renderable on GL, integer ones are).
pub(crate) const UV: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// The pass's pipeline and bind group layout.
pub(crate) struct VisibilityPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// The visibility buffer's textures, of one size.
pub(crate) struct VisibilityTargets {
    pub depth: wgpu::TextureView,
    pub normal: wgpu::TextureView,
    pub ids: wgpu::TextureView,
    pub ids_texture: wgpu::Texture,
    pub uv: wgpu::TextureView,
    pub uv_texture: wgpu::Texture,
}

impl VisibilityTargets {
    /// Targets of `width` × `height`.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> VisibilityTargets {
        let make = |label, format, extra: wgpu::TextureUsages| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | extra,
                view_formats: &[],
            })
        };
        let depth = make("depth", DEPTH, wgpu::TextureUsages::empty());
        let normal = make("normal", NORMAL, wgpu::TextureUsages::empty());
        let ids = make("ids", IDS, wgpu::TextureUsages::COPY_SRC);
        let uv = make("uv", UV, wgpu::TextureUsages::COPY_SRC);
        VisibilityTargets {
            depth: depth.create_view(&Default::default()),
            normal: normal.create_view(&Default::default()),
            ids: ids.create_view(&Default::default()),
            ids_texture: ids,
            uv: uv.create_view(&Default::default()),
            uv_texture: uv,
        }
    }
}

impl VisibilityPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> VisibilityPass {
        let module = shader(device, "visibility", include_str!("visibility.wgsl"));
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(device, "visibility", &entries(BINDINGS, stages));
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "visibility",
                layout: &pipeline_layout,
                module: &module,
                fragment: "fs_main",
                buffers: &[Some(mesh_vertex_layout())],
                depth: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(true),
                    // Reverse Z: nearer is larger.
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                targets: &[Some(NORMAL.into()), Some(IDS.into()), Some(UV.into())],
            },
        );
        VisibilityPass { pipeline, layout }
    }

    /// Records the pass: clears the targets and draws every call of `scene`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        frame: &wgpu::Buffer,
        scene: &FrameScene<'_>,
    ) {
        let bind = bind_group(
            device,
            "visibility",
            &self.layout,
            &[frame.as_entire_binding(), scene.draws.as_entire_binding()],
        );
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("visibility"),
            color_attachments: &[
                clear(&targets.normal),
                clear(&targets.ids),
                clear(&targets.uv),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        draw_meshes(&mut pass, scene, &scene.calls);
    }
}
