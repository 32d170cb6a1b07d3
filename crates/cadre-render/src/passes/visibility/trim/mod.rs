//! The trim back-end (seed 000, Part III): B-Rep faces drawn from their exact definition.
//! Each frame, a compute pass (`tessellate.wgsl`) chooses for every face of every mesh call
//! the grid its support surface is drawn with (its error within a tolerance in pixels at the
//! face's nearest instance; none when it is out of view) and writes it as an indirect draw;
//! the visibility pass then draws each call's faces with one `multi_draw_indirect`, the
//! vertex shader evaluating the surface in closed form at the grid's corners (`trim.wgsl`),
//! and every fragment tested against the face's trim tree (`cadre_trim`'s `trim.wgsl`) with
//! the pixel-footprint stop rule before `visibility_texel` writes it, as the mesh back-end's
//! are. What it does not draw (faces without a tree or on surfaces it cannot evaluate, the
//! see-through and x-ray phases) the meshes draw.

use std::sync::OnceLock;

use super::{Phase, PhaseInputs, TARGETS, TARGETS_NO_UV, TEXEL_WGSL, depth_state};
use crate::layout::{Binding, FrameUniform, GpuStruct, TrimCall, TrimSurface, TrimTask};
use crate::passes::common::{PipelineSpec, entries, layouts, pipeline, shader, wgsl};
use crate::passes::instances::{INSTANCES_WGSL, InstanceLayout};
use wgpu::util::DeviceExt;

/// The render shader's bind group 0: frame, surfaces, the tessellation's levels, the five
/// trim buffers (`cadre_trim::TrimBuffers`), the packed B-splines, the evaluated grid
/// points; group 1: the instances.
pub(crate) const BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(TrimSurface::WGSL_NAME),
    Binding::Storage("u32"),
    Binding::Storage("TrimFace"),
    Binding::Storage("u32"),
    Binding::Storage("f32"),
    Binding::Storage("u32"),
    Binding::Storage("u32"),
    Binding::Storage("f32"),
    Binding::Storage("vec4<f32>"),
];

/// The exact crack fill's bind group 0 (`crack.wgsl`, after the render shader): the render
/// shader's [`BINDINGS`], then the crack map, the entries, the state and the hits
/// (`passes::cracks`), the frame's trim draws and the crack seeds (the seeded solves');
/// group 1: the instances.
pub(crate) const CRACK_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(TrimSurface::WGSL_NAME),
    Binding::Storage("u32"),
    Binding::Storage("TrimFace"),
    Binding::Storage("u32"),
    Binding::Storage("f32"),
    Binding::Storage("u32"),
    Binding::Storage("u32"),
    Binding::Storage("f32"),
    Binding::Storage("vec4<f32>"),
    Binding::Storage("u32"),
    Binding::Storage("vec4<u32>"),
    Binding::AtomicStorage,
    Binding::StorageWrite("vec4<u32>"),
    Binding::Storage(TrimCall::WGSL_NAME),
    Binding::StorageWrite("vec4<u32>"),
];

/// Of [`CRACK_BINDINGS`], those the raster fill (`vs_crack`, `fs_crack`) binds: the render
/// shader's and the crack map, entries, state and hits.
const CRACK_RASTER_BINDINGS: usize = 14;

/// Of [`CRACK_BINDINGS`], those the seeded solves leave out (the levels, the grid points,
/// the crack map), so that their compute stage binds 14 storage buffers with the instances'
/// (the device is asked for 16 a stage at most, `Gpu`).
const SEEDED_UNBOUND: [u32; 3] = [2, 9, 10];

/// The pass that picks the exact crack fill's faces (`crack_faces.wgsl`), bind group 0:
/// frame, surfaces, tasks, the tessellation's indirect draws, the fill's (written), the
/// crack entries and state (`passes::cracks`), the packed B-splines; group 1: the instances.
pub(crate) const CRACK_FACES_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(TrimSurface::WGSL_NAME),
    Binding::Storage(TrimTask::WGSL_NAME),
    Binding::Storage("u32"),
    Binding::StorageWrite("u32"),
    Binding::Storage("vec4<u32>"),
    Binding::AtomicStorage,
    Binding::Storage("f32"),
    Binding::Storage("vec4<u32>"),
];

/// Storage buffers the exact crack fill's fragment stage binds: the render shader's nine,
/// the crack buffers' four and the instances' two.
pub(crate) const CRACK_STORAGE_BUFFERS: u32 = 15;

/// The tessellation pass's bind group 0: frame, surfaces, tasks, what it writes (the
/// indirect draws and the levels), the packed B-splines (their knot lines), the count of
/// grid points taken and the points (with the cells' verdicts after them), the five trim
/// buffers; group 1: the instances.
pub(crate) const TESSELLATE_BINDINGS: &[Binding] = &[
    Binding::Uniform(FrameUniform::WGSL_NAME),
    Binding::Storage(TrimSurface::WGSL_NAME),
    Binding::Storage(TrimTask::WGSL_NAME),
    Binding::StorageWrite("u32"),
    Binding::StorageWrite("u32"),
    Binding::Storage("f32"),
    Binding::AtomicStorage,
    Binding::StorageWrite("vec4<f32>"),
    Binding::Storage("TrimFace"),
    Binding::Storage("u32"),
    Binding::Storage("f32"),
    Binding::Storage("u32"),
    Binding::Storage("u32"),
];

/// Storage buffers a stage of the back-end binds, at most: the tessellation pass' twelve and
/// the instances' two (the render shader's stages bind eleven); an adapter allowing fewer
/// per stage draws every face from its mesh.
pub(crate) const STORAGE_BUFFERS: u32 = 14;

/// Grid points the tessellation pass may hold per task, on average, before faces fall back
/// to being evaluated by the vertex shader: a 32 × 32 grid (a frame's faces mostly need far
/// fewer; the room is taken first come, first served).
const POINTS_PER_TASK: u64 = 33 * 33;

/// Bytes of one grid point (two `vec4<f32>`).
const POINT_BYTES: u64 = 32;

/// Vertices reserved for each face of a draw: 6 a cell of the largest grid, 256 × 256 cells
/// (`TRIM_VERTICES` in surface.wgsl).
pub(crate) const TRIM_VERTICES: u32 = 6 * 256 * 256;

/// Faces one indirect draw can hold: their vertex numbers stay within `u32`.
pub(crate) const FACES_PER_DRAW: u32 = u32::MAX / TRIM_VERTICES;

/// The tessellation's tolerance in pixels (`TOLERANCE_PX` in tessellate.wgsl).
pub const TOLERANCE_PX: f64 = 0.5;

/// The tessellation's tolerance relative to a face's bounding radius (`TOLERANCE_REL` in
/// tessellate.wgsl): a bound in depth too, so a coarse grid does not sag through a surface
/// just behind it (a thin wall's other side).
pub const TOLERANCE_REL: f64 = 0.002;

/// Workgroups evaluating one task's grid points (`POINT_CHUNKS` in tessellate.wgsl): 1,024
/// invocations share a grid, so none evaluates more than 65 points of the largest (257²).
/// Mesa's llvmpipe ends a shader's loops after 65,535 iterations in all, inner loops
/// counted: with one workgroup a task, a degree-8 × 11 B-spline point (≈ 360 iterations)
/// stopped each lane after 180 points and left the rest of a 257 × 256 grid unwritten —
/// an earlier frame's points, drawn as triangles across the view (trj7_b1-ec-214 at 1000×,
/// 2026-12-06); 65 points of a degree-15 × 15 point's ≈ 600 iterations stay within it.
const POINT_CHUNKS: u32 = 16;

/// The shared declarations: the face record and the surfaces' closed forms.
const SURFACE_WGSL: &str = include_str!("surface.wgsl");

/// The render shader's whole WGSL.
pub(crate) fn source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        TEXEL_WGSL,
        SURFACE_WGSL,
        include_str!("bspline.wgsl"),
        include_str!("sweep.wgsl"),
        include_str!("raycast.wgsl"),
        include_str!("trim.wgsl"),
        cadre_trim::TRIM_WGSL,
    ])
}

/// The exact crack fill's whole WGSL: the render shader's and `crack.wgsl`.
pub(crate) fn crack_source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        TEXEL_WGSL,
        SURFACE_WGSL,
        include_str!("bspline.wgsl"),
        include_str!("sweep.wgsl"),
        include_str!("raycast.wgsl"),
        include_str!("trim.wgsl"),
        cadre_trim::TRIM_WGSL,
        crate::passes::cracks::LAYOUT_WGSL,
        include_str!("crack.wgsl"),
    ])
}

/// The WGSL of the pass that picks the exact crack fill's faces.
pub(crate) fn crack_faces_source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        SURFACE_WGSL,
        crate::passes::cracks::LAYOUT_WGSL,
        include_str!("crack_faces.wgsl"),
    ])
}

/// The tessellation pass's whole WGSL.
pub(crate) fn tessellate_source() -> String {
    wgsl(&[
        INSTANCES_WGSL,
        SURFACE_WGSL,
        include_str!("bspline.wgsl"),
        include_str!("sweep.wgsl"),
        include_str!("tessellate.wgsl"),
        cadre_trim::TRIM_WGSL,
    ])
}

/// A prepared scene's trimmed faces on the GPU: their records and their trees.
pub(crate) struct TrimGeometry {
    surfaces: wgpu::Buffer,
    faces: wgpu::Buffer,
    nodes: wgpu::Buffer,
    floats: wgpu::Buffer,
    piece_offsets: wgpu::Buffer,
    lists: wgpu::Buffer,
    bspline: wgpu::Buffer,
}

/// A storage buffer of `bytes` (one word when empty: storage bindings may not be).
fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    let bytes = if bytes.is_empty() {
        &[0u8; 4][..]
    } else {
        bytes
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

impl TrimGeometry {
    /// Uploads the face records `surfaces` and the packed `trees` they point into.
    pub fn new(
        device: &wgpu::Device,
        surfaces: &[TrimSurface],
        (trees, bspline): (&cadre_trim::TrimBuffers, &[f32]),
    ) -> TrimGeometry {
        TrimGeometry {
            surfaces: storage(device, "trim surfaces", bytemuck::cast_slice(surfaces)),
            faces: storage(
                device,
                "trim faces",
                bytemuck::cast_slice(&trees.face_words()),
            ),
            nodes: storage(device, "trim nodes", bytemuck::cast_slice(&trees.nodes)),
            floats: storage(device, "trim floats", bytemuck::cast_slice(&trees.floats)),
            piece_offsets: storage(
                device,
                "trim piece offsets",
                bytemuck::cast_slice(&trees.piece_offsets),
            ),
            lists: storage(device, "trim lists", bytemuck::cast_slice(&trees.lists)),
            bspline: storage(device, "trim B-splines", bytemuck::cast_slice(bspline)),
        }
    }
}

/// One indirect draw of a frame: `faces` faces of a mesh call through call `slot` (whose
/// `range` holds the first surface and the first task), their draws at task `task_first`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TrimDraw {
    pub slot: u32,
    pub faces: u32,
    pub task_first: u32,
}

/// A frame's tessellation tasks and the indirect draws they become.
pub(crate) struct FrameTrim {
    tasks: wgpu::Buffer,
    args: wgpu::Buffer,
    /// The exact crack fill's draws: `args` where a face is about a crack, else empty
    /// (`crack_faces.wgsl`).
    crack_args: wgpu::Buffer,
    levels: wgpu::Buffer,
    count: u32,
    pub draws: Vec<TrimDraw>,
    /// The draws as the seeded solves' match reads them (a [`TrimCall`] each).
    seed_calls: wgpu::Buffer,
    /// The seeded solves' match dispatch: x copied from the crack pass's count each frame,
    /// a workgroup row (y, then z past 65,535) a draw.
    seed_dispatch: wgpu::Buffer,
}

impl FrameTrim {
    /// The buffers of `tasks` and of what the tessellation pass writes for them; `None` when
    /// there is nothing to draw.
    pub fn new(device: &wgpu::Device, tasks: &[TrimTask], draws: Vec<TrimDraw>) -> Option<Self> {
        if tasks.is_empty() {
            return None;
        }
        let count = tasks.len() as u32;
        let calls: Vec<TrimCall> = draws
            .iter()
            .filter_map(|d| {
                let t = tasks.get(d.task_first as usize)?;
                Some(TrimCall {
                    first_surface: t.surface,
                    faces: d.faces,
                    record: t.record,
                    locals_first: t.locals_first,
                    locals_count: t.locals_count,
                    instances: t.instances,
                    pad: [0; 2],
                })
            })
            .collect();
        let rows = (calls.len() as u32).max(1);
        let dispatch = [0, rows.min(SEED_ROWS), rows.div_ceil(SEED_ROWS), 0];
        let written = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        Some(FrameTrim {
            tasks: storage(device, "trim tasks", bytemuck::cast_slice(tasks)),
            args: written(
                "trim draws",
                16 * u64::from(count),
                wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC,
            ),
            crack_args: written(
                "trim crack fill draws",
                16 * u64::from(count),
                wgpu::BufferUsages::INDIRECT,
            ),
            levels: written(
                "trim levels",
                8 * u64::from(count),
                wgpu::BufferUsages::empty(),
            ),
            count,
            draws,
            seed_calls: storage(device, "trim seed calls", bytemuck::cast_slice(&calls)),
            seed_dispatch: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trim seed match dispatch"),
                contents: bytemuck::cast_slice(&dispatch),
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            }),
        })
    }
}

/// Workgroup rows of the seeded solves' match dispatch at most (`CRACK_SEED_ROWS` in
/// crack.wgsl; wgpu's limit on a dimension).
const SEED_ROWS: u32 = 65_535;

/// How the back-end draws: as it should (the default), or with a part switched off, for the
/// tests' negative control and the benchmarks that separate its costs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrimVariant {
    /// Fragments are tested against their trees (off: every face drawn over its whole box).
    pub trim_test: bool,
    /// Grid lines a face may have each way (256; 1 leaves the geometry at its least).
    pub max_level: u32,
    /// Grid points evaluated in the tessellation pass (off: room for none, so that every
    /// face takes the vertex shader's way, which the tests check as well).
    pub grid_points: bool,
    /// Plane, cylinder, cone, sphere and ring torus faces ray cast against their support
    /// surface and trimmed at the hit (`raycast.wgsl`, `--method raycast`) instead of
    /// tessellated.
    pub ray_cast: bool,
}

impl Default for TrimVariant {
    fn default() -> Self {
        TrimVariant {
            trim_test: true,
            max_level: 256,
            grid_points: true,
            ray_cast: false,
        }
    }
}

/// The back-end's pipelines: the tessellation pass, and the render pipelines per variant
/// (sections, (u, v) target), built on first use.
pub(crate) struct TrimBackend {
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    layout: wgpu::BindGroupLayout,
    tessellate: wgpu::ComputePipeline,
    /// The tessellation's second entry point: the grid points.
    points: wgpu::ComputePipeline,
    tessellate_layout: wgpu::BindGroupLayout,
    /// The grid points' buffer (its capacity in points), kept while large enough, and the
    /// count of points taken (cleared each frame).
    grid: std::sync::Mutex<Option<(wgpu::Buffer, u64)>>,
    points_used: wgpu::Buffer,
    /// Indexed by `sections + 2 × with_uv + 4 × coverage`.
    pipelines: [OnceLock<wgpu::RenderPipeline>; 8],
    /// Whether fragments are trimmed (off only for the tests' negative control).
    trim_test: bool,
    /// Whether the tessellation pass evaluates grid points ([`TrimVariant::grid_points`]).
    grid_points: bool,
    /// Whether analytic faces are ray cast ([`TrimVariant::ray_cast`]).
    ray_cast: bool,
    /// The last frame's indirect draws and their count, for [`TrimBackend::last_triangles`].
    last: std::sync::Mutex<Option<(wgpu::Buffer, u32)>>,
    /// The exact crack fill, built on the first frame that asks for it.
    cracks: OnceLock<CrackFill>,
    /// The instances' layout (the crack fill's group 1).
    instances: InstanceLayout,
}

/// The exact crack fill's module, layouts and pipelines (by `sections`).
struct CrackFill {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: [OnceLock<wgpu::RenderPipeline>; 2],
    /// The pass that picks its faces (`crack_faces.wgsl`) and its bind group's layout.
    faces: wgpu::ComputePipeline,
    faces_layout: wgpu::BindGroupLayout,
    /// The seeded solves of the flagged pixels (`crack.wgsl`'s `cs_seed_match` and
    /// `cs_seeded`), by `sections`, and their bind group 0's layout (the fill's
    /// bindings, seen by compute).
    seeded: [OnceLock<[wgpu::ComputePipeline; 2]>; 2],
    seeded_layout: wgpu::BindGroupLayout,
    seeded_pipeline_layout: wgpu::PipelineLayout,
}

impl CrackFill {
    fn new(device: &wgpu::Device, instances: &InstanceLayout) -> CrackFill {
        let early = device
            .features()
            .contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST);
        let source = crate::passes::cracks::with_early_depth(crack_source(), "fs_crack", early);
        let module = shader(device, "trim crack fill", &source);
        // The render shader's bindings as its stages see them; the crack buffers only in the
        // fragment stage (vertex stages may not write storage).
        let shared = BINDINGS.len();
        let mut group = entries(
            &CRACK_BINDINGS[..shared],
            wgpu::ShaderStages::VERTEX_FRAGMENT,
        );
        for (i, mut e) in entries(
            &CRACK_BINDINGS[shared..CRACK_RASTER_BINDINGS],
            wgpu::ShaderStages::FRAGMENT,
        )
        .into_iter()
        .enumerate()
        {
            e.binding = (shared + i) as u32;
            group.push(e);
        }
        let (layout, pipeline_layout) = layouts(device, "trim crack fill", &group, Some(instances));
        let (seeded_layout, seeded_pipeline_layout) = layouts(
            device,
            "trim crack seeded solves",
            &entries(CRACK_BINDINGS, wgpu::ShaderStages::COMPUTE)
                .into_iter()
                .filter(|e| !SEEDED_UNBOUND.contains(&e.binding))
                .collect::<Vec<_>>(),
            Some(instances),
        );
        let (faces_layout, faces_pipeline_layout) = layouts(
            device,
            "trim crack fill faces",
            &entries(CRACK_FACES_BINDINGS, wgpu::ShaderStages::COMPUTE),
            Some(instances),
        );
        let faces = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("trim crack fill faces"),
            layout: Some(&faces_pipeline_layout),
            module: &shader(device, "trim crack fill faces", &crack_faces_source()),
            entry_point: Some("cs_crack_faces"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &[(
                    "CRACK_ENTRY_CAPACITY",
                    f64::from(crate::passes::cracks::ENTRY_CAPACITY),
                )],
                ..Default::default()
            },
            cache: None,
        });
        CrackFill {
            module,
            layout,
            pipeline_layout,
            pipelines: Default::default(),
            faces,
            faces_layout,
            seeded: Default::default(),
            seeded_layout,
            seeded_pipeline_layout,
        }
    }

    /// The seeded solves' pipelines (the match, the solves) for frames with (`sections`)
    /// or without section planes.
    fn seeded(
        &self,
        device: &wgpu::Device,
        sections: bool,
        (trim_test, ray_cast): (bool, bool),
    ) -> &[wgpu::ComputePipeline; 2] {
        self.seeded[usize::from(sections)].get_or_init(|| {
            let flag = |on: bool| if on { 1.0 } else { 0.0 };
            ["cs_seed_match", "cs_seeded"].map(|entry| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&self.seeded_pipeline_layout),
                    module: &self.module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &[
                            ("SECTIONS", flag(sections)),
                            ("TRIM_TEST_CRACKS", flag(trim_test)),
                            ("RAYCAST", flag(ray_cast)),
                            (
                                "CRACK_HIT_CAPACITY",
                                f64::from(crate::passes::cracks::HIT_CAPACITY),
                            ),
                            (
                                "CRACK_ENTRY_CAPACITY",
                                f64::from(crate::passes::cracks::ENTRY_CAPACITY),
                            ),
                        ],
                        ..Default::default()
                    },
                    cache: None,
                })
            })
        })
    }
}

impl TrimBackend {
    /// Compiles both shaders and the tessellation pipeline (`instances` must be visible to
    /// compute shaders); `variant`: see [`TrimVariant`].
    pub fn new(device: &wgpu::Device, instances: &InstanceLayout, variant: TrimVariant) -> Self {
        let trim_test = variant.trim_test;
        let module = shader(device, "visibility trim", &source());
        // Both stages read the trees (the vertex stage classifies each grid cell, the
        // fragment stage each crossed cell's pixels).
        let group = entries(BINDINGS, wgpu::ShaderStages::VERTEX_FRAGMENT);
        let (layout, pipeline_layout) = layouts(device, "visibility trim", &group, Some(instances));
        let compute = shader(device, "trim tessellation", &tessellate_source());
        let (tessellate_layout, tessellate_pipeline_layout) = layouts(
            device,
            "trim tessellation",
            &entries(TESSELLATE_BINDINGS, wgpu::ShaderStages::COMPUTE),
            Some(instances),
        );
        let tessellate = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("trim tessellation"),
            layout: Some(&tessellate_pipeline_layout),
            module: &compute,
            entry_point: Some("cs_main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &[
                    ("TOLERANCE_PX", TOLERANCE_PX),
                    ("TOLERANCE_REL", TOLERANCE_REL),
                    ("MAX_LEVEL", f64::from(variant.max_level.clamp(1, 256))),
                    ("MIN_LEVEL", f64::from(variant.max_level.clamp(1, 4))),
                    ("RAYCAST", if variant.ray_cast { 1.0 } else { 0.0 }),
                ],
                ..Default::default()
            },
            cache: None,
        });
        let points = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("trim grid points"),
            layout: Some(&tessellate_pipeline_layout),
            module: &compute,
            entry_point: Some("cs_points"),
            compilation_options: Default::default(),
            cache: None,
        });
        let points_used = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("trim points taken"),
            size: 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        TrimBackend {
            module,
            pipeline_layout,
            layout,
            tessellate,
            points,
            grid: std::sync::Mutex::new(None),
            points_used,
            tessellate_layout,
            pipelines: Default::default(),
            trim_test,
            grid_points: variant.grid_points,
            ray_cast: variant.ray_cast,
            last: std::sync::Mutex::new(None),
            cracks: OnceLock::new(),
            instances: instances.clone(),
        }
    }

    /// Triangles the last frame's trimmed faces were drawn with (every instance counted),
    /// read back from its indirect draws (waits for the GPU); 0 when it had none.
    pub fn last_triangles(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> u64 {
        let Some((args, count)) = self.last.lock().unwrap_or_else(|e| e.into_inner()).clone()
        else {
            return 0;
        };
        let size = 16 * u64::from(count);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("trim draws readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&args, 0, &readback, 0, size);
        queue.submit([encoder.finish()]);
        let slice = readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        if device.poll(wgpu::PollType::wait_indefinitely()).is_err() {
            return 0;
        }
        let Ok(view) = slice.get_mapped_range() else {
            return 0;
        };
        let words: &[u32] = bytemuck::cast_slice(&view);
        words
            .chunks_exact(4)
            .map(|d| u64::from(d[0] / 3) * u64::from(d[1]))
            .sum()
    }

    /// Records the tessellation pass of a frame with trimmed faces.
    pub fn tessellate(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        inputs: &PhaseInputs<'_>,
    ) {
        let (Some(trim), Some(geometry)) = (&inputs.scene.trim, &inputs.scene.geometry.trim) else {
            return;
        };
        let grid = self.grid_points(device, trim.count);
        encoder.clear_buffer(&self.points_used, 0, None);
        let bind = binds.get(
            device,
            "trim tessellation",
            &self.tessellate_layout,
            &[
                inputs.frame.as_entire_binding(),
                geometry.surfaces.as_entire_binding(),
                trim.tasks.as_entire_binding(),
                trim.args.as_entire_binding(),
                trim.levels.as_entire_binding(),
                geometry.bspline.as_entire_binding(),
                self.points_used.as_entire_binding(),
                grid.as_entire_binding(),
                geometry.faces.as_entire_binding(),
                geometry.nodes.as_entire_binding(),
                geometry.floats.as_entire_binding(),
                geometry.piece_offsets.as_entire_binding(),
                geometry.lists.as_entire_binding(),
            ],
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("trim tessellation"),
            timestamp_writes: None,
        });
        *self.last.lock().unwrap_or_else(|e| e.into_inner()) =
            Some((trim.args.clone(), trim.count));
        pass.set_pipeline(&self.tessellate);
        pass.set_bind_group(0, &bind, &[]);
        pass.set_bind_group(1, &inputs.scene.instances.bind, &[0]);
        pass.dispatch_workgroups(trim.count.div_ceil(64), 1, 1);
        // POINT_CHUNKS workgroups a task (z), the tasks in rows of at most 65,535.
        pass.set_pipeline(&self.points);
        pass.dispatch_workgroups(
            trim.count.min(65_535),
            trim.count.div_ceil(65_535),
            POINT_CHUNKS,
        );
    }

    /// The grid points' buffer for a frame of `tasks` tasks: the kept one, or a larger one
    /// ([`POINTS_PER_TASK`] a task, within the device's largest storage binding).
    fn grid_points(&self, device: &wgpu::Device, tasks: u32) -> wgpu::Buffer {
        let most = device.limits().max_storage_buffer_binding_size / POINT_BYTES;
        let wanted = if self.grid_points {
            (u64::from(tasks) * POINTS_PER_TASK).clamp(1 << 12, most.max(1))
        } else {
            1
        };
        let mut kept = self.grid.lock().unwrap_or_else(|e| e.into_inner());
        match &*kept {
            Some((buffer, capacity)) if *capacity >= wanted => buffer.clone(),
            _ => {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("trim grid points"),
                    size: wanted * POINT_BYTES,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                });
                *kept = Some((buffer.clone(), wanted));
                buffer
            }
        }
    }

    /// Draws its part of `phase`: the trimmed faces into the visibility buffer (the
    /// see-through phases are the meshes').
    pub fn draw(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        pass: &mut wgpu::RenderPass<'_>,
        inputs: &PhaseInputs<'_>,
        phase: Phase,
    ) {
        let (Some(trim), Some(geometry)) = (&inputs.scene.trim, &inputs.scene.geometry.trim) else {
            return;
        };
        if phase != Phase::Visibility {
            return;
        }
        let k = usize::from(inputs.sections)
            + 2 * usize::from(inputs.with_uv)
            + 4 * usize::from(inputs.coverage);
        let pipeline = self.pipelines[k].get_or_init(|| {
            pipeline(
                device,
                PipelineSpec {
                    label: "visibility trim",
                    layout: &self.pipeline_layout,
                    module: &self.module,
                    vertex: "vs_main",
                    // Both sides: the face's side is decided from its normal.
                    cull: None,
                    // The ray-cast variant writes its hits' depth.
                    fragment: if self.ray_cast {
                        "fs_raycast"
                    } else {
                        "fs_main"
                    },
                    buffers: &[],
                    depth: Some(depth_state()),
                    targets: if inputs.with_uv {
                        &TARGETS
                    } else {
                        &TARGETS_NO_UV
                    },
                    constants: &[
                        ("SECTIONS", if inputs.sections { 1.0 } else { 0.0 }),
                        ("TRIM_TEST", if self.trim_test { 1.0 } else { 0.0 }),
                        ("COVERAGE", if inputs.coverage { 1.0 } else { 0.0 }),
                        ("RAYCAST", if self.ray_cast { 1.0 } else { 0.0 }),
                    ],
                },
            )
        });
        let Some(grid) = self
            .grid
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|(buffer, _)| buffer.clone())
        else {
            return;
        };
        let bind = binds.get(
            device,
            "visibility trim",
            &self.layout,
            &render_resources(inputs, (geometry, trim), &grid),
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        let instances = &inputs.scene.instances;
        for draw in &trim.draws {
            pass.set_bind_group(1, &instances.bind, &[instances.offset(draw.slot)]);
            pass.multi_draw_indirect(&trim.args, 16 * u64::from(draw.task_first), draw.faces);
        }
    }

    /// Records the exact crack fill (`crack.wgsl`): the seeded solves, then `mask` (the crack
    /// mask, about the cracks they left), then the trimmed faces about those cracks
    /// (`crack_faces.wgsl` empties the others' draws) drawn again over their whole boxes,
    /// their fragments next to the crack pixels of `buffers`
    /// solving for the exact surface seen there; into a pass over the crack mask
    /// (`buffers.mask`, tested, not written: only the fragments about a crack run).
    pub fn draw_cracks(
        &self,
        (device, binds): (&wgpu::Device, &crate::frame_buffers::BindCache),
        encoder: &mut wgpu::CommandEncoder,
        inputs: &PhaseInputs<'_>,
        buffers: &crate::passes::cracks::CrackBuffers,
        mask: &mut dyn FnMut(&mut wgpu::CommandEncoder),
    ) {
        let (Some(trim), Some(geometry)) = (&inputs.scene.trim, &inputs.scene.geometry.trim) else {
            return;
        };
        let Some(grid) = self
            .grid
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|(buffer, _)| buffer.clone())
        else {
            return;
        };
        let fill = self
            .cracks
            .get_or_init(|| CrackFill::new(device, &self.instances));
        let pipeline = fill.pipelines[usize::from(inputs.sections)].get_or_init(|| {
            pipeline(
                device,
                PipelineSpec {
                    label: "trim crack fill",
                    layout: &fill.pipeline_layout,
                    module: &fill.module,
                    vertex: "vs_crack",
                    cull: None,
                    fragment: "fs_crack",
                    buffers: &[],
                    depth: Some(wgpu::DepthStencilState {
                        depth_write_enabled: Some(false),
                        depth_compare: Some(wgpu::CompareFunction::Greater),
                        ..depth_state()
                    }),
                    targets: &[],
                    constants: &[
                        ("SECTIONS", if inputs.sections { 1.0 } else { 0.0 }),
                        ("TRIM_TEST", 0.0),
                        ("TRIM_TEST_CRACKS", if self.trim_test { 1.0 } else { 0.0 }),
                        ("COVERAGE", 0.0),
                        ("RAYCAST", if self.ray_cast { 1.0 } else { 0.0 }),
                        (
                            "CRACK_HIT_CAPACITY",
                            f64::from(crate::passes::cracks::HIT_CAPACITY),
                        ),
                    ],
                },
            )
        });
        let resources = [
            render_resources(inputs, (geometry, trim), &grid).as_slice(),
            &[
                buffers.map.as_entire_binding(),
                buffers.entries.as_entire_binding(),
                buffers.state.as_entire_binding(),
                buffers.hits.as_entire_binding(),
                trim.seed_calls.as_entire_binding(),
                buffers.seeds.as_entire_binding(),
            ],
        ]
        .concat();
        let bind = binds.get(
            device,
            "trim crack fill",
            &fill.layout,
            &resources[..CRACK_RASTER_BINDINGS],
        );
        let instances = &inputs.scene.instances;
        record_seeded_solves(
            device,
            encoder,
            (fill, self.trim_test, self.ray_cast, inputs.sections),
            (trim, buffers, instances),
            &resources,
        );
        // The depth mask, about the cracks the seeds left.
        mask(encoder);
        // The faces about the cracks: their draws copied, the others' emptied.
        let faces_bind = binds.get(
            device,
            "trim crack fill faces",
            &fill.faces_layout,
            &[
                inputs.frame.as_entire_binding(),
                geometry.surfaces.as_entire_binding(),
                trim.tasks.as_entire_binding(),
                trim.args.as_entire_binding(),
                trim.crack_args.as_entire_binding(),
                buffers.entries.as_entire_binding(),
                buffers.state.as_entire_binding(),
                geometry.bspline.as_entire_binding(),
                buffers.seeds.as_entire_binding(),
            ],
        );
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("trim crack fill faces"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&fill.faces);
            pass.set_bind_group(0, &faces_bind, &[]);
            pass.set_bind_group(1, &inputs.scene.instances.bind, &[0]);
            pass.dispatch_workgroups(trim.count.div_ceil(64), 1, 1);
        }
        let mut pass =
            crate::passes::cracks::depth_only_pass(encoder, "trim crack fill", &buffers.mask, None);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind, &[]);
        for draw in &trim.draws {
            pass.set_bind_group(1, &instances.bind, &[instances.offset(draw.slot)]);
            pass.multi_draw_indirect(
                &trim.crack_args,
                16 * u64::from(draw.task_first),
                draw.faces,
            );
        }
    }
}

/// Records the seeded solves (`crack.wgsl`'s `cs_seed_match` and `cs_seeded`): each seed's
/// face and instance found by one dispatch over the entries and the trim draws, then one
/// dispatch over the entries solves them. `resources`: the exact fill's bind group 0
/// ([`CRACK_BINDINGS`]), of which the solves bind all but [`SEEDED_UNBOUND`].
fn record_seeded_solves(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    (fill, trim_test, ray_cast, sections): (&CrackFill, bool, bool, bool),
    (trim, buffers, instances): (
        &FrameTrim,
        &crate::passes::cracks::CrackBuffers,
        &crate::gpu_scene::FrameInstances,
    ),
    resources: &[wgpu::BindingResource<'_>],
) {
    let [matches, solves] = fill.seeded(device, sections, (trim_test, ray_cast));
    // Made each frame, not cached (`BindCache` numbers bindings by their place).
    let entries: Vec<wgpu::BindGroupEntry<'_>> = crate::passes::common::numbered(resources)
        .filter(|e| !SEEDED_UNBOUND.contains(&e.binding))
        .collect();
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("trim crack seeded solves"),
        layout: &fill.seeded_layout,
        entries: &entries,
    });
    let at = crate::passes::cracks::SEEDED_DISPATCH_OFFSET;
    encoder.copy_buffer_to_buffer(&buffers.args, at, &trim.seed_dispatch, 0, 4);
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("trim crack seeded solves"),
        timestamp_writes: None,
    });
    pass.set_pipeline(matches);
    pass.set_bind_group(0, &bind, &[]);
    pass.set_bind_group(1, &instances.bind, &[0]);
    pass.dispatch_workgroups_indirect(&trim.seed_dispatch, 0);
    pass.set_pipeline(solves);
    pass.dispatch_workgroups_indirect(&buffers.args, at);
}

/// The render shader's bind group 0 ([`BINDINGS`]): the frame, the faces' records and
/// trees, the frame's levels and grid points; the exact crack fill's starts with them.
fn render_resources<'a>(
    inputs: &PhaseInputs<'a>,
    (geometry, trim): (&'a TrimGeometry, &'a FrameTrim),
    grid: &'a wgpu::Buffer,
) -> Vec<wgpu::BindingResource<'a>> {
    vec![
        inputs.frame.as_entire_binding(),
        geometry.surfaces.as_entire_binding(),
        trim.levels.as_entire_binding(),
        geometry.faces.as_entire_binding(),
        geometry.nodes.as_entire_binding(),
        geometry.floats.as_entire_binding(),
        geometry.piece_offsets.as_entire_binding(),
        geometry.lists.as_entire_binding(),
        geometry.bspline.as_entire_binding(),
        grid.as_entire_binding(),
    ]
}
