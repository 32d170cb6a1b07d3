//! Helpers shared by the renderer's GPU tests: fixtures, the device, golden images.

#![allow(dead_code)] // each test binary uses its own subset

use std::path::{Path, PathBuf};

use cadre_mesh::{MeshParams, mesh_model};
use cadre_render::compare::compare;
use cadre_render::{Camera, FrameOptions, Gpu, RenderError, RenderScene, Renderer, ViewState};
use image::RgbaImage;

/// A pixel differs when a channel is more than this far off.
pub const TOLERANCE: u8 = 24;
/// At most this fraction of pixels may differ (edges of shapes move by a pixel between
/// drivers).
pub const MAX_DIFFERING: f64 = 0.01;

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The machine's adapter (a GPU, or Mesa's lavapipe in CI).
pub fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| {
        panic!("{e}\nthe renderer tests need a GPU or Mesa's software Vulkan (lavapipe)")
    })
}

/// A fixture: the bundled example, or a test model under `tests/data`.
pub fn fixture(name: &str) -> PathBuf {
    let example = root().join("examples").join(name);
    if example.is_file() {
        example
    } else {
        root().join("crates/cadre-render/tests/data").join(name)
    }
}

/// The fixture's model and its tessellated scene (0.01 mm, 0.3 rad).
pub fn model_and_scene(name: &str) -> (cadre_brep::Model, RenderScene) {
    model_and_scene_at(name, 0.01)
}

/// The fixture's model and its scene tessellated to `deflection` (mm; 0.3 rad).
pub fn model_and_scene_at(name: &str, deflection: f64) -> (cadre_brep::Model, RenderScene) {
    let bytes = std::fs::read(fixture(name)).expect("fixture reads");
    model_and_scene_of(bytes, deflection)
}

/// The model of a STEP file's `bytes` and its scene tessellated to `deflection`.
pub fn model_and_scene_of(bytes: Vec<u8>, deflection: f64) -> (cadre_brep::Model, RenderScene) {
    let file = cadre_step::syntax::StepFile::parse(bytes).expect("the file parses");
    let model = cadre_step::map_file(&file);
    let params = MeshParams {
        deflection,
        angle: 0.3,
        ..MeshParams::default()
    };
    let mesh = mesh_model(&model, &params, None);
    let scene = RenderScene::from_model(&model, &mesh);
    (model, scene)
}

/// The fixture's text with every entity id `#n` of its DATA section moved to `#(n + offset)`
/// (ids past 2³² with `offset` ≥ 2³²).
pub fn renumbered(name: &str, offset: u64) -> Vec<u8> {
    let text = std::fs::read_to_string(fixture(name)).expect("fixture reads");
    cadre_step::syntax::shift_entity_ids(&text, offset)
        .expect("ids shift")
        .into_bytes()
}

/// The fixture's tessellated scene.
pub fn scene(name: &str) -> RenderScene {
    model_and_scene(name).1
}

/// Compares `image` with the golden image `name` in `tests/golden` (or, with
/// `CADRE_BLESS=1`, writes it); a failure leaves the actual and diff images in `target/golden`.
pub fn check_golden(name: &str, image: &RgbaImage) {
    let reference = root().join("crates/cadre-render/tests/golden").join(name);
    if std::env::var_os("CADRE_BLESS").is_some() {
        image.save(&reference).expect("write reference");
        return;
    }
    let expected = image::open(&reference)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e} (render it with CADRE_BLESS=1 and review it before committing)",
                reference.display()
            )
        })
        .to_rgba8();
    let c = compare(image, &expected, TOLERANCE);
    if !c.passes(MAX_DIFFERING) {
        let out = root().join("target/golden");
        std::fs::create_dir_all(&out).expect("target/golden");
        image
            .save(out.join(format!("actual-{name}")))
            .expect("write actual");
        c.diff
            .save(out.join(format!("diff-{name}")))
            .expect("write diff");
        panic!(
            "{name}: {:.2} % of pixels differ (max channel delta {}); actual and diff in {}",
            100.0 * c.differing,
            c.max_delta,
            out.display()
        );
    }
}

/// Options of a `width` × `height` frame, shaded with edges, without supersampling: what the
/// id and viewer tests draw.
pub fn shaded_edges(width: u32, height: u32) -> cadre_render::FrameOptions {
    cadre_render::FrameOptions {
        width,
        height,
        supersample: 1,
        mode: cadre_render::DisplayMode::ShadedEdges,
        ..cadre_render::FrameOptions::default()
    }
}

/// One-shot frames of an unprepared scene in the default view state: each prepares the scene
/// and reads one frame (what the tests that draw a scene once want).
pub trait OneShot {
    /// The image of `scene`.
    fn image_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<RgbaImage, RenderError>;

    /// The visibility buffer's ids of `scene`.
    fn ids_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<Vec<[u32; 4]>, RenderError>;

    /// The visibility buffer's (u, v) of `scene`.
    fn uv_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<Vec<[f32; 2]>, RenderError>;
}

impl OneShot for Renderer {
    fn image_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<RgbaImage, RenderError> {
        let prepared = self.prepare(gpu, scene);
        self.render(gpu, &prepared, camera, options, &ViewState::default())
    }

    fn ids_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<Vec<[u32; 4]>, RenderError> {
        let prepared = self.prepare(gpu, scene);
        self.render_ids(gpu, &prepared, camera, options, &ViewState::default())
    }

    fn uv_of(
        &self,
        gpu: &Gpu,
        scene: &RenderScene,
        camera: &Camera,
        options: &FrameOptions,
    ) -> Result<Vec<[f32; 2]>, RenderError> {
        let prepared = self.prepare(gpu, scene);
        self.render_uv(gpu, &prepared, camera, options, &ViewState::default())
    }
}

/// A uniform random number in [0, 1) from an xorshift generator seeded with `seed` (the
/// tests' queries: reproducible, no dependency).
pub fn xorshift(mut seed: u64) -> impl FnMut() -> f32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Runs the compute shader `wgsl` (entry point `main`, workgroups of 64) over `invocations`
/// on `gpu`: `inputs` bound as read-only storage at bindings 0, 1, …, and a read-write
/// buffer of `answer_bytes` after them, whose bytes come back.
pub fn run_compute(
    gpu: &Gpu,
    wgsl: &str,
    inputs: &[&[u8]],
    (invocations, answer_bytes): (u32, u64),
) -> Vec<u8> {
    use cadre_render::wgpu;
    use wgpu::util::DeviceExt;
    let device = &gpu.device;
    let buffers: Vec<wgpu::Buffer> = inputs
        .iter()
        .map(|bytes| {
            // Storage bindings may not be empty.
            let bytes = if bytes.is_empty() {
                &[0u8; 4][..]
            } else {
                bytes
            };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("input"),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        })
        .collect();
    let answers = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("answers"),
        size: answer_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: answer_bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("test compute"),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("test compute"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .chain([&answers])
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("test compute"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(invocations.div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&answers, 0, &readback, 0, answer_bytes);
    gpu.queue.submit([encoder.finish()]);
    readback
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    let view = readback.slice(..).get_mapped_range().expect("mapped");
    view.to_vec()
}
