//! Shading pass: lights the visibility buffer into the colour target.

use super::common::{PipelineSpec, colour_pass, entries, layouts, pipeline, shader, wgsl};
use super::visibility::{DEPTH, VisibilityTargets};
use crate::frame_buffers::BindCache;
use crate::layout::{Binding, FrameUniform, GpuStruct, LightGpu, LightRig, Material};
use std::collections::BTreeMap;
use std::sync::Mutex;

/// Bind group 0: frame, materials, the normal and id targets, the light rig, selection, the depth
/// target (read by the silhouettes: 4 bytes a neighbour where the ids are 16).
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(Material::WGSL_NAME),
    Binding::FloatTexture,
    Binding::UintTexture,
    Binding::Uniform(LightRig::WGSL_NAME),
    Binding::Storage("vec4<u32>"),
    Binding::FloatTexture,
    Binding::FloatTexture,
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
    /// The shader's parts the frame needs.
    pub variant: ShadeVariant,
    /// The key light's shadow map, when the frame has one.
    pub shadow: Option<&'a wgpu::TextureView>,
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

/// Which of the shade shader's optional parts a frame needs: each is a pipeline-overridable
/// constant of `shade.wgsl`, so a pipeline is built per combination met. A CPU rasterizer
/// (llvmpipe) runs both sides of every branch under lane masks, so a part that a frame cannot
/// reach costs its full price per pixel unless it is compiled out; measured on the cube at
/// 1600 × 1200: silhouettes ≈ 35 ms, section caps ≈ 20 ms of a 155 ms frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct ShadeVariant {
    /// Section planes are set: caps, their outlines and hatching (`SECTIONS`).
    pub sections: bool,
    /// Outlines where the depth jumps (`SILHOUETTES`).
    pub silhouettes: bool,
    /// Point or spot lights, not only directional ones (`POSITIONAL_LIGHTS`).
    pub positional_lights: bool,
    /// The number of lights (`LIGHTS`, the frame's `counts[0]`).
    pub lights: u32,
    /// Something is selected (`SELECTION`, the frame's `counts[1] > 0`).
    pub selection: bool,
    /// Trimmed edges' pixels are blended by their coverage (`COVERAGE`, the frame's
    /// `counts[3] > 0`).
    pub coverage: bool,
    /// The key light casts shadows (`SHADOWS`, the frame's `shadow_params[3] > 0`).
    pub shadows: bool,
}

impl ShadeVariant {
    /// The variant that shades a frame with this uniform and these lights.
    pub fn of(frame: &FrameUniform, lights: &[LightGpu]) -> ShadeVariant {
        ShadeVariant {
            sections: frame.counts[2] > 0,
            silhouettes: frame.modes[3] != 0,
            // Only the first `counts[0]` lights are lit (the buffer holds one when there is
            // none: bindings may not be empty).
            positional_lights: lights
                .iter()
                .take(frame.counts[0] as usize)
                .any(|l| l.position[3] != 0.0),
            lights: frame.counts[0],
            selection: frame.counts[1] > 0,
            coverage: frame.counts[3] > 0,
            shadows: frame.shadow_params[3] > 0.0,
        }
    }

    /// The pipeline constants of `shade.wgsl` for this variant.
    fn constants(self) -> [(&'static str, f64); 7] {
        [
            ("SECTIONS", f64::from(u8::from(self.sections))),
            ("SILHOUETTES", f64::from(u8::from(self.silhouettes))),
            (
                "POSITIONAL_LIGHTS",
                f64::from(u8::from(self.positional_lights)),
            ),
            ("LIGHTS", f64::from(self.lights)),
            ("SELECTION", f64::from(u8::from(self.selection))),
            ("COVERAGE", f64::from(u8::from(self.coverage))),
            ("SHADOWS", f64::from(u8::from(self.shadows))),
        ]
    }
}

/// The pass's pipelines (one per [`ShadeVariant`] met, built on first use) and bind group
/// layout.
pub(crate) struct ShadePass {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    layout: wgpu::BindGroupLayout,
    colour: wgpu::TextureFormat,
    /// Whether the pass depth-tests against the visibility depth (`Gpu::read_only_depth`):
    /// without it (GL) every pixel is shaded and the background is the shader's.
    cull: bool,
    pipelines: Mutex<BTreeMap<ShadeVariant, wgpu::RenderPipeline>>,
}

impl ShadePass {
    /// Builds the pass for a `colour` target of that format, with the pipelines of the
    /// variants `cadre render` and the viewer start with (directional lights, no section;
    /// with and without silhouettes) so that their first frame compiles nothing; `cull`: test
    /// against the visibility depth so that only covered pixels are shaded.
    pub fn new(device: &wgpu::Device, colour: wgpu::TextureFormat, cull: bool) -> ShadePass {
        let module = shader(device, "shade", &source());
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let (layout, pipeline_layout) =
            layouts(device, "shade", &entries(BINDINGS, fragment), None);
        let pass = ShadePass {
            module,
            pipeline_layout,
            layout,
            colour,
            cull,
            pipelines: Mutex::new(BTreeMap::new()),
        };
        let rig_lights = crate::lights::Light::cad_rig().len() as u32;
        for silhouettes in [false, true] {
            pass.pipeline(
                device,
                ShadeVariant {
                    sections: false,
                    silhouettes,
                    positional_lights: false,
                    lights: rig_lights,
                    selection: false,
                    coverage: false,
                    shadows: false,
                },
            );
        }
        pass
    }

    /// The pipeline of `variant`, built the first time it is asked for.
    fn pipeline(&self, device: &wgpu::Device, variant: ShadeVariant) -> wgpu::RenderPipeline {
        // A poisoned lock only means another frame panicked while inserting; the map is
        // still whole.
        let mut pipelines = self.pipelines.lock().unwrap_or_else(|e| e.into_inner());
        pipelines
            .entry(variant)
            .or_insert_with(|| {
                pipeline(
                    device,
                    PipelineSpec {
                        label: "shade",
                        layout: &self.pipeline_layout,
                        module: &self.module,
                        vertex: "vs_main",
                        cull: None,
                        fragment: "fs_main",
                        buffers: &[],
                        depth: self.cull.then(faces_only),
                        targets: &[Some(self.colour.into())],
                        constants: &variant.constants(),
                    },
                )
            })
            .clone()
    }

    /// Records the pass into `target`, cleared to `background` (linear): only the pixels
    /// that a surface covers are shaded.
    pub fn record(
        &self,
        (device, binds): (&wgpu::Device, &BindCache),
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
            variant,
            shadow,
        } = inputs;
        let bind = binds.get(
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
                wgpu::BindingResource::TextureView(&visibility.depth),
                wgpu::BindingResource::TextureView(shadow.unwrap_or(&visibility.depth)),
            ],
        );
        // Read only: the depth test keeps the shader off the background.
        let depth = self.cull.then_some(&visibility.depth);
        let mut pass = colour_pass(encoder, "shade", (target, Some(*background)), depth);
        pass.set_pipeline(&self.pipeline(device, *variant));
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variant_follows_the_frame_and_its_lights() {
        let mut frame = FrameUniform::default();
        let directional = LightGpu::default();
        let mut point = LightGpu::default();
        point.position[3] = 1.0;
        let plain = ShadeVariant::of(&frame, &[directional]);
        assert_eq!(
            plain,
            ShadeVariant {
                sections: false,
                silhouettes: false,
                positional_lights: false,
                lights: 0,
                selection: false,
                coverage: false,
                shadows: false,
            }
        );
        frame.counts = [2, 1, 1, 1];
        frame.modes[3] = 1;
        let all = ShadeVariant::of(&frame, &[directional, point]);
        assert!(all.sections && all.silhouettes && all.positional_lights && all.selection);
        assert!(all.coverage);
        assert_eq!(
            all.constants().map(|(_, v)| v),
            [1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 0.0],
            "every part compiled in, two lights"
        );
        // A light past the frame's count is not lit: it does not ask for positional code.
        frame.counts[0] = 1;
        assert!(!ShadeVariant::of(&frame, &[directional, point]).positional_lights);
    }
}
