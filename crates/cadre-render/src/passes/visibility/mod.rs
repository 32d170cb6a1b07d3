//! Visibility pass: the mesh back-end's draw into the visibility buffer.

use crate::gpu_scene::GpuScene;
use crate::layout::Vertex;

/// Formats of the visibility buffer.
pub(crate) const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// View-space unit normal (xyz), coverage (w).
pub(crate) const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Face id, instance + 1 (0 = background), material, depth (f32 bits).
pub(crate) const IDS: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// (u, v) on the face's exact surface.
pub(crate) const UV: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

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
        let shader = device.create_shader_module(wgpu::include_wgsl!("visibility.wgsl"));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("visibility"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("visibility"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("visibility"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Uint32, 3 => Float32x2],
                })],
            },
            // No culling: open shells and mirrored instances show both sides.
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(true),
                // Reverse Z: nearer is larger.
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(NORMAL.into()), Some(IDS.into()), Some(UV.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        VisibilityPass { pipeline, layout }
    }

    /// Records the pass: clears the targets and draws every call of `scene`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        frame: &wgpu::Buffer,
        scene: &GpuScene,
    ) {
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("visibility"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: scene.draws.as_entire_binding(),
                },
            ],
        });
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
        for call in &scene.calls {
            pass.set_vertex_buffer(0, scene.vertices[call.mesh].slice(..));
            pass.set_index_buffer(
                scene.indices[call.mesh].slice(..),
                wgpu::IndexFormat::Uint32,
            );
            pass.draw_indexed(
                call.first..call.first + call.count,
                0,
                call.draw..call.draw + 1,
            );
        }
    }
}
