//! Backdrop pass: the background (gradient or image; a solid one is the shade pass's clear)
//! and the ground grid, over the shaded image before the see-through parts, edges and lines
//! (see `backdrop.wgsl` and [`crate::backdrop`]).

use std::sync::{Arc, Mutex};

use super::common::{PipelineSpec, blended, colour_pass, entries, layouts, pipeline, shader, wgsl};
use super::visibility::VisibilityTargets;
use crate::Camera;
use crate::backdrop::{Background, GroundGrid};
use crate::layout::{BackdropUniform, Binding, FrameUniform, GpuStruct};
use glam::DVec3;
use wgpu::util::DeviceExt;

/// Bind group 0: frame, backdrop, the visibility depth and ids, the background image.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Uniform(BackdropUniform::WGSL_NAME),
    Binding::FloatTexture,
    Binding::UintTexture,
    Binding::FloatTexture,
];

/// The pass's whole WGSL.
pub(crate) fn source() -> String {
    wgsl(&[include_str!("backdrop.wgsl")])
}

/// sRGB component → linear.
fn linear(c: [f32; 4]) -> [f32; 4] {
    let f = crate::renderer::srgb_to_linear;
    [f(c[0]), f(c[1]), f(c[2]), c[3]]
}

/// The frame's backdrop constants: `scene_floor` is the scene's lowest Z (the grid's
/// default height).
pub(crate) fn uniform(
    camera: &Camera,
    aspect: f64,
    (background, grid): (&Background, Option<&GroundGrid>),
    scene_floor: f64,
) -> BackdropUniform {
    let view_proj = camera.projection_matrix(aspect) * camera.view_rotation();
    let mut u = BackdropUniform {
        inv_view_proj: view_proj.inverse().as_mat4().to_cols_array_2d(),
        ..BackdropUniform::default()
    };
    match background {
        Background::Solid => {}
        Background::Gradient { top, bottom } => {
            u.top = linear(*top);
            u.bottom = linear(*bottom);
            u.modes[0] = 1;
        }
        Background::Image(_) => u.modes[0] = 2,
    }
    if let Some(grid) = grid {
        let height = grid.height.unwrap_or(scene_floor);
        // The grid's origin: the eye snapped to a power of ten above the view's size, so
        // that every spacing in view divides it and the offsets stay small in f32.
        let snap = 10f64.powf((camera.view_height().max(1e-9) * 10.0).log10().ceil());
        let origin = (camera.eye / snap).round() * snap;
        let offset = camera.eye - origin;
        u.modes[1] = 1;
        u.grid_colour = linear(grid.colour);
        u.plane = [0.0, 0.0, 1.0, (height - camera.eye.z) as f32];
        u.origin = (offset.extend(0.0)).as_vec4().to_array();
        u.axes = ((DVec3::ZERO - origin).extend(0.0)).as_vec4().to_array();
        u.params = [
            grid.spacing
                .filter(|s| s.is_finite() && *s > 0.0)
                .unwrap_or(0.0) as f32,
            camera.far as f32,
            0.0,
            if grid.axes { 1.0 } else { 0.0 },
        ];
    }
    u
}

/// The pass's pipeline and the background image's texture, kept while the image is the same.
pub(crate) struct BackdropPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The image last uploaded (by its allocation) and its view; a 1 × 1 texel otherwise.
    image: Mutex<Option<(usize, wgpu::TextureView)>>,
    blank: wgpu::TextureView,
}

impl BackdropPass {
    /// Builds the pass for a `colour` target.
    pub fn new(gpu: &crate::Gpu, colour: wgpu::TextureFormat) -> BackdropPass {
        let device = &gpu.device;
        let module = shader(device, "backdrop", &source());
        let (layout, pipeline_layout) = layouts(
            device,
            "backdrop",
            &entries(BINDINGS, wgpu::ShaderStages::VERTEX_FRAGMENT),
            None,
        );
        let pipeline = pipeline(
            device,
            PipelineSpec {
                label: "backdrop",
                layout: &pipeline_layout,
                module: &module,
                vertex: "vs_main",
                cull: None,
                fragment: "fs_main",
                buffers: &[],
                depth: None,
                targets: &[Some(blended(colour))],
                constants: &[],
            },
        );
        let blank = texture((device, &gpu.queue), 1, 1, &[255, 255, 255, 255]);
        BackdropPass {
            layout,
            pipeline,
            image: Mutex::new(None),
            blank,
        }
    }

    /// Records the pass over `target`.
    pub fn record(
        &self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        visibility: &VisibilityTargets,
        (frame, uniform, background): (&wgpu::Buffer, &BackdropUniform, &Background),
        target: &wgpu::TextureView,
    ) {
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("backdrop"),
            contents: bytemuck::bytes_of(uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut kept = self.image.lock().unwrap_or_else(|e| e.into_inner());
        let image_view = match background {
            Background::Image(image) if image.width() > 0 && image.height() > 0 => {
                let key = Arc::as_ptr(image) as usize;
                if kept.as_ref().is_none_or(|(k, _)| *k != key) {
                    // Larger than a texture may be: scaled down to fit (it is stretched
                    // over the view anyway).
                    let max = device.limits().max_texture_dimension_2d;
                    let (w, h) = image.dimensions();
                    let fitted;
                    let image: &image::RgbaImage = if w > max || h > max {
                        let scale = f64::from(max) / f64::from(w.max(h));
                        fitted = image::imageops::resize(
                            image.as_ref(),
                            ((f64::from(w) * scale) as u32).max(1),
                            ((f64::from(h) * scale) as u32).max(1),
                            image::imageops::FilterType::Triangle,
                        );
                        &fitted
                    } else {
                        image
                    };
                    let (w, h) = image.dimensions();
                    *kept = Some((key, texture((device, queue), w, h, image.as_raw())));
                }
                &kept.as_ref().expect("uploaded").1
            }
            _ => &self.blank,
        };
        let bind = super::common::bind_group(
            device,
            "backdrop",
            &self.layout,
            &[
                frame.as_entire_binding(),
                buffer.as_entire_binding(),
                wgpu::BindingResource::TextureView(&visibility.depth),
                wgpu::BindingResource::TextureView(&visibility.ids),
                wgpu::BindingResource::TextureView(image_view),
            ],
        );
        let mut pass = colour_pass(encoder, "backdrop", (target, None), None);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// An RGBA8 texture of `pixels` (row by row; a size the device refuses is left to its
/// validation error, which the frame reports).
fn texture(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    w: u32,
    h: u32,
    pixels: &[u8],
) -> wgpu::TextureView {
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("background image"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        pixels,
    );
    texture.create_view(&Default::default())
}
