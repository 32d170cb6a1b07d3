//! Lines pass: a [`crate::LineSet`]'s polylines drawn over the shaded image with joins, caps
//! and an exact stipple (see [`crate::lines`]).
//!
//! Each frame: the screen arc length of every point, by a segmented scan in one compute pass
//! (`scan.wgsl`: blocks of 1,024 points, the carries between blocks, the carries added —
//! three dispatches whatever the count), then every segment as one instanced quad
//! (`lines.wgsl`) whose fragments find their coverage in the segment's frame. Where the
//! adapter has no compute shaders the arc lengths come from [`crate::lines::reference`] on the
//! CPU.
//!
//! The set is uploaded in chunks of at most one storage binding of points (32 bytes a point:
//! 4 M points at 128 MiB); a polyline that crosses into the next chunk continues there, its
//! stipple restarting at the chunk's first point.

use super::common::{blended, colour_pass, entries, layouts, shader, wgsl};
use crate::Camera;
use crate::gpu_scene::buffer_limit;
use crate::layout::{
    Binding, FrameUniform, GpuStruct, LINE_CAP_BUTT, LINE_CAP_ROUND, LINE_CAP_SQUARE,
    LINE_HIDDEN_SHOWN, LINE_HIDDEN_STYLED, LINE_JOIN_BEVEL, LINE_JOIN_MITER, LINE_JOIN_ROUND,
    LINE_POINT_COLOURS, LINE_WHOLE, LINE_WORLD_WIDTH, LineFrame, LinePoint, LineStyleGpu,
};
use crate::lines::{Cap, Hidden, Join, LineSet, LineStyle, LineView, LineWidth};
use glam::{DMat4, DVec3};
use wgpu::util::DeviceExt;

/// Points a scan block holds (`BLOCK` in scan.wgsl).
const BLOCK: u32 = 1024;
/// Most workgroups along one dispatch dimension.
const MAX_GROUPS: u32 = 65_535;

/// The scan's bind group 0: frame, line frame, points, arc lengths, block records.
pub(crate) const SCAN_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Uniform(LineFrame::WGSL_NAME),
    Binding::Storage(LinePoint::WGSL_NAME),
    Binding::StorageWrite("f32"),
    Binding::StorageWrite("vec2<u32>"),
];

/// The draw's bind group 0: frame, line frame, points, arc lengths, each polyline's style,
/// the styles, the visibility depth.
pub(crate) const DRAW_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Uniform(LineFrame::WGSL_NAME),
    Binding::Storage(LinePoint::WGSL_NAME),
    Binding::Storage("f32"),
    Binding::Storage("u32"),
    Binding::Storage(LineStyleGpu::WGSL_NAME),
    Binding::FloatTexture,
];

/// The scan's whole WGSL.
pub(crate) fn scan_source() -> String {
    wgsl(&[include_str!("project.wgsl"), include_str!("scan.wgsl")])
}

/// The draw's whole WGSL.
pub(crate) fn draw_source() -> String {
    wgsl(&[include_str!("project.wgsl"), include_str!("lines.wgsl")])
}

/// A style as the shader reads it.
pub(crate) fn style_to_gpu(style: &LineStyle, point_colours: bool) -> LineStyleGpu {
    let linear = |c: [f32; 4]| {
        let f = crate::renderer::srgb_to_linear;
        [f(c[0]), f(c[1]), f(c[2]), c[3]]
    };
    let (width, world) = match style.width {
        LineWidth::Pixels(px) => (px, false),
        LineWidth::World(w) => (w as f32, true),
    };
    let (join, miter_limit) = match style.join {
        Join::Miter { limit } => (LINE_JOIN_MITER, limit.max(1.0)),
        Join::Round => (LINE_JOIN_ROUND, 1.0),
        Join::Bevel => (LINE_JOIN_BEVEL, 1.0),
    };
    let (hidden_colour, hidden, hidden_flag) = match style.hidden {
        Hidden::Hide => ([0.0; 4], style.stipple, 0),
        Hidden::Show => ([0.0; 4], style.stipple, LINE_HIDDEN_SHOWN),
        Hidden::Styled { colour, stipple } => (linear(colour), stipple, LINE_HIDDEN_STYLED),
    };
    LineStyleGpu {
        colour: linear(style.colour),
        hidden_colour,
        width,
        factor: style.stipple.factor.max(1) as f32,
        hidden_factor: hidden.factor.max(1) as f32,
        miter_limit,
        pattern: u32::from(style.stipple.pattern),
        hidden_pattern: u32::from(hidden.pattern),
        join,
        cap: match style.cap {
            Cap::Butt => LINE_CAP_BUTT,
            Cap::Square => LINE_CAP_SQUARE,
            Cap::Round => LINE_CAP_ROUND,
        },
        flags: hidden_flag
            | if world { LINE_WORLD_WIDTH } else { 0 }
            | if point_colours { LINE_POINT_COLOURS } else { 0 }
            | if style.follows_view { 0 } else { LINE_WHOLE },
        pad: [0; 3],
    }
}

/// One chunk of a set's points on the GPU, with its per-frame buffers.
pub(crate) struct LineChunk {
    /// Points in it.
    count: u32,
    points: wgpu::Buffer,
    /// One `f32` a point: the scan's output.
    arc: wgpu::Buffer,
    /// One `vec2<u32>` a scan block.
    blocks: wgpu::Buffer,
    /// Its [`LineFrame`], written every frame.
    frame: wgpu::Buffer,
    /// The chunk's points in world coordinates, polyline by polyline, for the CPU scan
    /// (only where the adapter has no compute shaders).
    cpu: Option<LineSet>,
}

/// A line set on the GPU.
pub(crate) struct GpuLines {
    /// What the points are relative to (the set's box centre).
    origin: DVec3,
    chunks: Vec<LineChunk>,
    polyline_styles: wgpu::Buffer,
    styles: wgpu::Buffer,
}

impl GpuLines {
    /// Uploads `set` (`None` when it has no segment); `cpu_scan`: keep the points for the
    /// CPU scan.
    pub fn new(gpu: &crate::Gpu, set: &LineSet, cpu_scan: bool) -> Option<GpuLines> {
        if set.is_empty() {
            return None;
        }
        let device = &gpu.device;
        let (lo, hi) = set.bounds()?;
        let origin = 0.5 * (lo + hi);
        let usage = wgpu::BufferUsages::STORAGE;
        let per_binding = (buffer_limit(&device.limits(), usage)
            / std::mem::size_of::<LinePoint>() as u64)
            .clamp(2, u64::from(u32::MAX)) as usize;
        let styles: Vec<LineStyleGpu> = if set.styles.is_empty() {
            vec![style_to_gpu(&LineStyle::default(), false)]
        } else {
            set.styles
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    let coloured = set
                        .polylines
                        .iter()
                        .any(|p| p.style as usize == k && !p.colours.is_empty());
                    style_to_gpu(s, coloured)
                })
                .collect()
        };
        let polyline_styles: Vec<u32> = set
            .polylines
            .iter()
            .map(|p| {
                if (p.style as usize) < styles.len() {
                    p.style
                } else {
                    0
                }
            })
            .collect();
        // The points, chunk by chunk; a polyline crossing a chunk's end goes on in the next
        // from its last point there.
        let mut chunks: Vec<(Vec<LinePoint>, LineSet)> = vec![Default::default()];
        let mut travel = 0.0f64;
        for (index, polyline) in set.polylines.iter().enumerate() {
            let mut previous: Option<DVec3> = None;
            // Whole polylines do not count along the travel (nor are cut by it).
            let counts = set.style_of(polyline).follows_view;
            for (k, p) in polyline.points.iter().enumerate() {
                if !p.is_finite() {
                    continue;
                }
                if let Some(q) = previous
                    && counts
                {
                    travel += q.distance(*p);
                }
                let colour = polyline
                    .colours
                    .get(k)
                    .map_or(0xffff_ffff, |c| u32::from_le_bytes(*c));
                let point = LinePoint {
                    position: (*p - origin).as_vec3().to_array(),
                    polyline: index as u32,
                    travel: travel as f32,
                    colour,
                    pad: [0; 2],
                };
                let full = chunks.last().is_some_and(|(c, _)| c.len() >= per_binding);
                if full {
                    let carried = chunks
                        .last()
                        .and_then(|(c, _)| c.last().copied())
                        .filter(|last| last.polyline == index as u32);
                    let mut next: (Vec<LinePoint>, LineSet) = Default::default();
                    if let Some(last) = carried {
                        next.0.push(last);
                        if cpu_scan {
                            next.1.polylines.push(crate::lines::Polyline {
                                points: vec![previous.unwrap_or(*p)],
                                ..Default::default()
                            });
                        }
                    }
                    chunks.push(next);
                }
                let (gpu_points, cpu) = chunks.last_mut().expect("a chunk");
                let starts = gpu_points.last().is_none_or(|l| l.polyline != index as u32);
                gpu_points.push(point);
                if cpu_scan {
                    if starts {
                        cpu.polylines.push(crate::lines::Polyline::default());
                    }
                    if let Some(last) = cpu.polylines.last_mut() {
                        last.points.push(*p);
                    }
                }
                previous = Some(*p);
            }
        }
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let chunks: Vec<LineChunk> = chunks
            .into_iter()
            .filter(|(p, _)| p.len() >= 2)
            .map(|(points, cpu)| {
                let count = points.len() as u32;
                let blocks = count.div_ceil(BLOCK);
                LineChunk {
                    count,
                    points: storage("line points", bytemuck::cast_slice(&points)),
                    arc: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("line arc lengths"),
                        size: 4 * u64::from(count),
                        usage: wgpu::BufferUsages::STORAGE
                            | wgpu::BufferUsages::COPY_DST
                            | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: false,
                    }),
                    blocks: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("line scan blocks"),
                        size: 8 * u64::from(blocks.max(1)),
                        usage: wgpu::BufferUsages::STORAGE,
                        mapped_at_creation: false,
                    }),
                    frame: device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("line frame"),
                        size: std::mem::size_of::<LineFrame>() as u64,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    }),
                    cpu: cpu_scan.then_some(cpu),
                }
            })
            .collect();
        if chunks.is_empty() {
            return None;
        }
        Some(GpuLines {
            origin,
            chunks,
            polyline_styles: storage(
                "line polyline styles",
                bytemuck::cast_slice(&polyline_styles),
            ),
            styles: storage("line styles", bytemuck::cast_slice(&styles)),
        })
    }

    /// The per-frame constants for `camera` on a `size` target of `scale` target pixels per
    /// output pixel, showing `view`.
    pub fn frame(
        &self,
        camera: &Camera,
        (w, h): (u32, u32),
        scale: f32,
        view: &LineView,
    ) -> LineFrame {
        let aspect = f64::from(w) / f64::from(h);
        let projection = camera.projection_matrix(aspect);
        let to_clip =
            projection * camera.view_rotation() * DMat4::from_translation(self.origin - camera.eye);
        let (clip_lo, clip_hi) = match view.clip_box {
            Some((lo, hi)) => {
                let (lo, hi) = ((lo - self.origin).as_vec3(), (hi - self.origin).as_vec3());
                (lo.extend(1.0).to_array(), hi.extend(1.0).to_array())
            }
            None => ([0.0; 4], [0.0; 4]),
        };
        LineFrame {
            to_clip: to_clip.as_mat4().to_cols_array_2d(),
            viewport: [w as f32, h as f32, scale, 0.0],
            clip_lo,
            clip_hi,
            limits: [
                view.up_to.map_or(f32::INFINITY, |d| d as f32),
                (projection.y_axis.y * 0.5 * f64::from(h)) as f32,
                0.0,
                0.0,
            ],
            counts: [0; 4],
        }
    }
}

/// The pass's pipelines.
pub(crate) struct LinesPass {
    scan_layout: wgpu::BindGroupLayout,
    /// `scan_blocks`, `scan_carries`, `scan_add`; `None` without compute shaders.
    scans: Option<[wgpu::ComputePipeline; 3]>,
    draw_layout: wgpu::BindGroupLayout,
    draw: wgpu::RenderPipeline,
}

impl LinesPass {
    /// Builds the pipelines for a `colour` target.
    pub fn new(gpu: &crate::Gpu, colour: wgpu::TextureFormat) -> LinesPass {
        let device = &gpu.device;
        let (scan_layout, scan_pipeline_layout) = layouts(
            device,
            "line scan",
            &entries(SCAN_BINDINGS, wgpu::ShaderStages::COMPUTE),
            None,
        );
        let scans = gpu.compute.then(|| {
            let module = shader(device, "line scan", &scan_source());
            ["scan_blocks", "scan_carries", "scan_add"].map(|entry| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&scan_pipeline_layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
        });
        let (draw_layout, draw_pipeline_layout) = layouts(
            device,
            "lines",
            &entries(DRAW_BINDINGS, wgpu::ShaderStages::VERTEX_FRAGMENT),
            None,
        );
        let module = shader(device, "lines", &draw_source());
        // A strip of four corners a segment (`vs_main`).
        let draw = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lines"),
            layout: Some(&draw_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
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
        LinesPass {
            scan_layout,
            scans,
            draw_layout,
            draw,
        }
    }

    /// Records the scan (or writes the CPU's arc lengths) of every chunk of `lines`.
    pub fn record_scan(
        &self,
        gpu: &crate::Gpu,
        encoder: &mut wgpu::CommandEncoder,
        (frame, lines): (&wgpu::Buffer, &GpuLines),
        (camera, size, line_frame): (&Camera, (u32, u32), &LineFrame),
    ) {
        let device = &gpu.device;
        for chunk in &lines.chunks {
            let blocks = chunk.count.div_ceil(BLOCK);
            let mut uniform = *line_frame;
            uniform.counts = [chunk.count, blocks, 0, 0];
            gpu.queue
                .write_buffer(&chunk.frame, 0, bytemuck::bytes_of(&uniform));
            match (&self.scans, &chunk.cpu) {
                (Some(scans), _) => {
                    let bind = super::common::bind_group(
                        device,
                        "line scan",
                        &self.scan_layout,
                        &[
                            frame.as_entire_binding(),
                            chunk.frame.as_entire_binding(),
                            chunk.points.as_entire_binding(),
                            chunk.arc.as_entire_binding(),
                            chunk.blocks.as_entire_binding(),
                        ],
                    );
                    let grid = (blocks.min(MAX_GROUPS), blocks.div_ceil(MAX_GROUPS));
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("line scan"),
                        timestamp_writes: None,
                    });
                    pass.set_bind_group(0, &bind, &[]);
                    pass.set_pipeline(&scans[0]);
                    pass.dispatch_workgroups(grid.0, grid.1, 1);
                    pass.set_pipeline(&scans[1]);
                    pass.dispatch_workgroups(1, 1, 1);
                    pass.set_pipeline(&scans[2]);
                    pass.dispatch_workgroups(grid.0, grid.1, 1);
                }
                (None, Some(cpu)) => {
                    let arc: Vec<f32> = crate::lines::reference::arc_lengths(cpu, camera, size)
                        .into_iter()
                        .map(|s| s as f32)
                        .collect();
                    gpu.queue
                        .write_buffer(&chunk.arc, 0, bytemuck::cast_slice(&arc));
                }
                (None, None) => {}
            }
        }
    }

    /// Records the draw of every chunk of `lines` over `target`, tested against `depth`.
    pub fn record_draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (frame, lines): (&wgpu::Buffer, &GpuLines),
        depth: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let binds: Vec<wgpu::BindGroup> = lines
            .chunks
            .iter()
            .map(|chunk| {
                super::common::bind_group(
                    device,
                    "lines",
                    &self.draw_layout,
                    &[
                        frame.as_entire_binding(),
                        chunk.frame.as_entire_binding(),
                        chunk.points.as_entire_binding(),
                        chunk.arc.as_entire_binding(),
                        lines.polyline_styles.as_entire_binding(),
                        lines.styles.as_entire_binding(),
                        wgpu::BindingResource::TextureView(depth),
                    ],
                )
            })
            .collect();
        let mut pass = colour_pass(encoder, "lines", (target, None), None);
        pass.set_pipeline(&self.draw);
        for (chunk, bind) in lines.chunks.iter().zip(&binds) {
            pass.set_bind_group(0, bind, &[]);
            pass.draw(0..4, 0..chunk.count - 1);
        }
    }

    /// Copies the first chunk's arc lengths into a readable buffer (for the tests).
    pub fn copy_arc(
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        lines: &GpuLines,
    ) -> Option<(wgpu::Buffer, u32)> {
        let chunk = lines.chunks.first()?;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("arc readback"),
            size: 4 * u64::from(chunk.count),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(&chunk.arc, 0, &buffer, 0, 4 * u64::from(chunk.count));
        Some((buffer, chunk.count))
    }
}
