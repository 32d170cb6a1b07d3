//! Text pass: a [`crate::LabelSet`]'s glyphs drawn from the MSDF atlas in one instanced draw
//! (`text.wgsl`). The labels are laid out once, when the set is uploaded ([`GpuText::new`]);
//! each frame only writes the camera ([`TextFrame`]).

use super::common::{blended, colour_pass, entries, layouts, shader, wgsl};
use crate::Camera;
use crate::layout::{
    Binding, FrameUniform, GpuStruct, TEXT_ANCHOR_BILLBOARD, TEXT_ANCHOR_PLANE, TEXT_ANCHOR_SCREEN,
    TEXT_QUAD_BOX, TEXT_QUAD_FILL, TEXT_QUAD_GLYPH, TEXT_QUAD_LEADER, TextFrame, TextGlyph,
    TextLabel,
};
use crate::text::{LabelSet, TextAnchor, TextDepth, TextHeight};
use cadre_text::{FontChain, MsdfAtlas, Shaper};
use glam::{DMat4, DVec3};
use rayon::prelude::*;
use std::sync::Arc;
use wgpu::util::DeviceExt;

/// The draw's bind group 0: frame, text frame, quads, labels, atlas, its sampler, the
/// visibility depth.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Uniform(TextFrame::WGSL_NAME),
    Binding::Storage(TextGlyph::WGSL_NAME),
    Binding::Storage(TextLabel::WGSL_NAME),
    Binding::FilteredTexture,
    Binding::Sampler,
    Binding::FloatTexture,
];

/// The pass's whole WGSL.
pub(crate) fn source() -> String {
    wgsl(&[include_str!("text.wgsl")])
}

use crate::text::BOX_MARGIN;

/// A label set laid out and uploaded: its quads, labels and the atlas they read.
pub struct GpuText {
    /// Where the set-local coordinates start (the first scene point), so `f32` positions
    /// stay precise far from the world origin.
    origin: DVec3,
    quads: wgpu::Buffer,
    quad_count: u32,
    labels: wgpu::Buffer,
    atlas_size: (u32, u32),
    atlas: wgpu::TextureView,
    sampler: wgpu::Sampler,
    frame: wgpu::Buffer,
    /// Characters no bundled font has (drawn as nothing), sorted.
    pub missing: Vec<char>,
}

/// The quads and labels of `set` (CPU side), the atlas holding their glyphs, and the
/// characters no font has.
pub(crate) fn build(
    set: &LabelSet,
) -> (
    Vec<TextGlyph>,
    Vec<TextLabel>,
    Arc<MsdfAtlas>,
    Vec<char>,
    DVec3,
) {
    let chain = FontChain::bundled();
    let shaper = Shaper::bundled();
    let origin = set
        .labels
        .iter()
        .find_map(|l| l.point())
        .or_else(|| set.fills.first().map(|f| f.corners[0]))
        .unwrap_or(DVec3::ZERO);
    let layouts: Vec<_> = set
        .labels
        .par_iter()
        .map(|l| cadre_text::layout(chain, shaper, &l.text, (l.align, l.baseline), 1.0))
        .collect();
    let mut atlas = cadre_text::cache::base_atlas();
    let wanted: Vec<_> = layouts
        .iter()
        .flat_map(|t| t.glyphs.iter().map(|g| g.key))
        .filter(|k| !atlas.contains(*k))
        .collect();
    if !wanted.is_empty() {
        let mut grown = (*atlas).clone();
        if let Err(e) = grown.insert(chain, &wanted) {
            tracing::warn!("labels: {e}");
        }
        atlas = Arc::new(grown);
    }
    let cap = chain.primary().cap_height;
    let linear = |c: [f32; 4]| {
        let f = crate::renderer::srgb_to_linear;
        [f(c[0]), f(c[1]), f(c[2]), c[3]]
    };
    let mut quads = Vec::new();
    let mut labels = Vec::with_capacity(set.labels.len() + set.fills.len());
    let mut missing = Vec::new();
    // Fills first (under the labels): a label record each, its corner and two edges.
    for fill in &set.fills {
        let [a, b, c] = fill.corners;
        let edge = |p: DVec3| (p - a).as_vec3().extend(0.0).to_array();
        quads.push(TextGlyph {
            plane: [0.0, 0.0, 1.0, 1.0],
            label: labels.len() as u32,
            kind: TEXT_QUAD_FILL,
            ..TextGlyph::default()
        });
        labels.push(TextLabel {
            origin: (a - origin).as_vec3().extend(1.0).to_array(),
            x_axis: edge(b),
            y_axis: edge(c),
            colour: linear(fill.colour),
            flags: [
                TEXT_ANCHOR_PLANE,
                u32::from(fill.depth == TextDepth::Tested),
                0,
                0,
            ],
            ..TextLabel::default()
        });
    }
    let first_label = labels.len() as u32;
    for (index, (label, text)) in set.labels.iter().zip(&layouts).enumerate() {
        missing.extend_from_slice(&text.missing);
        // Units per em: pixels for screen and billboard labels, model units in a plane.
        let per_em = match label.height {
            TextHeight::Pixels(px) => f64::from(px.max(0.0)) / f64::from(cap),
            TextHeight::Model(h) => h.max(0.0) / f64::from(cap),
        };
        let mut gpu = TextLabel {
            colour: linear(label.colour),
            background: linear(label.background.unwrap_or([0.0; 4])),
            flags: [0, u32::from(label.depth == TextDepth::Tested), 0, 0],
            ..TextLabel::default()
        };
        let local = |p: DVec3| (p - origin).as_vec3().extend(1.0).to_array();
        match label.anchor {
            TextAnchor::Screen(at) => {
                gpu.origin = [at.x, at.y, 0.0, 0.0];
                gpu.params = [per_em as f32, 0.0, 0.0, 0.0];
                gpu.flags[0] = TEXT_ANCHOR_SCREEN;
            }
            TextAnchor::Billboard { point, offset } => {
                gpu.origin = local(point);
                gpu.params = [per_em as f32, offset.x, offset.y, 0.0];
                gpu.flags[0] = TEXT_ANCHOR_BILLBOARD;
            }
            TextAnchor::Plane {
                origin: at,
                x_axis,
                y_axis,
            } => {
                gpu.origin = local(at);
                gpu.x_axis = (x_axis * per_em).as_vec3().extend(0.0).to_array();
                gpu.y_axis = (y_axis * per_em).as_vec3().extend(0.0).to_array();
                gpu.flags[0] = TEXT_ANCHOR_PLANE;
            }
        }
        let index = first_label + index as u32;
        if let Some(from) = label.leader
            && gpu.flags[0] == TEXT_ANCHOR_BILLBOARD
        {
            gpu.leader = local(from);
            quads.push(TextGlyph {
                label: index,
                kind: TEXT_QUAD_LEADER,
                ..TextGlyph::default()
            });
        }
        labels.push(gpu);
        if label.background.is_some() && !text.glyphs.is_empty() {
            quads.push(TextGlyph {
                plane: [
                    text.min.x - BOX_MARGIN,
                    text.min.y - BOX_MARGIN,
                    text.max.x + BOX_MARGIN,
                    text.max.y + BOX_MARGIN,
                ],
                label: index,
                kind: TEXT_QUAD_BOX,
                ..TextGlyph::default()
            });
        }
        for g in &text.glyphs {
            let Some(a) = atlas.glyph(g.key) else {
                continue;
            };
            let [x, y, w, h] = a.texels.map(|v| v as f32);
            quads.push(TextGlyph {
                plane: [
                    g.pen.x + a.plane[0],
                    g.pen.y + a.plane[1],
                    g.pen.x + a.plane[2],
                    g.pen.y + a.plane[3],
                ],
                texels: [x, y, x + w, y + h],
                label: index,
                kind: TEXT_QUAD_GLYPH,
                pad: [0; 2],
            });
        }
    }
    missing.sort_unstable();
    missing.dedup();
    (quads, labels, atlas, missing, origin)
}

impl GpuText {
    /// Lays out and uploads `set`; `None` when it draws nothing.
    pub fn new(gpu: &crate::Gpu, set: &LabelSet) -> Option<GpuText> {
        if set.is_empty() {
            return None;
        }
        let (quads, labels, atlas, missing, origin) = build(set);
        if quads.is_empty() {
            return None;
        }
        if !missing.is_empty() {
            tracing::warn!(
                "labels: no bundled font has {}",
                missing.iter().collect::<String>()
            );
        }
        let device = &gpu.device;
        let storage = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let (w, h) = atlas.size();
        let texture = device.create_texture_with_data(
            &gpu.queue,
            &wgpu::TextureDescriptor {
                label: Some("glyph atlas"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                // Distances, not colours: no sRGB decoding.
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            atlas.pixels(),
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("glyph atlas"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Some(GpuText {
            origin,
            quad_count: quads.len() as u32,
            quads: storage("text quads", bytemuck::cast_slice(&quads)),
            labels: storage("text labels", bytemuck::cast_slice(&labels)),
            atlas_size: (w, h.max(1)),
            atlas: texture.create_view(&Default::default()),
            sampler,
            frame: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("text frame"),
                size: size_of::<TextFrame>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            missing,
        })
    }

    /// How many quads (glyphs and boxes) one draw covers.
    pub fn quad_count(&self) -> u32 {
        self.quad_count
    }

    /// The per-frame constants for `camera` on a `size` target of `scale` target pixels per
    /// output pixel.
    pub fn frame(&self, camera: &Camera, (w, h): (u32, u32), scale: f32) -> TextFrame {
        let aspect = f64::from(w) / f64::from(h);
        let to_clip = camera.projection_matrix(aspect)
            * camera.view_rotation()
            * DMat4::from_translation(self.origin - camera.eye);
        TextFrame {
            to_clip: to_clip.as_mat4().to_cols_array_2d(),
            viewport: [w as f32, h as f32, scale, 0.0],
            atlas: [
                self.atlas_size.0 as f32,
                self.atlas_size.1 as f32,
                cadre_text::RANGE_PX as f32,
                0.0,
            ],
        }
    }
}

/// The pass's pipeline.
pub(crate) struct TextPass {
    layout: wgpu::BindGroupLayout,
    draw: wgpu::RenderPipeline,
}

impl TextPass {
    /// Builds the pipeline for a `colour` target.
    pub fn new(gpu: &crate::Gpu, colour: wgpu::TextureFormat) -> TextPass {
        let device = &gpu.device;
        let (layout, pipeline_layout) = layouts(
            device,
            "text",
            &entries(BINDINGS, wgpu::ShaderStages::VERTEX_FRAGMENT),
            None,
        );
        let module = shader(device, "text", &source());
        let draw = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("text"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            // A strip of four corners a quad.
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(blended(colour))],
            }),
            multiview_mask: None,
            cache: None,
        });
        TextPass { layout, draw }
    }

    /// Records the one draw of every quad of `text` over `target`, tested against `depth`.
    pub fn record(
        &self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (frame, text, text_frame): (&wgpu::Buffer, &GpuText, &TextFrame),
        depth: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        queue.write_buffer(&text.frame, 0, bytemuck::bytes_of(text_frame));
        let bind = super::common::bind_group(
            device,
            "text",
            &self.layout,
            &[
                frame.as_entire_binding(),
                text.frame.as_entire_binding(),
                text.quads.as_entire_binding(),
                text.labels.as_entire_binding(),
                wgpu::BindingResource::TextureView(&text.atlas),
                wgpu::BindingResource::Sampler(&text.sampler),
                wgpu::BindingResource::TextureView(depth),
            ],
        );
        let mut pass = colour_pass(encoder, "text", (target, None), None);
        pass.set_pipeline(&self.draw);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..4, 0..text.quad_count);
    }
}
