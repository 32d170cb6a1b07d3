//! Visibility pass: the visibility buffer (depth, normal, ids, (u, v)) and the surface
//! back-ends that write it. The pass is opened once per frame (targets cleared) and every
//! back-end draws into it in turn; each back-end's fragments go through the one texel writer
//! of `texel.wgsl` (section caps, id packing), so shading, edges, picking and sections read
//! the same buffer whatever drew it. Back-ends: [`mesh`] (the scene's triangles), then
//! [`analytic`] (spheres and rectangles ray cast per pixel).

pub(crate) mod analytic;
pub(crate) mod mesh;

use crate::gpu_scene::FrameScene;

/// The WGSL of the shared texel writer, placed before each back-end's own source.
pub(crate) const TEXEL_WGSL: &str = include_str!("texel.wgsl");

/// Formats of the visibility buffer.
pub(crate) const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// View-space unit normal (xyz), coverage (w).
pub(crate) const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Face id, instance + 1 (0 = background), material, depth (f32 bits).
pub(crate) const IDS: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// (u, v) on the face's exact surface, as f32 bits (float targets of 32 bits are not
/// renderable on GL, integer ones are).
pub(crate) const UV: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// The surface back-ends, drawn in this order into one opened pass.
pub(crate) struct VisibilityPass {
    mesh: mesh::MeshBackend,
    analytic: analytic::AnalyticBackend,
}

/// Depth state of every back-end: reverse Z (nearer is larger), written.
pub(crate) fn depth_state() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Greater),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A visibility target of `format`, written whole, not blended.
const fn written(format: wgpu::TextureFormat) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    })
}

/// Colour targets of every back-end: normal, ids, (u, v); [`TARGETS_NO_UV`] when nothing
/// reads the (u, v).
pub(crate) const TARGETS: [Option<wgpu::ColorTargetState>; 3] =
    [written(NORMAL), written(IDS), written(UV)];

/// [`TARGETS`] without the (u, v) target: only the exact-surface tests read it, and on a CPU
/// rasterizer every target is memory to clear, write and fault in (8 of the 36 bytes a pixel).
pub(crate) const TARGETS_NO_UV: [Option<wgpu::ColorTargetState>; 3] =
    [written(NORMAL), written(IDS), None];

/// The visibility buffer's textures, of one size.
pub(crate) struct VisibilityTargets {
    pub depth: wgpu::TextureView,
    pub normal: wgpu::TextureView,
    pub ids: wgpu::TextureView,
    pub ids_texture: wgpu::Texture,
    /// The (u, v) target, made only for frames that read it back.
    pub uv: Option<(wgpu::TextureView, wgpu::Texture)>,
}

impl VisibilityTargets {
    /// Targets of `width` × `height`, with the (u, v) one when `with_uv`.
    pub fn new(
        device: &wgpu::Device,
        (width, height): (u32, u32),
        with_uv: bool,
    ) -> VisibilityTargets {
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
        let uv = with_uv.then(|| {
            let texture = make("uv", UV, wgpu::TextureUsages::COPY_SRC);
            (texture.create_view(&Default::default()), texture)
        });
        VisibilityTargets {
            depth: depth.create_view(&Default::default()),
            normal: normal.create_view(&Default::default()),
            ids: ids.create_view(&Default::default()),
            ids_texture: ids,
            uv,
        }
    }
}

impl VisibilityPass {
    /// Builds every back-end's pipeline.
    pub fn new(
        device: &wgpu::Device,
        instances: &crate::passes::instances::InstanceLayout,
    ) -> VisibilityPass {
        VisibilityPass {
            mesh: mesh::MeshBackend::new(device, instances),
            analytic: analytic::AnalyticBackend::new(device),
        }
    }

    /// Records the pass: opens it once on `targets` (cleared) and has every back-end draw
    /// `scene` into it; `sections` says whether the frame has section planes;
    /// `proxy_depth` has the analytic back-end write its proxies' depth (the tests' negative
    /// control).
    pub fn record(
        &self,
        recorder: (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        targets: &VisibilityTargets,
        (frame, sections, proxy_depth): (&wgpu::Buffer, bool, bool),
        scene: &FrameScene<'_>,
    ) {
        let mut pass = open(encoder, targets);
        let with_uv = targets.uv.is_some();
        let variant = mesh::MeshVariant::of(sections, with_uv);
        self.mesh.draw(recorder, &mut pass, frame, scene, variant);
        self.analytic.draw(
            recorder,
            &mut pass,
            frame,
            &scene.primitives,
            (with_uv, proxy_depth),
        );
    }
}

/// The visibility render pass over `targets`, cleared: background ids 0, depth 0 (far).
fn open<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    targets: &VisibilityTargets,
) -> wgpu::RenderPass<'e> {
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
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("visibility"),
        color_attachments: &[
            clear(&targets.normal),
            clear(&targets.ids),
            targets.uv.as_ref().and_then(|(uv, _)| clear(uv)),
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
    })
}
