//! The visible-edges mode's segments rasterized in compute (`raster.wgsl`) into a per-pixel
//! coverage buffer, then blended over the image by one full-screen draw (`composite.wgsl`).
//!
//! Why: drawn as quads, each segment is two triangles through the rasterizer's per-primitive
//! work. On lavapipe that work runs on the submitting thread alone; on Hopper GPUs, which have
//! little raster hardware, primitives are what a frame is bound by. The 100× scene's 165,600
//! segments cost 80 ms of quads on lavapipe at 1280×960; the 10 M-triangle scene's edges took
//! its H200 frame from 18.9 to 25.6 ms (BENCHMARKS.md).

use super::super::common::{
    PipelineSpec, blended, colour_pass, entries, layouts, pipeline, shader, wgsl,
};
use super::EDGE_SEGMENTS_WGSL;
use crate::frame_buffers::BindCache;
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, FrameUniform, GpuStruct, Segment};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use crate::passes::visibility::VisibilityTargets;
use std::sync::Mutex;

/// The compute rasterizer's bind group 0: frame, segments, the visibility depth, selection
/// (as the quads'), and the coverage it sums into (group 1: the instances).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Segment::WGSL_NAME),
    Binding::FloatTexture,
    Binding::Storage("vec4<u32>"),
    Binding::AtomicStorage,
];

/// The composite's bind group 0: frame and the summed coverage.
pub(crate) const COMPOSITE_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage("u32"),
];

/// Invocations per workgroup (`GROUP` in raster.wgsl).
const GROUP: u32 = 64;

/// The compute rasterizer's whole WGSL.
pub(crate) fn source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        EDGE_SEGMENTS_WGSL,
        include_str!("raster.wgsl"),
    ])
}

/// The composite's whole WGSL.
pub(crate) fn composite_source() -> String {
    wgsl(&[include_str!("composite.wgsl")])
}

/// The compute rasterizer, its composite, and the coverage buffer of the last size drawn.
pub(crate) struct EdgeRaster {
    raster_layout: wgpu::BindGroupLayout,
    raster: wgpu::ComputePipeline,
    composite_layout: wgpu::BindGroupLayout,
    composite: wgpu::RenderPipeline,
    /// One `u32` a pixel, kept for the next frame of the same size.
    cover: Mutex<Option<((u32, u32), wgpu::Buffer)>>,
    /// The largest storage buffer a binding may hold: larger targets are left to the quads.
    max_binding: u64,
}

impl EdgeRaster {
    /// Builds both pipelines for a `colour` target; `behind`: the quads' `CULL_BEHIND` and
    /// `BACK_MARGIN`.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
        behind: (bool, f32),
    ) -> EdgeRaster {
        let module = shader(device, "edges raster", &source());
        let (raster_layout, raster_pipeline_layout) = layouts(
            device,
            "edges raster",
            &entries(BINDINGS, wgpu::ShaderStages::COMPUTE),
            Some(instances),
        );
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let raster = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("edges raster"),
            layout: Some(&raster_pipeline_layout),
            module: &module,
            entry_point: Some("cs_main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &[
                    ("CULL_BEHIND", flag(behind.0)),
                    ("BACK_MARGIN", f64::from(behind.1)),
                ],
                ..Default::default()
            },
            cache: None,
        });
        let composite_module = shader(device, "edges composite", &composite_source());
        let (composite_layout, composite_pipeline_layout) = layouts(
            device,
            "edges composite",
            &entries(COMPOSITE_BINDINGS, wgpu::ShaderStages::FRAGMENT),
            None,
        );
        let composite = pipeline(
            device,
            PipelineSpec {
                label: "edges composite",
                layout: &composite_pipeline_layout,
                module: &composite_module,
                vertex: "vs_main",
                cull: None,
                fragment: "fs_main",
                buffers: &[],
                depth: None,
                targets: &[Some(blended(colour))],
                constants: &[],
            },
        );
        EdgeRaster {
            raster_layout,
            raster,
            composite_layout,
            composite,
            cover: Mutex::new(None),
            max_binding: device.limits().max_storage_buffer_binding_size,
        }
    }

    /// Whether a target of `size` fits the coverage buffer.
    pub fn fits(&self, (width, height): (u32, u32)) -> bool {
        u64::from(width) * u64::from(height) * 4 <= self.max_binding
    }

    /// The coverage buffer of `size`, cleared by `encoder` (made anew when the size changed).
    fn cover(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (width, height): (u32, u32),
    ) -> wgpu::Buffer {
        let mut kept = self.cover.lock().unwrap_or_else(|e| e.into_inner());
        let buffer = match &*kept {
            Some((size, buffer)) if *size == (width, height) => buffer.clone(),
            _ => {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("edge coverage"),
                    size: u64::from(width) * u64::from(height) * 4,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                *kept = Some(((width, height), buffer.clone()));
                buffer
            }
        };
        encoder.clear_buffer(&buffer, 0, None);
        buffer
    }

    /// Rasterizes every segment call of `scene` but its highlighted segments into the
    /// coverage buffer, then blends it over `target` in the edge colour.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        (frame, selection): (&wgpu::Buffer, &wgpu::Buffer),
        scene: &FrameScene<'_>,
        size: (u32, u32),
        target: &wgpu::TextureView,
    ) {
        let cover = self.cover(device, encoder, size);
        let [b0, b1, b2, b3] = super::segment_bindings(frame, scene, visibility, selection);
        let bind = binds.get(
            device,
            "edges raster",
            &self.raster_layout,
            &[b0, b1, b2, b3, cover.as_entire_binding()],
        );
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("edges raster"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.raster);
            pass.set_bind_group(0, &bind, &[]);
            let max_x = device.limits().max_compute_workgroups_per_dimension.max(1);
            for call in &scene.edge_calls {
                let invocations = u64::from(call.count) * u64::from(call.instances);
                let groups = invocations.div_ceil(u64::from(GROUP));
                if groups == 0 {
                    continue;
                }
                let x = groups.min(u64::from(max_x)) as u32;
                let y = groups.div_ceil(u64::from(x)).min(u64::from(max_x)) as u32;
                pass.set_bind_group(
                    1,
                    &scene.instances.bind,
                    &[scene.instances.offset(call.slot)],
                );
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        let composite_bind = binds.get(
            device,
            "edges composite",
            &self.composite_layout,
            &[frame.as_entire_binding(), cover.as_entire_binding()],
        );
        let mut pass = colour_pass(encoder, "edges composite", (target, None), None);
        pass.set_pipeline(&self.composite);
        pass.set_bind_group(0, &composite_bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
