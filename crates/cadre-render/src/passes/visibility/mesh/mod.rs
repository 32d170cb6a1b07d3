//! The mesh back-end: the scene's triangles, instanced over their draw records, into the
//! visibility buffer (`mesh.wgsl`) and in the see-through phases (`see_through.wgsl`).

use super::{
    Phase, PhaseInputs, SEE_THROUGH_WGSL, TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state,
    see_through_depth,
};
use crate::gpu_scene::FrameScene;
use crate::layout::{Binding, FrameUniform, GpuStruct, Material};
use crate::passes::common::{
    PipelineSpec, blended, draw_mesh_call, draw_meshes, entries, layouts, mesh_vertex_layout,
    pipeline, shader, wgsl,
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

/// Bind group 0 of the see-through phases: frame, materials (group 1: the instances).
pub(crate) const SEE_THROUGH_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Material::WGSL_NAME),
];

/// The see-through phases' whole WGSL: the shared declarations, the instances, the shared
/// see-through colours, its own source.
pub(crate) fn see_through_source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        SEE_THROUGH_WGSL,
        include_str!("see_through.wgsl"),
    ])
}

/// The pipelines of the see-through phases and their bind group layout.
struct SeeThrough {
    /// Every triangle blended, no depth (x-ray mode).
    xray: wgpu::RenderPipeline,
    /// See-through parts of an opaque view: lit, blended, hidden behind the opaque depth.
    transparent: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl SeeThrough {
    fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
    ) -> SeeThrough {
        let module = shader(device, "mesh see-through", &see_through_source());
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let (layout, pipeline_layout) = layouts(
            device,
            "mesh see-through",
            &entries(SEE_THROUGH_BINDINGS, stages),
            Some(instances),
        );
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
        SeeThrough {
            xray: pipeline(device, spec("mesh x-ray", "fs_xray", None)),
            transparent: pipeline(
                device,
                spec(
                    "mesh transparent",
                    "fs_transparent",
                    Some(see_through_depth()),
                ),
            ),
            layout,
        }
    }
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
    see_through: SeeThrough,
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
    /// Builds the plain visibility pipeline and the see-through ones (for a `colour` target
    /// of that format); the other variants come on first use.
    pub fn new(
        device: &wgpu::Device,
        colour: wgpu::TextureFormat,
        instances: &InstanceLayout,
    ) -> MeshBackend {
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
            see_through: SeeThrough::new(device, colour, instances),
        }
    }

    /// Draws its part of `phase` into the pass opened for it: the opaque calls into the
    /// visibility buffer, the see-through calls over an opaque view, every call in x-ray.
    pub fn draw(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        inputs: &PhaseInputs<'_>,
        phase: Phase,
    ) {
        let scene = inputs.scene;
        match phase {
            Phase::Visibility => {
                let variant = MeshVariant::of(inputs.sections, inputs.with_uv);
                self.draw_visibility(recorder, pass, inputs.frame, scene, variant);
            }
            Phase::Transparent | Phase::XRay => {
                let (device, binds) = recorder;
                let bind = binds.get(
                    device,
                    "mesh see-through",
                    &self.see_through.layout,
                    &[
                        inputs.frame.as_entire_binding(),
                        scene.materials.as_entire_binding(),
                    ],
                );
                pass.set_bind_group(0, &bind, &[]);
                if phase == Phase::XRay {
                    pass.set_pipeline(&self.see_through.xray);
                    draw_meshes(pass, scene, &scene.calls);
                } else {
                    pass.set_pipeline(&self.see_through.transparent);
                }
                draw_meshes(pass, scene, &scene.transparent);
            }
        }
    }

    /// Draws every opaque call of `scene` into the opened visibility pass.
    fn draw_visibility(
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
