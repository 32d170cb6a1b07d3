//! GPU struct layouts, one source for Rust and WGSL: each struct here has a twin in
//! `passes/common.wgsl` ([`GpuStruct::WGSL_NAME`]), and `tests/shaders.rs` checks every
//! member's name and offset, in order, and the struct's size against what naga computes for
//! that twin in every pass, so two fields swapped on either side fail the build's tests.

use bytemuck::{Pod, Zeroable};

/// What one binding of a pass's bind group 0 holds, as the Rust side lays it out and binds
/// it (the binding number is its index in the pass's list). Each pass's layout entries are
/// made from its list, and `tests/shaders.rs` checks the list against the pass's WGSL.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binding {
    /// A uniform buffer holding one struct (its WGSL name).
    Uniform(&'static str),
    /// A read-only storage buffer: an array of this element (a struct's WGSL name, or a WGSL
    /// vector type such as `vec4<u32>`).
    Storage(&'static str),
    /// A 2D `f32` texture read with `textureLoad` (not filterable).
    FloatTexture,
    /// A 2D `u32` texture read with `textureLoad`.
    UintTexture,
    /// A 2D `f32` texture read through a filtering sampler (naga sees a [`Binding::FloatTexture`]).
    FilteredTexture,
    /// A filtering sampler.
    Sampler,
    /// A read-write storage buffer of `atomic<u32>` (the edges' coverage, summed by the
    /// compute rasterizer).
    AtomicStorage,
    /// A read-write storage buffer: an array of this element (what a compute pass writes
    /// for a later pass, such as the trim back-end's indirect draws).
    StorageWrite(&'static str),
}

/// A shader the renderer compiles: its name, its whole WGSL as compiled, and its bind group.
#[derive(Clone, Debug)]
pub struct PassShader {
    /// The pass or back-end (`visibility/mesh`, `shade`, ...).
    pub name: &'static str,
    /// The WGSL exactly as the pipeline compiles it.
    pub source: String,
    /// Its bind group 0, binding `i` at index `i`.
    pub bindings: &'static [Binding],
    /// Whether it draws the scene's instances, binding [`INSTANCE_BINDINGS`] as group 1.
    pub instanced: bool,
}

/// Every shader of the renderer, with what the Rust side binds to it (for the layout tests).
pub fn pass_shaders() -> Vec<PassShader> {
    use crate::passes::{backdrop, cracks, edges, lines, pick, shade, text, visibility};
    let shader = |name, source, bindings, instanced| PassShader {
        name,
        source,
        bindings,
        instanced,
    };
    vec![
        shader(
            "visibility/mesh",
            visibility::mesh::source(),
            visibility::mesh::BINDINGS,
            true,
        ),
        shader(
            "visibility/analytic",
            visibility::analytic::source(),
            visibility::analytic::BINDINGS,
            false,
        ),
        shader(
            "visibility/trim",
            visibility::trim::source(),
            visibility::trim::BINDINGS,
            true,
        ),
        shader(
            "visibility/trim tessellation",
            visibility::trim::tessellate_source(),
            visibility::trim::TESSELLATE_BINDINGS,
            true,
        ),
        shader(
            "visibility/trim crack fill",
            visibility::trim::crack_source(),
            visibility::trim::CRACK_BINDINGS,
            true,
        ),
        shader(
            "visibility/trim crack fill faces",
            visibility::trim::crack_faces_source(),
            visibility::trim::CRACK_FACES_BINDINGS,
            true,
        ),
        shader(
            "cracks detection",
            cracks::detect_source(),
            cracks::DETECT_BINDINGS,
            false,
        ),
        shader(
            "cracks resolve",
            cracks::resolve_source(),
            cracks::RESOLVE_BINDINGS,
            false,
        ),
        shader("shade", shade::source(), shade::BINDINGS, false),
        shader("edges", edges::source(), edges::BINDINGS, true),
        shader(
            "edges raster",
            edges::raster::source(),
            edges::raster::BINDINGS,
            true,
        ),
        shader(
            "edges composite",
            edges::raster::composite_source(),
            edges::raster::COMPOSITE_BINDINGS,
            false,
        ),
        shader(
            "visibility/mesh see-through",
            visibility::mesh::see_through_source(),
            visibility::mesh::SEE_THROUGH_BINDINGS,
            true,
        ),
        shader("pick", pick::source(), pick::BINDINGS, true),
        shader(
            "lines scan",
            lines::scan_source(),
            lines::SCAN_BINDINGS,
            false,
        ),
        shader("lines", lines::draw_source(), lines::DRAW_BINDINGS, false),
        shader("backdrop", backdrop::source(), backdrop::BINDINGS, false),
        shader("text", text::source(), text::BINDINGS, false),
    ]
}

/// One member of a GPU struct: its name and byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Member {
    /// Field name, as written in Rust and in WGSL.
    pub name: &'static str,
    /// Byte offset from the start of the struct.
    pub offset: usize,
}

/// A struct shared with the shaders: its WGSL name and its members in declaration order.
pub trait GpuStruct: Pod {
    /// The name of its twin in `passes/common.wgsl`.
    const WGSL_NAME: &'static str;
    /// Every field, in declaration order.
    fn members() -> Vec<Member>;
}

/// Implements [`GpuStruct`] for a struct from the list of all its fields (a field left out
/// or misnamed fails `offset_of!` or the member count the layout test compares).
macro_rules! gpu_struct {
    ($t:ty, $wgsl:literal, [$($field:ident),+ $(,)?]) => {
        impl GpuStruct for $t {
            const WGSL_NAME: &'static str = $wgsl;
            fn members() -> Vec<Member> {
                vec![$(Member {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($t, $field),
                }),+]
            }
        }
    };
}

/// One mesh vertex: position and unit normal (mesh-local), and the id of its B-Rep face.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Vertex {
    /// Position, model units, mesh-local.
    pub position: [f32; 3],
    /// Unit normal, mesh-local.
    pub normal: [f32; 3],
    /// Face id (the scene's dense model id, 0 = none).
    pub face_id: u32,
    /// Parameters on the face's exact surface (0, 0 for meshes from the file).
    pub uv: [f32; 2],
}

/// Per-frame constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct FrameUniform {
    /// Projection × rotation-only view (positions are camera-relative).
    pub view_proj: [[f32; 4]; 4],
    /// Inverse projection, to rebuild view-space positions from depth.
    pub inv_proj: [[f32; 4]; 4],
    /// Background colour, linear RGBA.
    pub background: [f32; 4],
    /// Target width and height, edge width and hidden-edge dash length, all in target pixels.
    pub viewport: [f32; 4],
    /// Relative depth tolerances: an edge behind the scene's depth by less is visible; a
    /// depth jump past the second makes a silhouette outline; then the crack pass's d_min
    /// and gap tolerance, world units (`passes::cracks::tolerances`).
    pub tolerances: [f32; 4],
    /// Projection ([`PROJECTION_PERSPECTIVE`], [`PROJECTION_ORTHOGRAPHIC`]), face fill
    /// ([`FILL_SHADED`], [`FILL_BACKGROUND`], [`FILL_NONE`]), edge mode ([`EDGES_VISIBLE`],
    /// [`EDGES_ALL`], [`EDGES_HIDDEN_DASHED`]), silhouette outlines (0 off, 1 on).
    pub modes: [u32; 4],
    /// Visible edge colour, linear RGBA.
    pub edge_colour: [f32; 4],
    /// Hidden edge colour, linear RGBA.
    pub hidden_colour: [f32; 4],
    /// World up in view space (the environment's zenith); w 1 where tessellated surfaces
    /// keep their raw interpolated normals across silhouettes and the trim back-end the
    /// faces of closed solids seen from inside (the tests' negative control,
    /// `Renderer::with_raw_silhouettes`), else 0.
    pub sky_up: [f32; 4],
    /// Number of lights, number of selected items, number of section planes (at most 3),
    /// whether trimmed edges carry their coverage (1) or not (0).
    pub counts: [u32; 4],
    /// What the cursor is over: kind (0 nothing, 1 face, 2 edge, 3 vertex, 4 part),
    /// instance + 1, model id, unused.
    pub hover: [u32; 4],
    /// Tint of hovered items, linear RGB and strength.
    pub hover_colour: [f32; 4],
    /// Tint of selected items, linear RGB and strength.
    pub selection_colour: [f32; 4],
    /// Section planes relative to the eye: unit world normal (xyz) and offset (w), keeping
    /// the camera-relative points `p` with `normal · p <= w` (the first `counts.z` are set).
    pub planes: [[f32; 4]; 3],
    /// The section planes' unit normals in view space (xyz; w unused), to shade caps.
    pub plane_normals: [[f32; 4]; 3],
    /// The camera's forward direction in world space (xyz; w: 1 when the crack pass's
    /// silhouette rule is on, `CrackOptions::silhouettes`): the view ray of every
    /// pixel when orthographic.
    pub forward: [f32; 4],
    /// Section caps: hatch spacing and hatch line width, outline width (target pixels),
    /// unused.
    pub section: [f32; 4],
    /// The key light's shadow map: view space → the light's clip space (column-major).
    pub shadow: [[f32; 4]; 4],
    /// The shadow map's world size of a texel per unit of the light's clip w (x), unused (y),
    /// the key light's share that shadows remove (z), its size in texels (w; 0: no shadows).
    pub shadow_params: [f32; 4],
}

/// [`FrameUniform::modes`]`[0]`: perspective projection.
pub const PROJECTION_PERSPECTIVE: u32 = 0;
/// [`FrameUniform::modes`]`[0]`: orthographic projection (every view ray is the camera's forward).
pub const PROJECTION_ORTHOGRAPHIC: u32 = 1;
/// [`FrameUniform::modes`]`[1]`: faces shaded.
pub const FILL_SHADED: u32 = 0;
/// [`FrameUniform::modes`]`[1]`: faces filled with the background colour (hidden-line drawings).
pub const FILL_BACKGROUND: u32 = 1;
/// [`FrameUniform::modes`]`[1]`: faces not filled (wireframe, x-ray).
pub const FILL_NONE: u32 = 2;
/// [`FrameUniform::modes`]`[2]`: only visible edges.
pub const EDGES_VISIBLE: u32 = 0;
/// [`FrameUniform::modes`]`[2]`: all edges, solid.
pub const EDGES_ALL: u32 = 1;
/// [`FrameUniform::modes`]`[2]`: visible edges solid, hidden ones dashed.
pub const EDGES_HIDDEN_DASHED: u32 = 2;

/// A light in view space, as the shade pass reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LightGpu {
    /// Position relative to the eye (xyz); kind (w: 0 directional, 1 point, 2 spot).
    pub position: [f32; 4],
    /// Towards the light (directional) or the spot's axis (xyz); range (w, 0 = none).
    pub direction: [f32; 4],
    /// Radiance or intensity (rgb); cosine of the spot's outer half-angle (w).
    pub colour: [f32; 4],
    /// Cosine of the spot's inner half-angle (x), unused.
    pub params: [f32; 4],
}

/// Lights a frame is lit by, at most (more are left out, with a warning).
pub const MAX_LIGHTS: usize = 8;

/// The frame's lights as the shade pass reads them: a uniform block, the first
/// `FrameUniform::counts[0]` of them lit. Uniform, not a storage array: the index is the
/// same for every pixel, which lavapipe then loads once for all lanes where a storage
/// array's element was fetched lane by lane (pr2db at 1280×960, `cadre bench view`, the
/// three-light CAD rig: 18.0–18.7 → 16 ms a frame with the lights as constants;
/// BENCHMARKS.md, issue 15).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LightRig {
    /// The lights; those past the frame's count are zero.
    pub lights: [LightGpu; MAX_LIGHTS],
}

/// A segment of a B-Rep edge or wire, or a B-Rep vertex (both ends equal), mesh-local.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Segment {
    /// First end (xyz); model id of its edge or vertex as `u32` bits (w, 0 for none).
    pub a: [f32; 4],
    /// Second end (xyz); kind as `u32` bits (w: 0 wire line, 1 edge, 2 vertex).
    pub b: [f32; 4],
    /// The outward unit normals of the two triangles of a closed solid's mesh along this
    /// segment, mesh-local, each packed as WGSL's `pack4x8snorm` (xyz); 0 where the segment
    /// does not lie between exactly two triangles of a closed solid. The edges pass drops
    /// the segments whose both faces turn away from the eye (hidden behind their own solid).
    pub faces: [u32; 2],
    /// Its place in its polyline (0 for the first piece of an edge or a wire: the pieces
    /// before it, which the hidden-line dashes count their arc length along), and padding
    /// to the WGSL struct's 16-byte alignment.
    pub pad: [u32; 2],
}

/// One draw: a primitive of a mesh placed by one instance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Draw {
    /// Mesh-local → camera-relative world (column-major).
    pub model: [[f32; 4]; 4],
    /// Mesh-local normals → view space (columns, xyz used).
    pub normal: [[f32; 4]; 3],
    /// Index into the material buffer.
    pub material: u32,
    /// Instance number (scene instance order).
    pub instance: u32,
    /// Flags: [`DRAW_CLOSED`], [`DRAW_INSIDE_OUT`].
    pub flags: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad: u32,
}

/// The first shader location of [`DRAW_ATTRIBUTES`] (the mesh's own vertex attributes take
/// 0–3).
pub const DRAW_FIRST_LOCATION: u32 = 8;

/// A [`Draw`] read as instance-step vertex attributes, for the calls whose instances are their
/// own records (nothing to compose: the identity local list): the model's four columns, the
/// normal matrix's three, then `material`, `instance`, `flags` (and the padding) as one
/// `vec4<u32>`, at locations [`DRAW_FIRST_LOCATION`] on. The WGSL twin is `DrawAttributes`
/// (`passes/instances.wgsl`); `tests/shaders.rs` checks each location's type and that the
/// offsets are the struct's.
pub const DRAW_ATTRIBUTES: [wgpu::VertexAttribute; 8] = {
    const M: u64 = std::mem::offset_of!(Draw, model) as u64;
    const N: u64 = std::mem::offset_of!(Draw, normal) as u64;
    const IDS: u64 = std::mem::offset_of!(Draw, material) as u64;
    const L: u32 = DRAW_FIRST_LOCATION;
    const fn column(offset: u64, location: u32) -> wgpu::VertexAttribute {
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x4,
            offset,
            shader_location: location,
        }
    }
    [
        column(M, L),
        column(M + 16, L + 1),
        column(M + 32, L + 2),
        column(M + 48, L + 3),
        column(N, L + 4),
        column(N + 16, L + 5),
        column(N + 32, L + 6),
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Uint32x4,
            offset: IDS,
            shader_location: L + 7,
        },
    ]
};

/// [`Draw::flags`] flag: the mesh is a closed, consistently oriented solid, so seeing one
/// of its faces from inside means looking through a section into the material (a cap).
pub const DRAW_CLOSED: u32 = 1;
/// [`Draw::flags`] flag: the draw's triangles wind clockwise seen from outside (the mesh
/// encloses a negative volume, or the instance's placement mirrors, but not both).
pub const DRAW_INSIDE_OUT: u32 = 2;

/// A placement below a draw record: instances of a shared sub-assembly drawn by one record
/// (10⁶ placed cubes of six levels of ten uses are 10³ records × 10³ locals, not 10⁶ records). A record's
/// instance `j` is placed by `record.model × local.model`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Local {
    /// Mesh-local → the record's frame (column-major).
    pub model: [[f32; 4]; 4],
    /// Mesh-local normals → the record's frame (columns, xyz used; the inverse transpose).
    pub normal: [[f32; 4]; 3],
    /// Scene instance number of this placement minus the record's [`Draw::instance`].
    pub offset: u32,
    /// Flags toggled on the record's: [`DRAW_INSIDE_OUT`] when this placement mirrors.
    pub flags: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad: [u32; 2],
}

impl Local {
    /// Its placement as an `f64` affine map.
    pub fn affine(&self) -> glam::DAffine3 {
        glam::DAffine3::from_mat4(glam::Mat4::from_cols_array_2d(&self.model).as_dmat4())
    }

    /// The placement that changes nothing (records drawn once each).
    pub const IDENTITY: Local = Local {
        model: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        normal: [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
        offset: 0,
        flags: 0,
        pad: [0; 2],
    };
}

/// One draw call's instances, read through a dynamic uniform offset: instance `i` of the call
/// is local `locals_first + i % locals_count` of record `record + i / locals_count`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Call {
    /// First draw record of the call.
    pub record: u32,
    /// First local placement shared by the call's records.
    pub locals_first: u32,
    /// Local placements per record (at least 1).
    pub locals_count: u32,
    /// Instances the call draws.
    pub instances: u32,
    /// What the call draws besides its instances: a segment call's segments (first, count)
    /// in the segment buffer, each drawn once per instance (what the edges' compute
    /// rasterizer dispatches over); a trim call's first surface and first tessellation task
    /// ([`TrimTask`]); 0 for a mesh call.
    pub range: [u32; 2],
    /// Padding to the WGSL struct's 16-byte alignment.
    pub pad: [u32; 2],
}

/// One face drawn by the trim back-end (`passes/visibility/trim`): its support surface in
/// closed form (`crate::trim_surfaces`), the (u, v) box its trim tree covers (the domain
/// tessellated), and what the tessellation's error and culling need.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TrimSurface {
    /// The surface frame's origin (mesh-local) and the kind's first number (radius, or the
    /// torus' major radius).
    pub origin: [f32; 4],
    /// The frame's x axis and the kind's second number (the cone's tan α, the torus' minor
    /// radius).
    pub axis_x: [f32; 4],
    /// The frame's y axis and the sign that turns the surface's normal S_u × S_v into the
    /// face's outward one (±1).
    pub axis_y: [f32; 4],
    /// The frame's z axis and the least bound the tessellation keeps in depth (model units,
    /// `TrimScene::depth_tolerance`).
    pub axis_z: [f32; 4],
    /// The trim tree's box: lower corner (u₀, v₀) and size.
    pub uv: [f32; 4],
    /// Bounding sphere of the face, mesh-local: centre and radius.
    pub sphere: [f32; 4],
    /// Bounds of |S_uu|, |S_uv|, |S_vv| over the box (model units), and the offset of the
    /// face's grid breakpoints (`trim_surfaces::TrimFaceSurface::breaks`, as `u32` bits).
    pub curvature: [f32; 4],
    /// Kind (`trim_surfaces::SURFACE_*`), face id (dense), the tree's index, unused.
    pub ids: [u32; 4],
}

/// One tessellation task of a frame: a trimmed face of one mesh call, whose tessellation the
/// trim back-end's compute pass chooses from the nearest of the call's instances (its error
/// at most the tolerance in pixels there) and writes as an indirect draw.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TrimTask {
    /// The face's [`TrimSurface`].
    pub surface: u32,
    /// The call's first draw record.
    pub record: u32,
    /// The call's local placements: first and count per record.
    pub locals_first: u32,
    /// Local placements per record (at least 1).
    pub locals_count: u32,
    /// Instances the call draws.
    pub instances: u32,
    /// The face's place in its draw (its vertices start at `slot × TRIM_VERTICES`).
    pub slot: u32,
    /// Nearest distance from the eye to the call's instances (camera-relative bounding
    /// spheres), for calls with more instances than the pass walks one by one.
    pub near: f32,
    /// Padding to the WGSL struct's alignment.
    pub pad: u32,
}

/// One trim draw of a frame (a mesh call's trimmed faces) as the exact crack fill's seeded
/// solves read it from storage (`crack.wgsl`'s `cs_seed_match`, a workgroup row a draw):
/// the call's data, which a uniform would give — but lavapipe compiles a shader again for
/// each binding of the uniforms its loops test (`shaders.rs`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TrimCall {
    /// The draw's first [`TrimSurface`]; its records are in ascending face id.
    pub first_surface: u32,
    /// Its faces (records from `first_surface`).
    pub faces: u32,
    /// The call's first draw record.
    pub record: u32,
    /// The call's first local placement.
    pub locals_first: u32,
    /// Local placements per record (at least 1).
    pub locals_count: u32,
    /// Instances the call draws.
    pub instances: u32,
    /// Padding to the WGSL struct's alignment.
    pub pad: [u32; 2],
}

/// Bind group 1 of every pass that draws the scene's instances: the call (uniform at a
/// dynamic offset), the draw records, the local placements.
pub const INSTANCE_BINDINGS: &[Binding] = &[
    Binding::Uniform(Call::WGSL_NAME),
    Binding::Storage(Draw::WGSL_NAME),
    Binding::Storage(Local::WGSL_NAME),
];

/// Where the pick pass's small target lies in the frame: the window's top-left pixel, so
/// that its fragments read the visibility buffer's ids at their frame pixel.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct PickRegion {
    /// Column and row of the window's top-left pixel in the frame.
    pub origin: [u32; 2],
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}

/// An analytic primitive placed for one frame, as the analytic back-end ray casts it
/// ([`crate::AnalyticPrimitive`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Primitive {
    /// Shape-local → camera-relative world (column-major).
    pub model: [[f32; 4]; 4],
    /// Camera-relative world → shape-local: the pixel's ray is cast in the shape's frame.
    pub to_local: [[f32; 4]; 4],
    /// Shape-local normals → view space (columns, xyz used).
    pub normal: [[f32; 4]; 3],
    /// Sphere: radius (x); rectangle: half width and half height (x, y); quadric: λ (xyz)
    /// and c (w) of Σ λᵢ zᵢ² + 2 bᵀz + c in its box's frame; unused lanes 0.
    pub size: [f32; 4],
    /// Quadric: b (xyz); 1 (w) when its tangent rays are its silhouettes (0 for two
    /// intersecting planes), which then carry their analytic coverage.
    pub linear: [f32; 4],
    /// The pixel's ray in the shape's frame, affine in its normalised device coordinates
    /// (x, y): origin o₀ + x oₓ + y o_y, direction d₀ + x dₓ + y d_y (xyz of each column, in
    /// that order; see `analytic::pixel_ray`).
    pub ray: [[f32; 4]; 6],
    /// The hit's reverse-Z depth from the ray parameter s: (Z, N, P₂₂, unused), depth =
    /// (N − P₂₂ s) / (Z + s) in perspective, N − P₂₂ s in orthographic projection.
    pub depth: [f32; 4],
    /// Quadric: the screen rectangle holding it, normalised device coordinates (low x, low y,
    /// high x, high y).
    pub screen: [f32; 4],
    /// [`crate::analytic::PRIMITIVE_SPHERE`], [`crate::analytic::PRIMITIVE_RECTANGLE`],
    /// [`crate::analytic::PRIMITIVE_QUADRIC_PATCH`] or
    /// [`crate::analytic::PRIMITIVE_QUADRIC_VOLUME`].
    pub kind: u32,
    /// Face id written into the visibility buffer.
    pub face: u32,
    /// Instance number (after the scene's mesh instances).
    pub instance: u32,
    /// Index into the material buffer.
    pub material: u32,
    /// Quadric: its first cutting plane in the frame's plane buffer, and their count.
    pub planes: [u32; 2],
    /// [`DRAW_CLOSED`] for spheres and quadric volumes (section planes cap them).
    pub flags: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad: u32,
}

/// A metallic-roughness material.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Material {
    /// Linear base colour and alpha.
    pub base_color: [f32; 4],
    /// Metalness, perceptual roughness, unused, unused.
    pub params: [f32; 4],
}

/// One point of a line set (`passes/lines`), set-local `f32` (relative to the set's
/// origin, which each frame's matrix places in `f64`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LinePoint {
    /// Position relative to the set's origin, model units.
    pub position: [f32; 3],
    /// Its polyline's index in the set: a point whose polyline differs from the one before
    /// starts a strip (and restarts the arc length).
    pub polyline: u32,
    /// Model-space distance along the set to this point ([`crate::LineView::up_to`]).
    pub travel: f32,
    /// sRGB colour (RGBA8, R in the low byte) of the segment from this point to the next,
    /// where its style takes colours per segment.
    pub colour: u32,
    /// Padding to 32 bytes.
    pub pad: [u32; 2],
}

/// A line style as the lines pass reads it ([`crate::LineStyle`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LineStyleGpu {
    /// Linear colour and alpha.
    pub colour: [f32; 4],
    /// Linear colour and alpha of the hidden parts.
    pub hidden_colour: [f32; 4],
    /// Width: output pixels, or model units with [`LINE_WORLD_WIDTH`].
    pub width: f32,
    /// Pixels per pattern bit (output pixels).
    pub factor: f32,
    /// Pixels per bit of the hidden parts' pattern.
    pub hidden_factor: f32,
    /// Miter limit in half widths (miter joins).
    pub miter_limit: f32,
    /// The 16-bit stipple pattern, bit 0 first.
    pub pattern: u32,
    /// The hidden parts' pattern.
    pub hidden_pattern: u32,
    /// [`LINE_JOIN_MITER`], [`LINE_JOIN_ROUND`] or [`LINE_JOIN_BEVEL`].
    pub join: u32,
    /// [`LINE_CAP_BUTT`], [`LINE_CAP_SQUARE`] or [`LINE_CAP_ROUND`].
    pub cap: u32,
    /// [`LINE_WORLD_WIDTH`], [`LINE_POINT_COLOURS`], [`LINE_HIDDEN_SHOWN`],
    /// [`LINE_HIDDEN_STYLED`].
    pub flags: u32,
    /// Padding to 80 bytes.
    pub pad: [u32; 3],
}

/// A line set's per-frame constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LineFrame {
    /// Set-local → clip space (the set's origin placed relative to the eye in `f64`).
    pub to_clip: [[f32; 4]; 4],
    /// Target width and height (pixels), target pixels per output pixel, depth tolerance.
    pub viewport: [f32; 4],
    /// The clip box's low corner, set-local; `w` = 1 when there is a box.
    pub clip_lo: [f32; 4],
    /// The clip box's high corner, set-local.
    pub clip_hi: [f32; 4],
    /// The travel shown up to ([`crate::LineView::up_to`]; +∞: all), the projection's
    /// vertical scale in pixels (`proj[1][1] × height / 2`: pixels per model unit at w = 1),
    /// unused, unused.
    pub limits: [f32; 4],
    /// Points, scan blocks, unused, unused.
    pub counts: [u32; 4],
}

/// The backdrop pass's per-frame constants ([`crate::Background`], [`crate::GroundGrid`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct BackdropUniform {
    /// Device coordinates → camera-relative world positions.
    pub inv_view_proj: [[f32; 4]; 4],
    /// The gradient's top colour, linear.
    pub top: [f32; 4],
    /// The gradient's bottom colour, linear.
    pub bottom: [f32; 4],
    /// The grid's colour (linear) and opacity.
    pub grid_colour: [f32; 4],
    /// The ground plane, camera-relative: unit normal and offset (n · p = w).
    pub plane: [f32; 4],
    /// What the grid's coordinates are offset by: camera-relative → relative to the grid's
    /// origin (a multiple of every spacing near the eye).
    pub origin: [f32; 4],
    /// The world origin relative to the grid's origin (where the axes cross).
    pub axes: [f32; 4],
    /// A fixed spacing (0: adaptive), the far plane's distance, unused, axes drawn (1) or
    /// not (0).
    pub params: [f32; 4],
    /// Background kind (0 solid, 1 gradient, 2 image), grid on (1) or off, unused, unused.
    pub modes: [u32; 4],
}

/// One quad of the text pass: a glyph, or the box behind a label ([`crate::text`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TextGlyph {
    /// The quad around the label's anchor, em, y up: left, bottom, right, top.
    pub plane: [f32; 4],
    /// Its atlas texels: left, top, right, bottom (a box, a leader: unused).
    pub texels: [f32; 4],
    /// Index of its label.
    pub label: u32,
    /// [`TEXT_QUAD_GLYPH`] or [`TEXT_QUAD_BOX`].
    pub kind: u32,
    /// Padding to 48 bytes.
    pub pad: [u32; 2],
}

/// A label as the text pass reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TextLabel {
    /// Anchor: set-local position (billboard, plane), or output pixels (screen, `xy`).
    pub origin: [f32; 4],
    /// Plane labels: the reading direction × model units per em; others unused.
    pub x_axis: [f32; 4],
    /// Plane labels: the up direction × model units per em; others unused.
    pub y_axis: [f32; 4],
    /// Linear text colour and alpha.
    pub colour: [f32; 4],
    /// Linear box colour and alpha.
    pub background: [f32; 4],
    /// Output pixels per em (screen, billboard), screen offset x, y (pixels, y down), unused.
    pub params: [f32; 4],
    /// Leader start: set-local position, `w` 1 when the label has a leader.
    pub leader: [f32; 4],
    /// Anchor kind (`TEXT_ANCHOR_*`), depth tested (1) or on top (0), unused, unused.
    pub flags: [u32; 4],
}

/// The text pass's per-frame constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TextFrame {
    /// Set-local → clip space (the labels' origin placed relative to the eye in `f64`).
    pub to_clip: [[f32; 4]; 4],
    /// Target width and height (pixels), target pixels per output pixel, unused.
    pub viewport: [f32; 4],
    /// Atlas width and height (texels), distance range (texels), unused.
    pub atlas: [f32; 4],
}

/// [`TextGlyph::kind`]: a glyph from the atlas.
pub const TEXT_QUAD_GLYPH: u32 = 0;
/// [`TextGlyph::kind`]: a label's box.
pub const TEXT_QUAD_BOX: u32 = 1;
/// [`TextGlyph::kind`]: a label's leader line.
pub const TEXT_QUAD_LEADER: u32 = 2;
/// [`TextGlyph::kind`]: a filled triangle (its "label" holds a corner and the two edges
/// from it, as an in-plane label's origin and axes).
pub const TEXT_QUAD_FILL: u32 = 3;
/// [`TextLabel::flags`]`[0]`: fixed to the screen.
pub const TEXT_ANCHOR_SCREEN: u32 = 0;
/// [`TextLabel::flags`]`[0]`: at a scene point, facing the viewer.
pub const TEXT_ANCHOR_BILLBOARD: u32 = 1;
/// [`TextLabel::flags`]`[0]`: in a plane of the scene.
pub const TEXT_ANCHOR_PLANE: u32 = 2;

/// [`LineStyleGpu::join`]: miter.
pub const LINE_JOIN_MITER: u32 = 0;
/// [`LineStyleGpu::join`]: round.
pub const LINE_JOIN_ROUND: u32 = 1;
/// [`LineStyleGpu::join`]: bevel.
pub const LINE_JOIN_BEVEL: u32 = 2;
/// [`LineStyleGpu::cap`]: butt.
pub const LINE_CAP_BUTT: u32 = 0;
/// [`LineStyleGpu::cap`]: square.
pub const LINE_CAP_SQUARE: u32 = 1;
/// [`LineStyleGpu::cap`]: round.
pub const LINE_CAP_ROUND: u32 = 2;
/// [`LineStyleGpu::flags`]: the width is in model units.
pub const LINE_WORLD_WIDTH: u32 = 1;
/// [`LineStyleGpu::flags`]: segments take their points' colours.
pub const LINE_POINT_COLOURS: u32 = 2;
/// [`LineStyleGpu::flags`]: hidden parts drawn as the visible ones.
pub const LINE_HIDDEN_SHOWN: u32 = 4;
/// [`LineStyleGpu::flags`]: hidden parts drawn in the hidden colour and pattern.
pub const LINE_HIDDEN_STYLED: u32 = 8;
/// [`LineStyleGpu::flags`]: drawn whole, whatever the [`crate::LineView`] (not cut).
pub const LINE_WHOLE: u32 = 16;

gpu_struct!(
    FrameUniform,
    "FrameUniform",
    [
        view_proj,
        inv_proj,
        background,
        viewport,
        tolerances,
        modes,
        edge_colour,
        hidden_colour,
        sky_up,
        counts,
        hover,
        hover_colour,
        selection_colour,
        planes,
        plane_normals,
        forward,
        section,
        shadow,
        shadow_params,
    ]
);
gpu_struct!(LightGpu, "Light", [position, direction, colour, params]);
gpu_struct!(TextGlyph, "TextGlyph", [plane, texels, label, kind, pad]);
gpu_struct!(
    TextLabel,
    "TextLabel",
    [
        origin, x_axis, y_axis, colour, background, params, leader, flags
    ]
);
gpu_struct!(TextFrame, "TextFrame", [to_clip, viewport, atlas]);
gpu_struct!(LightRig, "LightRig", [lights]);
gpu_struct!(Segment, "Segment", [a, b, faces, pad]);
gpu_struct!(
    Draw,
    "Draw",
    [model, normal, material, instance, flags, pad]
);
gpu_struct!(Material, "Material", [base_color, params]);
gpu_struct!(Local, "Local", [model, normal, offset, flags, pad]);
gpu_struct!(
    Call,
    "Call",
    [record, locals_first, locals_count, instances, range, pad]
);
gpu_struct!(
    TrimSurface,
    "TrimSurface",
    [origin, axis_x, axis_y, axis_z, uv, sphere, curvature, ids]
);
gpu_struct!(
    TrimTask,
    "TrimTask",
    [
        surface,
        record,
        locals_first,
        locals_count,
        instances,
        slot,
        near,
        pad
    ]
);
gpu_struct!(
    TrimCall,
    "TrimCall",
    [
        first_surface,
        faces,
        record,
        locals_first,
        locals_count,
        instances,
        pad
    ]
);
gpu_struct!(PickRegion, "PickRegion", [origin, pad]);
gpu_struct!(
    LinePoint,
    "LinePoint",
    [position, polyline, travel, colour, pad]
);
gpu_struct!(
    LineStyleGpu,
    "LineStyle",
    [
        colour,
        hidden_colour,
        width,
        factor,
        hidden_factor,
        miter_limit,
        pattern,
        hidden_pattern,
        join,
        cap,
        flags,
        pad
    ]
);
gpu_struct!(
    BackdropUniform,
    "BackdropUniform",
    [
        inv_view_proj,
        top,
        bottom,
        grid_colour,
        plane,
        origin,
        axes,
        params,
        modes
    ]
);
gpu_struct!(
    LineFrame,
    "LineFrame",
    [to_clip, viewport, clip_lo, clip_hi, limits, counts]
);
gpu_struct!(
    Primitive,
    "Primitive",
    [
        model, to_local, normal, size, linear, ray, depth, screen, kind, face, instance, material,
        planes, flags, pad
    ]
);
