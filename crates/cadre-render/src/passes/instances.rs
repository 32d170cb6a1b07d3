//! Bind group 1 of the passes that draw the scene's instances: the draw call (a uniform at a
//! dynamic offset), the draw records and the local placements ([`INSTANCE_BINDINGS`]), and
//! the WGSL that composes them.

use crate::layout::{Call, INSTANCE_BINDINGS};
use crate::passes::common::entries;

/// The WGSL of bind group 1, its `instance_draw` function and the flat-varying ids
/// (`pack_instance` / `unpack_instance`).
pub(crate) const INSTANCES_WGSL: &str = include_str!("instances.wgsl");

/// Bind group 1's layout, built once per renderer and shared by its pipelines (the bind
/// group made with it is set on each of them).
#[derive(Clone)]
pub(crate) struct InstanceLayout {
    pub layout: wgpu::BindGroupLayout,
}

impl InstanceLayout {
    /// The layout of [`INSTANCE_BINDINGS`]: the call uniform with a dynamic offset, then the
    /// records and locals, visible to vertex and fragment stages, and to compute shaders
    /// where the adapter has them (`compute`: [`crate::Gpu::compute`]).
    pub fn new(device: &wgpu::Device, compute: bool) -> InstanceLayout {
        let stages = if compute {
            wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE
        } else {
            wgpu::ShaderStages::VERTEX_FRAGMENT
        };
        let mut entries = entries(INSTANCE_BINDINGS, stages);
        // The call: one `Call` wide, at a per-draw dynamic offset.
        entries[0].ty = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Call>() as u64),
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("instances"),
            entries: &entries,
        });
        InstanceLayout { layout }
    }

    /// A pipeline layout of `group` (bind group 0) and this one (bind group 1).
    pub fn pipeline_layout(
        &self,
        device: &wgpu::Device,
        label: &str,
        group: &wgpu::BindGroupLayout,
    ) -> wgpu::PipelineLayout {
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(group), Some(&self.layout)],
            immediate_size: 0,
        })
    }

    /// Byte stride between calls in the call buffer: the device's dynamic-offset alignment.
    pub fn call_stride(device: &wgpu::Device) -> u64 {
        u64::from(device.limits().min_uniform_buffer_offset_alignment)
            .max(std::mem::size_of::<Call>() as u64)
    }
}
