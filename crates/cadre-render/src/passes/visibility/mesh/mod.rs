//! The mesh back-end: the scene's triangles, instanced over their draw records, into the
//! visibility buffer (`mesh.wgsl`) and in the see-through phases (`see_through.wgsl`).

use super::{
    Phase, PhaseInputs, SEE_THROUGH_WGSL, TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state,
    tested_not_written,
};
use crate::gpu_scene::{DrawCall, FrameScene};
use crate::layout::{Binding, FrameUniform, GpuStruct, Material};
use crate::passes::common::{
    PipelineSpec, blended, draw_mesh_call, draw_mesh_call_direct, draw_meshes, entries, layouts,
    mesh_vertex_layout, pipeline, record_instance_layout, shader, wgsl,
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
                    Some(tested_not_written()),
                ),
            ),
            layout,
        }
    }
}

/// The back-end's pipelines and bind group layout. Each is built on first use, one per
/// [`PipelineKey`]: the plain ones (no section plane, no (u, v) target; `vs_plain`/`fs_plain`,
/// every image and viewer frame without sections), culling back or front faces or none;
/// the one with section planes and caps; the one that also writes the (u, v) target; each
/// reading its instances' records through the call slot or, for direct calls, as vertex
/// attributes.
pub(crate) struct MeshBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: [OnceLock<wgpu::RenderPipeline>; PipelineKey::COUNT],
    layout: wgpu::BindGroupLayout,
    see_through: SeeThrough,
}

/// What tells the back-end's pipelines apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PipelineKey {
    variant: MeshVariant,
    /// Faces culled (only in the plain variant: with section planes back faces show caps).
    cull: Option<wgpu::Face>,
    /// Records read as instance-step vertex attributes (`DrawCall::direct`).
    direct: bool,
}

impl PipelineKey {
    /// Keys there are: 3 variants × 3 cullings × 2 ways of reading the records.
    const COUNT: usize = 18;

    /// The key of `variant` for a call culling `cull` (kept in the plain variant only) and
    /// read `direct` or not.
    fn new(variant: MeshVariant, cull: Option<wgpu::Face>, direct: bool) -> PipelineKey {
        let cull = cull.filter(|_| variant == MeshVariant::Plain);
        PipelineKey {
            variant,
            cull,
            direct,
        }
    }

    /// Its place in [`MeshBackend::pipelines`].
    fn index(self) -> usize {
        let variant = match self.variant {
            MeshVariant::Plain => 0,
            MeshVariant::Sections => 1,
            MeshVariant::WithUv => 2,
        };
        let cull = match self.cull {
            None => 0,
            Some(wgpu::Face::Back) => 1,
            Some(wgpu::Face::Front) => 2,
        };
        (variant * 3 + cull) * 2 + usize::from(self.direct)
    }
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
    /// Builds the see-through pipelines (for a `colour` target of that format); the
    /// visibility ones come on first use.
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
        MeshBackend {
            module,
            pipeline_layout,
            pipelines: std::array::from_fn(|_| OnceLock::new()),
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
        pass.set_bind_group(0, &bind, &[]);
        // The pipeline is set again only when the culling or the way of reading the records
        // changes between calls.
        let mut current: Option<PipelineKey> = None;
        for call in &scene.calls {
            // Faces the trim back-end draws are not drawn twice.
            if call.untrimmed == 0 {
                continue;
            }
            let call = &DrawCall {
                count: call.untrimmed,
                ..*call
            };
            let key = PipelineKey::new(variant, call.cull, call.direct.is_some());
            if current != Some(key) {
                let pipeline =
                    self.pipelines[key.index()].get_or_init(|| mesh_pipeline(device, parts, key));
                pass.set_pipeline(pipeline);
                current = Some(key);
            }
            if key.direct {
                draw_mesh_call_direct(pass, scene, call);
            } else {
                draw_mesh_call(pass, scene, call);
            }
        }
    }
}

/// The back-end's pipeline of `key`.
fn mesh_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::PipelineLayout, &wgpu::ShaderModule),
    key: PipelineKey,
) -> wgpu::RenderPipeline {
    let (vertex, fragment, sections, targets) = match (key.variant, key.direct) {
        (MeshVariant::Plain, false) => ("vs_plain", "fs_plain", 0.0, &TARGETS_NO_UV),
        (MeshVariant::Plain, true) => ("vs_plain_direct", "fs_plain", 0.0, &TARGETS_NO_UV),
        (MeshVariant::Sections, false) => ("vs_main", "fs_main", 1.0, &TARGETS_NO_UV),
        (MeshVariant::Sections, true) => ("vs_main_direct", "fs_main", 1.0, &TARGETS_NO_UV),
        (MeshVariant::WithUv, false) => ("vs_main", "fs_main", 1.0, &TARGETS),
        (MeshVariant::WithUv, true) => ("vs_main_direct", "fs_main", 1.0, &TARGETS),
    };
    let with_records = [Some(mesh_vertex_layout()), Some(record_instance_layout())];
    let buffers = if key.direct {
        &with_records[..]
    } else {
        &with_records[..1]
    };
    pipeline(
        device,
        PipelineSpec {
            label: "visibility mesh",
            layout,
            module,
            vertex,
            cull: key.cull,
            fragment,
            buffers,
            depth: Some(depth_state()),
            targets,
            constants: &[("SECTIONS", sections)],
        },
    )
}

#[cfg(test)]
mod tests {
    use super::{MeshVariant, PipelineKey};

    /// Every key has its own slot (a shared one would hand a call another's pipeline).
    #[test]
    fn pipeline_keys_have_distinct_slots() {
        let mut seen = std::collections::BTreeSet::new();
        for variant in [
            MeshVariant::Plain,
            MeshVariant::Sections,
            MeshVariant::WithUv,
        ] {
            for cull in [None, Some(wgpu::Face::Back), Some(wgpu::Face::Front)] {
                for direct in [false, true] {
                    let key = PipelineKey::new(variant, cull, direct);
                    assert!(key.index() < PipelineKey::COUNT);
                    if variant == MeshVariant::Plain {
                        assert!(seen.insert(key.index()), "{key:?}");
                    } else {
                        assert_eq!(key.cull, None, "only plain pipelines cull");
                    }
                }
            }
        }
        assert_eq!(seen.len(), 6);
    }
}
