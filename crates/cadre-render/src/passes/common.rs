//! Pieces every pass uses: its shader module (the shared WGSL declarations first), bind group
//! layout entries, the mesh vertex layout, overlay render passes and drawing a scene's meshes.

use crate::gpu_scene::{DrawCall, EdgeCall, FrameInstances, FrameScene};
use crate::layout::{Binding, DRAW_ATTRIBUTES, Draw, Vertex};
use crate::passes::instances::InstanceLayout;

/// The WGSL every pass starts with (`common.wgsl`: the layout structs and the frame uniform).
pub(crate) const COMMON_WGSL: &str = include_str!("common.wgsl");

/// A pass's whole WGSL: [`COMMON_WGSL`] followed by `parts` (shared pieces, then its own).
pub(crate) fn wgsl(parts: &[&str]) -> String {
    let mut source = COMMON_WGSL.to_string();
    for part in parts {
        source.push('\n');
        source.push_str(part);
    }
    source
}

/// A pass's shader module from its whole WGSL (see [`wgsl`]).
pub(crate) fn shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// The bind group layout entries of a pass's [`Binding`] list: buffers visible to `stages`,
/// textures to the fragment stage (the compute stage for a compute pass).
pub(crate) fn entries(
    bindings: &[Binding],
    stages: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let texture_stages = if stages.contains(wgpu::ShaderStages::COMPUTE) {
        wgpu::ShaderStages::COMPUTE
    } else {
        wgpu::ShaderStages::FRAGMENT
    };
    bindings
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let i = i as u32;
            match b {
                Binding::Uniform(_) => buffer_entry(i, wgpu::BufferBindingType::Uniform, stages),
                Binding::Storage(_) => buffer_entry(i, STORAGE, stages),
                Binding::AtomicStorage => buffer_entry(
                    i,
                    wgpu::BufferBindingType::Storage { read_only: false },
                    stages,
                ),
                Binding::StorageWrite(_) => buffer_entry(
                    i,
                    wgpu::BufferBindingType::Storage { read_only: false },
                    stages,
                ),
                Binding::FloatTexture => texture_entry(
                    i,
                    wgpu::TextureSampleType::Float { filterable: false },
                    texture_stages,
                ),
                Binding::UintTexture => {
                    texture_entry(i, wgpu::TextureSampleType::Uint, texture_stages)
                }
                Binding::FilteredTexture => texture_entry(
                    i,
                    wgpu::TextureSampleType::Float { filterable: true },
                    texture_stages,
                ),
                Binding::Sampler => wgpu::BindGroupLayoutEntry {
                    binding: i,
                    visibility: texture_stages,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            }
        })
        .collect()
}

/// A uniform or storage buffer binding.
pub(crate) fn buffer_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A read-only storage buffer binding.
pub(crate) const STORAGE: wgpu::BufferBindingType =
    wgpu::BufferBindingType::Storage { read_only: true };

/// A 2D texture read by `textureLoad` in the `visibility` stages.
pub(crate) fn texture_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// The bind group layout (group 0) of `entries` and a pipeline layout with it, followed by
/// `instances` as group 1 for the passes that draw the scene's instances.
pub(crate) fn layouts(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
    instances: Option<&InstanceLayout>,
) -> (wgpu::BindGroupLayout, wgpu::PipelineLayout) {
    let group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    });
    let pipeline = match instances {
        Some(instances) => instances.pipeline_layout(device, label, &group),
        None => device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&group)],
            immediate_size: 0,
        }),
    };
    (group, pipeline)
}

/// A bind group whose entries are `resources` at bindings 0, 1, 2, ...
pub(crate) fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = numbered(resources).collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// `resources` as bind group entries at bindings 0, 1, 2, ...
pub(crate) fn numbered<'a>(
    resources: &[wgpu::BindingResource<'a>],
) -> impl Iterator<Item = wgpu::BindGroupEntry<'a>> {
    resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
}

/// Attributes of [`Vertex`]: position, normal, face id, (u, v).
const MESH_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Uint32, 3 => Float32x2];

/// The vertex buffer layout of the scene's meshes.
pub(crate) fn mesh_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &MESH_ATTRIBUTES,
    }
}

/// The layout of the draw records read as instance-step vertex attributes (the calls with
/// [`DrawCall::direct`] records), bound at slot [`records_slot`].
pub(crate) fn record_instance_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Draw>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &DRAW_ATTRIBUTES,
    }
}

/// The vertex buffer slot of the draw records in the pipelines that read them as attributes
/// (after the mesh vertices in the mesh back-end; the edges pass has no other).
pub(crate) const fn records_slot(with_mesh: bool) -> u32 {
    if with_mesh { 1 } else { 0 }
}

/// A colour target that blends over what is there.
pub(crate) fn blended(format: wgpu::TextureFormat) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState {
        format,
        blend: Some(wgpu::BlendState::ALPHA_BLENDING),
        write_mask: wgpu::ColorWrites::ALL,
    }
}

/// A render pass over `target` that keeps its content (`clear` to start from a colour), with
/// `read_only_depth`, if any, as its depth attachment read only: the pipelines' depth test,
/// while their shaders may read the same texture (not on GL: `Gpu::read_only_depth`).
pub(crate) fn colour_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    (target, clear): (&wgpu::TextureView, Option<wgpu::Color>),
    read_only_depth: Option<&wgpu::TextureView>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: read_only_depth.map(|view| {
            wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: None,
                stencil_ops: None,
            }
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Draws `calls` of `scene`, each instanced over its draw records (picked by the instance
/// index, composed through the call's slot).
pub(crate) fn draw_meshes(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &FrameScene<'_>,
    calls: &[DrawCall],
) {
    for call in calls {
        draw_mesh_call(pass, scene, call);
    }
}

/// Draws one mesh call with the pipeline already set.
pub(crate) fn draw_mesh_call(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &FrameScene<'_>,
    call: &DrawCall,
) {
    draw_mesh_call_as(pass, scene, call, None);
}

/// [`draw_mesh_call`] by a pipeline that reads a direct call's records as instance-step
/// attributes (slot 1, [`record_instance_layout`]): `call.direct` must be `Some`.
pub(crate) fn draw_mesh_call_direct(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &FrameScene<'_>,
    call: &DrawCall,
) {
    draw_mesh_call_as(pass, scene, call, call.direct);
}

/// A mesh call, its instances `direct..direct + instances` of the records bound as vertex
/// attributes, or `0..instances` composed through its slot.
fn draw_mesh_call_as(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &FrameScene<'_>,
    call: &DrawCall,
    direct: Option<u32>,
) {
    let geometry = scene.geometry;
    pass.set_bind_group(
        1,
        &scene.instances.bind,
        &[scene.instances.offset(call.slot)],
    );
    pass.set_vertex_buffer(0, geometry.vertices[call.mesh].slice(..));
    pass.set_index_buffer(
        geometry.indices[call.mesh].slice(..),
        wgpu::IndexFormat::Uint32,
    );
    let first = match direct {
        Some(first) => {
            pass.set_vertex_buffer(records_slot(true), scene.instances.records.slice(..));
            first
        }
        None => 0,
    };
    pass.draw_indexed(
        call.first..call.first + call.count,
        0,
        first..first + call.instances,
    );
}

/// Draws segment `calls` (a quad of four indexed corners per segment, `quads` being
/// `PreparedScene::quad_indices`), each over its instances read through `instances` (bind
/// group 1).
pub(crate) fn draw_segments(
    pass: &mut wgpu::RenderPass<'_>,
    instances: &FrameInstances,
    calls: &[EdgeCall],
    quads: &wgpu::Buffer,
) {
    pass.set_index_buffer(quads.slice(..), wgpu::IndexFormat::Uint32);
    for call in calls {
        draw_segment_call(pass, instances, call, false);
    }
}

/// Draws one segment call, the segments' quad indices bound: with `direct` by a pipeline
/// that reads a direct call's records as instance-step attributes (slot
/// [`records_slot`]`(false)`, bound here), else composed through its slot.
pub(crate) fn draw_segment_call(
    pass: &mut wgpu::RenderPass<'_>,
    instances: &FrameInstances,
    call: &EdgeCall,
    direct: bool,
) {
    pass.set_bind_group(1, &instances.bind, &[instances.offset(call.slot)]);
    let first = match call.direct.filter(|_| direct) {
        Some(first) => {
            pass.set_vertex_buffer(records_slot(false), instances.records.slice(..));
            first
        }
        None => 0,
    };
    pass.draw_indexed(
        0..call.count * 6,
        (call.first * 4) as i32,
        first..first + call.instances,
    );
}

/// What differs between the passes' render pipelines.
pub(crate) struct PipelineSpec<'a> {
    pub label: &'a str,
    pub layout: &'a wgpu::PipelineLayout,
    pub module: &'a wgpu::ShaderModule,
    /// Vertex entry point (`vs_main` unless a pass has variants).
    pub vertex: &'a str,
    /// Faces culled (none: both sides drawn).
    pub cull: Option<wgpu::Face>,
    /// Fragment entry point.
    pub fragment: &'a str,
    /// Vertex buffers (none: vertices are built from storage buffers or the vertex index).
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub depth: Option<wgpu::DepthStencilState>,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    /// Values of the shader's pipeline-overridable constants (none: their defaults), for both
    /// stages.
    pub constants: &'a [(&'a str, f64)],
}

/// A render pipeline with entry points `spec.vertex` and `spec.fragment`, triangle lists
/// (counter-clockwise in front), culling `spec.cull` (none but for closed solids: open shells
/// and mirrored instances show both sides), no multisampling.
pub(crate) fn pipeline(device: &wgpu::Device, spec: PipelineSpec<'_>) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(spec.layout),
        vertex: wgpu::VertexState {
            module: spec.module,
            entry_point: Some(spec.vertex),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
            buffers: spec.buffers,
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: spec.cull,
            ..Default::default()
        },
        depth_stencil: spec.depth,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: spec.module,
            entry_point: Some(spec.fragment),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: spec.constants,
                ..Default::default()
            },
            targets: spec.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
