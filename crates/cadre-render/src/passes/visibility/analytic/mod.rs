//! The analytic back-end: spheres and rectangles ray cast per pixel
//! ([`crate::AnalyticPrimitive`]), drawn into the passes the mesh back-end drew into: the
//! visibility buffer through the same texel writer, the see-through phases in the same
//! colours. Pipelines are built on the first frame that has primitives.

use std::sync::OnceLock;

use super::{
    Phase, PhaseInputs, SEE_THROUGH_WGSL, TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state,
    tested_not_written,
};
use crate::layout::{Binding, FrameUniform, GpuStruct, Material, Primitive};
use crate::passes::common::{PipelineSpec, blended, entries, layouts, pipeline, shader, wgsl};

/// Bind group 0: the frame, the frame's primitives (opaque or see-through ones), the
/// frame's materials, the quadrics' cutting planes.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Primitive::WGSL_NAME),
    Binding::Storage(Material::WGSL_NAME),
    Binding::Storage("vec4<f32>"),
];

/// Vertices of a primitive's proxy: a bounding cube's 12 triangles (a rectangle uses 2).
const PROXY_VERTICES: u32 = 36;

/// The back-end's whole WGSL: the shared declarations, the texel writer, the see-through
/// colours, its own source.
pub(crate) fn source() -> String {
    wgsl(&[
        TEXEL_WGSL,
        SEE_THROUGH_WGSL,
        include_str!("quadric.wgsl"),
        include_str!("analytic.wgsl"),
    ])
}

/// The back-end's pipelines (with and without the (u, v) target; with the proxy's depth for
/// the tests' negative control; per see-through phase and layer) and bind group layout.
pub(crate) struct AnalyticBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    layout: wgpu::BindGroupLayout,
    /// Format of the colour target of the see-through phases.
    colour: wgpu::TextureFormat,
    /// Indexed by `with_uv + 2 × proxy_depth + 4 × coverage`.
    pipelines: [OnceLock<wgpu::RenderPipeline>; 8],
    /// Indexed by `layer + 2 × transparent` (x-ray otherwise).
    see_through: [OnceLock<wgpu::RenderPipeline>; 4],
}

/// One frame's primitives on the GPU: the opaque and the see-through ones' records, each in
/// chunks of at most a storage binding, with their counts.
pub(crate) struct FramePrimitives {
    pub opaque: Vec<(wgpu::Buffer, u32)>,
    pub see_through: Vec<(wgpu::Buffer, u32)>,
    /// The quadrics' cutting planes (in their boxes' frames), indexed by their records.
    pub planes: wgpu::Buffer,
}

impl AnalyticBackend {
    /// Compiles the shader; pipelines come on first use (the see-through ones for a `colour`
    /// target of that format).
    pub fn new(device: &wgpu::Device, colour: wgpu::TextureFormat) -> AnalyticBackend {
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
            colour,
            pipelines: Default::default(),
            see_through: Default::default(),
        }
    }

    /// Draws its part of `phase` into the pass opened for it: the opaque primitives into
    /// the visibility buffer, the see-through ones over an opaque view, all of them in
    /// x-ray (each see-through one's farther hit, then its nearer).
    pub fn draw(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        inputs: &PhaseInputs<'_>,
        phase: Phase,
    ) {
        let primitives = &inputs.scene.primitives;
        let materials = &inputs.scene.materials;
        match phase {
            Phase::Visibility => {
                let pipeline = self.visibility_pipeline(recorder.0, inputs);
                for chunk in &primitives.opaque {
                    self.draw_records(
                        recorder,
                        pass,
                        pipeline,
                        (inputs.frame, materials, &primitives.planes),
                        chunk,
                    );
                }
            }
            Phase::Transparent | Phase::XRay => {
                let transparent = phase == Phase::Transparent;
                let sets: Vec<&(wgpu::Buffer, u32)> = if transparent {
                    primitives.see_through.iter().collect()
                } else {
                    primitives
                        .opaque
                        .iter()
                        .chain(&primitives.see_through)
                        .collect()
                };
                for layer in [1, 0] {
                    let pipeline = self.see_through_pipeline(recorder.0, transparent, layer);
                    for records in &sets {
                        self.draw_records(
                            recorder,
                            pass,
                            pipeline,
                            (inputs.frame, materials, &primitives.planes),
                            records,
                        );
                    }
                }
            }
        }
    }

    /// Draws the proxies of `records` with `pipeline`.
    fn draw_records(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        (frame, materials, planes): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        (records, count): &(wgpu::Buffer, u32),
    ) {
        if *count == 0 {
            return;
        }
        let bind = binds.get(
            device,
            "analytic",
            &self.layout,
            &[
                frame.as_entire_binding(),
                records.as_entire_binding(),
                materials.as_entire_binding(),
                planes.as_entire_binding(),
            ],
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..PROXY_VERTICES, 0..*count);
    }

    /// The see-through pipeline of the transparent phase (x-ray otherwise) drawing hit
    /// `layer` (0 the nearer).
    fn see_through_pipeline(
        &self,
        device: &wgpu::Device,
        transparent: bool,
        layer: u32,
    ) -> &wgpu::RenderPipeline {
        let k = layer as usize + 2 * usize::from(transparent);
        self.see_through[k].get_or_init(|| {
            let targets = [Some(blended(self.colour))];
            pipeline(
                device,
                PipelineSpec {
                    label: if transparent {
                        "analytic transparent"
                    } else {
                        "analytic x-ray"
                    },
                    layout: &self.pipeline_layout,
                    module: &self.module,
                    vertex: "vs_main",
                    // Both sides; `draws_pixel` keeps one fragment per pixel.
                    cull: None,
                    fragment: if transparent {
                        "fs_transparent"
                    } else {
                        "fs_xray"
                    },
                    buffers: &[],
                    depth: transparent.then(tested_not_written),
                    targets: &targets,
                    constants: &[("LAYER", f64::from(layer))],
                },
            )
        })
    }

    /// The visibility pipeline of a frame with or without the (u, v) target, and with the
    /// proxies' depth for the tests' negative control.
    fn visibility_pipeline(
        &self,
        device: &wgpu::Device,
        inputs: &PhaseInputs<'_>,
    ) -> &wgpu::RenderPipeline {
        let (with_uv, proxy_depth) = (inputs.with_uv, inputs.proxy_depth);
        let k =
            usize::from(with_uv) + 2 * usize::from(proxy_depth) + 4 * usize::from(inputs.coverage);
        self.pipelines[k].get_or_init(|| {
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
                    constants: &[
                        ("EXACT_DEPTH", if proxy_depth { 0.0 } else { 1.0 }),
                        ("COVERAGE", if inputs.coverage { 1.0 } else { 0.0 }),
                    ],
                },
            )
        })
    }
}
