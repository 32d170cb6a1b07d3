//! Device setup: a wgpu device and queue on whatever adapter the machine has.

use crate::RenderError;

/// A wgpu device and queue, and what adapter they run on.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's description (name, backend, whether it is a software renderer).
    pub info: wgpu::AdapterInfo,
    /// Whether a depth target can be read as a texture in a pass that depth-tests against it
    /// (read-only attachment; `DownlevelFlags::READ_ONLY_DEPTH_STENCIL`, which GL lacks): the
    /// shade pass then tests the visibility depth to skip the background.
    pub read_only_depth: bool,
    /// Whether the adapter runs compute shaders with storage buffers
    /// (`DownlevelFlags::COMPUTE_SHADERS`): the B-Rep edges of the visible-edges mode are
    /// then rasterized in compute ([`crate::passes`]' edges raster), else drawn as quads.
    pub compute: bool,
    /// Whether fragment shaders may write storage buffers
    /// (`DownlevelFlags::FRAGMENT_WRITABLE_STORAGE`): the crack pass needs it.
    pub fragment_storage: bool,
}

impl Gpu {
    /// A device for offscreen rendering: the high-performance adapter of the backends named
    /// by `WGPU_BACKEND` when set, else of Vulkan/Metal/DX12 and, failing those, GL. On a
    /// machine without a GPU that is Mesa's lavapipe (Vulkan) or llvmpipe (GL through EGL,
    /// no X server needed).
    pub fn headless() -> Result<Gpu, RenderError> {
        let from_env = std::env::var_os("WGPU_BACKEND").is_some();
        // GL is asked last: probing it prints EGL noise where Vulkan would do.
        let tries: &[wgpu::Backends] = if from_env {
            &[wgpu::Backends::all()]
        } else {
            &[wgpu::Backends::PRIMARY, wgpu::Backends::GL]
        };
        Gpu::first_of(tries, !from_env)
    }

    /// A device on the high-performance adapter of `backends` only (e.g.
    /// `wgpu::Backends::GL` for llvmpipe through EGL).
    pub fn headless_on(backends: wgpu::Backends) -> Result<Gpu, RenderError> {
        Gpu::first_of(&[backends], true)
    }

    /// The first adapter found trying each set of backends in turn (`force`: the sets replace
    /// what `WGPU_BACKEND` would choose).
    fn first_of(tries: &[wgpu::Backends], force: bool) -> Result<Gpu, RenderError> {
        let mut last: Option<Box<dyn std::error::Error + Send + Sync>> = None;
        let mut found = None;
        for &backends in tries {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            if force {
                desc.backends = backends;
            }
            // No indirect draws here, so no indirect-call validation: its compute pipeline
            // fails on NVIDIA's GL driver through EGL ("the selected version doesn't support
            // COMPUTE_SHADER"), losing the device (seen on an H100, 2026-11-26).
            desc.flags
                .remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
            let instance = wgpu::Instance::new(desc);
            match pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            })) {
                // An adapter that cannot run the passes: try the next set of backends.
                Ok(a) => match Gpu::from_adapter(&a) {
                    Ok(gpu) => {
                        found = Some(gpu);
                        break;
                    }
                    Err(e) => last = Some(Box::new(e)),
                },
                Err(e) => last = Some(Box::new(e)),
            }
        }
        found.ok_or(RenderError::NoAdapter(last))
    }

    /// A device on `adapter`: what a window's viewer calls with the adapter it requested as
    /// compatible with its surface (`wgpu::RequestAdapterOptions::compatible_surface`), then
    /// renders with [`crate::Renderer::for_format`] into the surface's textures.
    pub fn from_adapter(adapter: &wgpu::Adapter) -> Result<Gpu, RenderError> {
        let info = adapter.get_info();
        tracing::info!(adapter = %info.name, backend = ?info.backend, "GPU adapter");
        // Edges, picking and draw records are read from storage buffers in vertex shaders:
        // GL contexts below GL 4.3 / GLES 3.1 (NVIDIA's EGL path gave one) cannot, and would
        // fail at pipeline creation.
        if !adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::VERTEX_STORAGE)
        {
            return Err(RenderError::NoVertexStorage {
                adapter: info.name.clone(),
                backend: info.backend,
            });
        }
        let downlevel = adapter.get_downlevel_capabilities().flags;
        let read_only_depth = downlevel.contains(wgpu::DownlevelFlags::READ_ONLY_DEPTH_STENCIL);
        // The edges' compute rasterizer binds five storage buffers (segments, selection,
        // coverage, records, locals): one more than the downlevel default; the trim
        // back-end's tessellation fourteen (`passes::visibility::trim::STORAGE_BUFFERS`;
        // lavapipe allows 32).
        let storage_buffers = adapter
            .limits()
            .max_storage_buffers_per_shader_stage
            .min(16);
        let compute =
            downlevel.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) && storage_buffers >= 5;
        let mut required_limits =
            wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits());
        required_limits.max_storage_buffers_per_shader_stage = required_limits
            .max_storage_buffers_per_shader_stage
            .max(storage_buffers);
        // Timestamps between a frame's stages, for the benchmarks' per-pass timings
        // (`Renderer::with_pass_timings`), where the adapter has them.
        let timestamps =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        // The exact crack fill's fragment shader tests its depth mask before it runs
        // (`@early_depth_test(force)`), where the adapter allows it (Vulkan, GLES 3.1+).
        let required_features =
            adapter.features() & (timestamps | wgpu::Features::SHADER_EARLY_DEPTH_TEST);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("cadre"),
            required_features,
            required_limits,
            ..Default::default()
        }))
        .map_err(RenderError::Device)?;
        // The flag is not enough on GL: NVIDIA's EGL context (H200, driver 580, 2026-12-04)
        // reports it, yet the GLSL version wgpu selects has no storage buffers and every
        // pipeline fails. A probe pipeline tells.
        if info.backend == wgpu::Backend::Gl && !compiles_vertex_storage(&device) {
            return Err(RenderError::NoVertexStorage {
                adapter: info.name.clone(),
                backend: info.backend,
            });
        }
        Ok(Gpu {
            device,
            queue,
            info,
            read_only_depth,
            compute,
            fragment_storage: downlevel.contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE),
        })
    }

    /// Whether the adapter is a CPU rasterizer (Mesa's lavapipe or llvmpipe, WARP): there
    /// every pass costs per pixel in CPU time, so images are anti-aliased by smoothing a 1×
    /// image rather than by supersampling it.
    pub fn is_cpu(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// Largest texture side the device allows.
    pub fn max_side(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }
}

/// Whether `device` builds a render pipeline whose vertex shader reads a storage buffer.
fn compiles_vertex_storage(device: &wgpu::Device) -> bool {
    // NVIDIA's GL reports the failure as an internal error (the shader's translation), not a
    // validation one (H200, 2026-12-04): both are caught, or the uncaught one panics.
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("vertex storage probe"),
        source: wgpu::ShaderSource::Wgsl(
            "@group(0) @binding(0) var<storage, read> corners: array<vec4<f32>>;
             @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
                 return corners[i];
             }
             @fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }"
                .into(),
        ),
    });
    let group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("vertex storage probe"),
        entries: &[crate::passes::common::buffer_entry(
            0,
            crate::passes::common::STORAGE,
            wgpu::ShaderStages::VERTEX,
        )],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("vertex storage probe"),
        bind_group_layouts: &[Some(&group)],
        immediate_size: 0,
    });
    let _pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("vertex storage probe"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::TextureFormat::Rgba8Unorm.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let internal = pollster::block_on(internal.pop());
    let validation = pollster::block_on(validation.pop());
    internal.is_none() && validation.is_none()
}
