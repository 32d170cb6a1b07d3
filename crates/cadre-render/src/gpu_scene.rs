//! A scene in GPU buffers: the geometry uploaded once ([`PreparedScene`]), and per frame the
//! draw records that place every instance relative to the camera, with the view's styles
//! ([`FrameScene`]).

use cadre_mesh::scene::SceneMesh;
use glam::{DAffine3, DMat3, DVec3};
use wgpu::util::DeviceExt;

use std::collections::BTreeMap;

use crate::Camera;
use crate::analytic::AnalyticPrimitive;
use crate::coverage::{ImageCoverage, MAX_IMAGE_COVERAGE, bounding_sphere, placed_sphere};
use crate::edge_faces::EdgeFaces;
use crate::error::RenderError;
use crate::feature_edges::feature_edges;
use crate::frame_buffers::{BindCache, FrameBuffers, GrowingBuffer};
use crate::layout::{
    Call, DRAW_CLOSED, DRAW_INSIDE_OUT, Draw, Material, Segment, TrimTask, Vertex,
};
use crate::passes::instances::InstanceLayout;
use crate::passes::visibility::analytic::FramePrimitives;
use crate::passes::visibility::trim::{FACES_PER_DRAW, FrameTrim, TrimDraw, TrimGeometry};
use crate::placements::{Placements, normal_columns, normal_matrix};
use crate::solid::closed_orientation;
use crate::vertex_cache;
use crate::view::{InstanceStyle, ViewState};

/// Default CAD material (light grey, dielectric, fairly rough) for primitives without one.
const DEFAULT_MATERIAL: Material = Material {
    base_color: [0.62, 0.64, 0.66, 1.0],
    params: [0.0, 0.5, 0.0, 0.0],
};

/// Opacity below which a material is drawn see-through (blended after shading), not into
/// the visibility buffer.
const SEE_THROUGH_BELOW: f32 = 0.999;

/// What a segment of the segment buffer is, in its `b.w` (as `f32` bits).
pub(crate) const SEGMENT_EDGE: u32 = 1;
/// A B-Rep vertex: a segment of zero length, drawn only for picking.
pub(crate) const SEGMENT_VERTEX: u32 = 2;

/// Most triangles one frame may draw (instances × their meshes' triangles): past it a frame
/// is refused, not left running for minutes on a software rasterizer (10⁶ placed cubes are
/// 1.2·10⁷).
pub const MAX_FRAME_TRIANGLES: u64 = 250_000_000;

/// One instanced indexed draw: `count` indices from `first` of mesh `mesh`, `instances`
/// times, each instance found through call `slot` of the frame's call buffer (its record
/// and local placement, [`Call`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct DrawCall {
    pub mesh: usize,
    pub first: u32,
    pub count: u32,
    /// The first `untrimmed` of the `count` indices are the triangles of faces the trim
    /// back-end does not draw: all the visibility phase draws of the mesh (`count` when the
    /// scene has no trims).
    pub untrimmed: u32,
    pub slot: u32,
    pub instances: u32,
    /// The triangles that can be culled: for a closed solid placed without a local list, the
    /// back faces (`Back` when its records are wound outward, `Front` when inside out; a
    /// consistently wound closed mesh never shows them from outside, unless a section plane
    /// opens it). `None` for open shells, see-through runs and shared sub-assemblies (whose
    /// local placements may mirror some instances and not others).
    pub cull: Option<wgpu::Face>,
    /// `Some(first)` when the call's instances are its records `first..first + instances`
    /// themselves (the identity local list): a pass may then read them as instance-step
    /// vertex attributes ([`crate::layout::DRAW_ATTRIBUTES`]) instead of composing them
    /// through the call slot.
    pub direct: Option<u32>,
}

/// One instanced segment draw: `count` segments from `first` of the segment buffer,
/// `instances` times through call `slot` (as [`DrawCall`]).
pub(crate) struct EdgeCall {
    pub first: u32,
    pub count: u32,
    pub slot: u32,
    pub instances: u32,
    /// As [`DrawCall::direct`].
    pub direct: Option<u32>,
}

/// One visible run's B-Rep edges and vertices, for the pick pass: its draw record, where it
/// lies (a bounding sphere relative to the eye, world units) and its segments. The pick pass
/// draws only the runs whose sphere reaches the pick window ([`crate::pick`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PickRun {
    pub record: Draw,
    /// Centre relative to the eye and radius.
    pub sphere: (DVec3, f64),
    /// The run's local placement list (first, count), as [`Call`].
    pub locals: (u32, u32),
    /// Its B-Rep edges and vertices in the segment buffer (first, count).
    pub edges: (u32, u32),
    pub points: (u32, u32),
}

/// A frame's bind group 1: its calls (one [`Call`] per `stride` bytes, bound at a dynamic
/// offset), draw records and the scene's local placements.
pub(crate) struct FrameInstances {
    pub bind: wgpu::BindGroup,
    /// The draw records, also bound as an instance-step vertex buffer by the calls that read
    /// them directly ([`DrawCall::direct`]).
    pub records: wgpu::Buffer,
    stride: u64,
}

impl FrameInstances {
    /// Bind group 1 over `headers` (one call slot each), the draw `records` and the scene's
    /// `locals`, in buffers of its own (a pick's); errors when a buffer would pass the
    /// device's limits.
    pub fn new(
        device: &wgpu::Device,
        layout: &InstanceLayout,
        headers: &[Call],
        records: &[Draw],
        locals: &wgpu::Buffer,
    ) -> Result<FrameInstances, RenderError> {
        let (records, calls) = instance_bytes(device, headers, records)?;
        let draws = checked_buffer(
            device,
            "draw records",
            &records,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
        )?;
        let calls = buffer(device, "draw calls", &calls, wgpu::BufferUsages::UNIFORM);
        let resources = instance_resources(&calls, &draws, locals);
        Ok(FrameInstances {
            bind: crate::passes::common::bind_group(
                device,
                "instances",
                &layout.layout,
                &resources,
            ),
            records: draws.clone(),
            stride: InstanceLayout::call_stride(device),
        })
    }

    /// [`FrameInstances::new`] written into a frame's kept buffers, its bind group from
    /// `binds` (the same as the last frame's while the buffers stay).
    pub fn kept(
        gpu: &crate::Gpu,
        (layout, binds): (&InstanceLayout, &BindCache),
        buffers: &mut FrameBuffers,
        (headers, records): (&[Call], &[Draw]),
        locals: &wgpu::Buffer,
    ) -> Result<FrameInstances, RenderError> {
        let (records, calls) = instance_bytes(&gpu.device, headers, records)?;
        buffers.draws.write(gpu, &records)?;
        buffers.calls.write(gpu, &calls)?;
        let resources = instance_resources(buffers.calls.buffer(), buffers.draws.buffer(), locals);
        Ok(FrameInstances {
            bind: binds.get(&gpu.device, "instances", &layout.layout, &resources),
            records: buffers.draws.buffer().clone(),
            stride: InstanceLayout::call_stride(&gpu.device),
        })
    }

    /// The dynamic offset of call `slot`.
    pub fn offset(&self, slot: u32) -> u32 {
        (u64::from(slot) * self.stride) as u32
    }
}

/// The bytes of a frame's draw records and of its call headers (one per dynamic-offset
/// stride), never empty (storage bindings may not be).
fn instance_bytes(
    device: &wgpu::Device,
    headers: &[Call],
    records: &[Draw],
) -> Result<(Vec<u8>, Vec<u8>), RenderError> {
    let (no_record, no_call) = ([Draw::default()], [Call::default()]);
    let records: &[Draw] = if records.is_empty() {
        &no_record
    } else {
        records
    };
    let headers: &[Call] = if headers.is_empty() {
        &no_call
    } else {
        headers
    };
    let stride = InstanceLayout::call_stride(device);
    let mut call_bytes = vec![0u8; headers.len() * stride as usize];
    for (k, header) in headers.iter().enumerate() {
        let at = k * stride as usize;
        call_bytes[at..at + std::mem::size_of::<Call>()]
            .copy_from_slice(bytemuck::bytes_of(header));
    }
    // Bound one call wide at a dynamic offset, so only the buffer limit applies, not the
    // uniform binding limit (16 KiB on downlevel devices: 64 calls).
    let limit = device.limits().max_buffer_size;
    if call_bytes.len() as u64 > limit {
        return Err(RenderError::TooLarge {
            what: "draw calls",
            bytes: call_bytes.len() as u64,
            limit,
        });
    }
    Ok((bytemuck::cast_slice(records).to_vec(), call_bytes))
}

/// Bind group 1's resources: the call (one wide, at a dynamic offset), records, locals.
fn instance_resources<'b>(
    calls: &'b wgpu::Buffer,
    draws: &'b wgpu::Buffer,
    locals: &'b wgpu::Buffer,
) -> [wgpu::BindingResource<'b>; 3] {
    [
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: calls,
            offset: 0,
            size: wgpu::BufferSize::new(std::mem::size_of::<Call>() as u64),
        }),
        draws.as_entire_binding(),
        locals.as_entire_binding(),
    ]
}

/// Where one primitive of a mesh lies in its index buffer, and its trimmed faces.
#[derive(Clone, Copy, Debug, Default)]
struct PrimitiveRange {
    /// First index and index count.
    first: u32,
    count: u32,
    /// Indices of the triangles the trim back-end does not draw, first in the range.
    untrimmed: u32,
    /// The scene's material.
    material: Option<usize>,
    /// The faces the trim back-end draws: first surface record and count.
    surfaces: (u32, u32),
}

/// Where one mesh's pieces lie in the shared buffers.
#[derive(Clone, Debug, Default)]
struct MeshRanges {
    /// Per primitive: its index range and trimmed faces.
    primitives: Vec<PrimitiveRange>,
    /// Wire-body lines in the segment buffer (first, count), drawn in every mode.
    lines: (u32, u32),
    /// B-Rep (or feature) edges after the lines, drawn in the modes with edges.
    edges: (u32, u32),
    /// B-Rep vertices after the edges, for picking only.
    points: (u32, u32),
    /// `Some(inside_out)` when the mesh is a closed solid (section planes cap it).
    solid: Option<bool>,
    /// Bounding sphere (centre, radius) of its vertices and lines, mesh-local.
    sphere: (glam::DVec3, f64),
    /// Where its stored geometry is measured from (vertices, segments, trimmed faces'
    /// records, `sphere`), in the mesh's own coordinates: its centre, so that `f32` keeps
    /// the precision of a part far from its file's origin (1,661 mm out, `f32` steps 0.12 µm:
    /// pixels of a small face magnified 100×); each draw record places it by its world
    /// placement times the translation to it, in `f64`. Zero where placements are factored.
    origin: glam::DVec3,
}

/// A scene's geometry on the GPU, uploaded once and drawn by any number of frames: vertex and
/// index buffers per mesh, the segments of its edges (with their ids), its materials and
/// its instances' placements. Made by [`crate::Renderer::prepare`].
pub struct PreparedScene {
    pub(crate) vertices: Vec<wgpu::Buffer>,
    pub(crate) indices: Vec<wgpu::Buffer>,
    pub(crate) segments: wgpu::Buffer,
    /// The index buffer of the segments' quads: corners `4k + [0, 1, 3, 0, 3, 2]` for every
    /// segment `k` of the longest run drawn (a call offsets them by its first segment with
    /// the base vertex). Indexed, a quad's four corners are shaded once each where six
    /// vertices were: a CPU rasterizer's vertex cache reuses the two shared ones, and every
    /// corner places both of the segment's ends.
    pub(crate) quad_indices: wgpu::Buffer,
    meshes: Vec<MeshRanges>,
    materials: Vec<Material>,
    /// Where the meshes are placed: runs over local placement lists.
    placements: Placements,
    /// [`Placements::locals`] on the GPU.
    pub(crate) locals: wgpu::Buffer,
    /// Analytic primitives drawn by ray casting, instances after the meshes' (each with its
    /// material at `primitive_materials[k]`: one a distinct colour, so that a crowd of 10⁷
    /// primitives in a few colours does not take 10⁷ materials).
    primitives: Vec<AnalyticPrimitive>,
    primitive_materials: Vec<u32>,
    /// The trimmed faces' records and trees, when the trim back-end draws some.
    pub(crate) trim: Option<TrimGeometry>,
    /// Faces the trim back-end draws (0 without trims).
    trimmed_faces: usize,
    /// The scene's bounding-box diagonal (0 when empty): the crack pass's d_min follows it.
    diagonal: f64,
    /// The scene's world box (what the key light's shadow map covers).
    bounds: Option<(DVec3, DVec3)>,
    /// The scene's line set on the GPU ([`crate::RenderScene::lines`]), set by
    /// [`crate::Renderer::prepare`].
    pub(crate) lines: Option<crate::passes::lines::GpuLines>,
    /// The scene's labels laid out and on the GPU ([`crate::RenderScene::labels`]), set by
    /// [`crate::Renderer::prepare`].
    pub(crate) text: Option<crate::passes::text::GpuText>,
}

impl PreparedScene {
    /// How many quads (glyphs and label boxes) the text pass draws, in one draw call.
    pub fn text_quads(&self) -> u32 {
        self.text.as_ref().map_or(0, |t| t.quad_count())
    }

    /// Characters of the labels no bundled font has (drawn as nothing), sorted.
    pub fn missing_glyphs(&self) -> &[char] {
        self.text.as_ref().map_or(&[], |t| &t.missing)
    }

    /// The scene's bounding-box diagonal, world units (0 when it is empty).
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }

    /// Whether the scene has quadric primitives (their silhouettes carry their coverage).
    pub fn has_quadrics(&self) -> bool {
        self.primitives
            .iter()
            .any(|p| matches!(p.shape, crate::AnalyticShape::Quadric(_)))
    }

    /// The scene's world box, `None` when it is empty.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.bounds
    }

    /// Uploads `scene`'s geometry: its meshes' and its primitives'; past `flat_limit`
    /// instances its placements are factored ([`Placements`]).
    /// `trims`: whether the renderer draws trimmed faces (the scene's [`crate::TrimScene`],
    /// if any, is used; otherwise every face is its mesh's).
    pub(crate) fn new(
        device: &wgpu::Device,
        scene: &crate::RenderScene,
        flat_limit: usize,
        trims: bool,
    ) -> PreparedScene {
        let primitives = &scene.primitives;
        let trim_scene = scene.trim.as_deref().filter(|_| trims);
        let face_records = &scene.faces;
        let bounds = scene.bounds();
        let diagonal = bounds.map_or(0.0, |(lo, hi)| (hi - lo).length());
        // The exact face a dense face id is drawn from by the trim back-end, if any.
        let trimmed = |id: u32| -> Option<&crate::trim_surfaces::TrimFaceSurface> {
            let trim = trim_scene?;
            match face_records.get((id as usize).checked_sub(1)?)? {
                crate::RenderFace::Brep { face, .. } => trim.faces.get(face.index())?.as_ref(),
                crate::RenderFace::Tessellated { .. } => None,
            }
        };
        let mut surfaces: Vec<crate::layout::TrimSurface> = Vec::new();
        let scene = &scene.assembly;
        let mut segments: Vec<Segment> = Vec::new();
        let mut meshes = Vec::with_capacity(scene.meshes.len());
        let mut vertices = Vec::with_capacity(scene.meshes.len());
        let mut indices = Vec::with_capacity(scene.meshes.len());
        let solids: Vec<Option<bool>> = scene.meshes.iter().map(closed_orientation).collect();
        let placements = Placements::new(scene, |m| solids[m].is_some(), flat_limit);
        // Each mesh is stored relative to its own centre, which its draw records add back in
        // f64 (`MeshRanges::origin`); not where placements are factored into shared local
        // lists, whose records cannot.
        let factored = placements.lists.len() > 1;
        for (mesh, &solid) in scene.meshes.iter().zip(&solids) {
            let origin = if factored {
                DVec3::ZERO
            } else {
                mesh_origin(mesh)
            };
            let shift = |p: [f32; 3]| {
                (DVec3::from(p.map(f64::from)) - origin)
                    .as_vec3()
                    .to_array()
            };
            let (mut verts, all, mut primitives, faces) =
                mesh_buffers(mesh, &|id| trimmed(id).is_some());
            for (range, ids) in primitives.iter_mut().zip(&faces) {
                let first = surfaces.len() as u32;
                surfaces.extend(ids.iter().filter_map(|&id| {
                    let exact = trimmed(id)?;
                    let trim = trim_scene?;
                    Some(crate::trim_surfaces::surface_record(
                        exact,
                        (&trim.bspline_data, trim.depth_tolerance),
                        id,
                        face_points(&verts, &all, range, id),
                        origin,
                    ))
                }));
                range.surfaces = (first, surfaces.len() as u32 - first);
            }
            for v in &mut verts {
                v.position = shift(v.position);
            }
            vertices.push(buffer(
                device,
                "vertices",
                bytemuck::cast_slice(&verts),
                wgpu::BufferUsages::VERTEX,
            ));
            indices.push(buffer(
                device,
                "indices",
                bytemuck::cast_slice(&all),
                wgpu::BufferUsages::INDEX,
            ));
            let lines = append(
                &mut segments,
                mesh.lines
                    .iter()
                    .map(|&[a, b]| (shift(a), shift(b), 0, 0, [0; 2])),
            );
            // (a, b, edge id) of the edges; meshes from the file: edges where the face id or
            // the surface folds.
            let edge_segments: Vec<([f32; 3], [f32; 3], u32)> = if mesh.edges.is_empty() {
                feature_edges(mesh)
                    .into_iter()
                    .map(|[a, b]| (a, b, 0))
                    .collect()
            } else {
                mesh.edges
                    .iter()
                    .flat_map(|e| e.points.windows(2).map(move |w| (w[0], w[1], e.id)))
                    .collect()
            };
            // The faces along each edge of a closed solid, for hidden-edge culling.
            let faces = solid.map(|inside_out| {
                EdgeFaces::new(
                    mesh,
                    inside_out,
                    edge_segments.iter().map(|&(a, b, _)| (a, b)),
                )
            });
            let edges = append(
                &mut segments,
                edge_segments.iter().map(|&(a, b, id)| {
                    let packed = faces.as_ref().map_or([0; 2], |f| f.packed(a, b));
                    (shift(a), shift(b), id, SEGMENT_EDGE, packed)
                }),
            );
            let points = append(
                &mut segments,
                mesh.vertices.iter().map(|v| {
                    let p = shift(v.position);
                    (p, p, v.id, SEGMENT_VERTEX, [0; 2])
                }),
            );
            let (centre, radius) = bounding_sphere(
                mesh.positions
                    .iter()
                    .copied()
                    .chain(mesh.lines.iter().flatten().copied()),
            );
            meshes.push(MeshRanges {
                primitives,
                lines,
                edges,
                points,
                solid,
                sphere: (centre - origin, radius),
                origin,
            });
        }
        let mut materials: Vec<Material> = scene
            .materials
            .iter()
            .map(|m| Material {
                base_color: m.base_color,
                params: [m.metallic, m.roughness, 0.0, 0.0],
            })
            .collect();
        let mut by_colour: std::collections::HashMap<[u32; 4], u32> = Default::default();
        let primitive_materials: Vec<u32> = primitives
            .iter()
            .map(|p| {
                *by_colour
                    .entry(p.colour.map(f32::to_bits))
                    .or_insert_with(|| {
                        materials.push(Material {
                            base_color: p.colour,
                            params: DEFAULT_MATERIAL.params,
                        });
                        materials.len() as u32 - 1
                    })
            })
            .collect();
        materials.push(DEFAULT_MATERIAL);
        // A call draws at most one mesh's lines, edges or points.
        let longest = meshes
            .iter()
            .map(|m| m.lines.1.max(m.edges.1).max(m.points.1))
            .max()
            .unwrap_or(0)
            .max(1);
        let quads: Vec<u32> = (0..longest)
            .flat_map(|k| [0, 1, 3, 0, 3, 2].map(|c| 4 * k + c))
            .collect();
        PreparedScene {
            quad_indices: buffer(
                device,
                "segment quads",
                bytemuck::cast_slice(&quads),
                wgpu::BufferUsages::INDEX,
            ),
            locals: buffer(
                device,
                "local placements",
                bytemuck::cast_slice(&placements.locals),
                wgpu::BufferUsages::STORAGE,
            ),
            vertices,
            indices,
            segments: buffer(
                device,
                "segments",
                bytemuck::cast_slice(&segments),
                wgpu::BufferUsages::STORAGE,
            ),
            meshes,
            materials,
            placements,
            primitives: primitives.clone(),
            primitive_materials,
            lines: None,
            text: None,
            diagonal,
            bounds,
            trimmed_faces: surfaces.len(),
            trim: trim_scene
                .filter(|_| !surfaces.is_empty())
                .map(|t| TrimGeometry::new(device, &surfaces, (&t.trees.buffers, &t.bspline_data))),
        }
    }

    /// How many face records the trim back-end draws (a face placed in several meshes
    /// counts once per mesh); 0 when every face is drawn from its mesh.
    pub fn trimmed_faces(&self) -> usize {
        self.trimmed_faces
    }

    /// Places analytic primitive `k` by `frame` from the next frame on (its records are
    /// built each frame: nothing is uploaded again); `false` when there is no such primitive.
    /// What a viewer moves a tool or a marker with.
    pub fn move_primitive(&mut self, k: usize, frame: cadre_geom::Frame) -> bool {
        match self.primitives.get_mut(k) {
            Some(p) => {
                p.frame = frame;
                true
            }
            None => false,
        }
    }

    /// The analytic primitives, in order.
    pub fn primitives(&self) -> &[AnalyticPrimitive] {
        &self.primitives
    }

    /// The instance number of analytic primitive `k` (after every mesh instance), as the
    /// visibility buffer and picking give it.
    pub fn primitive_instance(&self, k: usize) -> u32 {
        (self.placements.instances + k) as u32
    }

    /// The visible primitives' records for a frame seen by `camera` in an image of `aspect`,
    /// opaque ones written into `buffers.0` and see-through ones (their material's or the
    /// view's colour has an opacity below 1) into `buffers.1` — each in buffers of at most
    /// the device's storage binding size, as many as they take — the quadrics' cutting planes
    /// into `buffers.2` (once per shape); a view's colour becomes a material of its own in
    /// `materials`, as for the meshes.
    fn frame_primitives(
        &self,
        gpu: &crate::Gpu,
        (opaque_buffers, see_through_buffers, planes_buffer): (
            &mut Vec<GrowingBuffer>,
            &mut Vec<GrowingBuffer>,
            &mut GrowingBuffer,
        ),
        (camera, aspect, state): (&Camera, f64, &ViewState),
        materials: &mut Vec<Material>,
    ) -> Result<FramePrimitives, RenderError> {
        let (mut opaque, mut see_through) = (Vec::new(), Vec::new());
        let mut planes = crate::analytic::FramePlanes::default();
        // Primitives wholly outside the view get no record (a close-up of a crowd of 10⁶).
        let frustum = crate::camera::Frustum::new(camera, aspect);
        let view = crate::analytic::FrameView::new(camera, aspect);
        for (k, p) in self.primitives.iter().enumerate() {
            if !frustum.holds(p.bounding_sphere()) {
                continue;
            }
            let instance = self.primitive_instance(k);
            let style = state
                .instances
                .get(instance as usize)
                .copied()
                .unwrap_or_default();
            if !style.visible {
                continue;
            }
            let material = match style.colour {
                Some(c) => {
                    materials.push(Material {
                        base_color: c,
                        params: DEFAULT_MATERIAL.params,
                    });
                    materials.len() as u32 - 1
                }
                None => self.primitive_materials[k],
            };
            let record = p.record(&view, (instance, material), &mut planes);
            if materials[material as usize].base_color[3] < SEE_THROUGH_BELOW {
                see_through.push(record);
            } else {
                opaque.push(record);
            }
        }
        let mut planes = planes.planes;
        // Storage bindings may not be empty.
        if planes.is_empty() {
            planes.push([0.0; 4]);
        }
        planes_buffer.write(gpu, bytemuck::cast_slice(&planes))?;
        Ok(FramePrimitives {
            planes: planes_buffer.buffer().clone(),
            opaque: write_chunks(gpu, opaque_buffers, &opaque)?,
            see_through: write_chunks(gpu, see_through_buffers, &see_through)?,
        })
    }

    /// Number of instances (placed meshes), in the scene's instance order.
    pub fn instance_count(&self) -> usize {
        self.placements.instances
    }

    /// Runs of placements: a frame of every instance has one draw record per run for its
    /// segments and one per run and primitive (see [`crate::layout::Local`]).
    pub fn run_count(&self) -> usize {
        self.placements.runs.len()
    }

    /// Index of the default material (after the scene's own).
    fn default_material(&self) -> u32 {
        self.materials.len() as u32 - 1
    }
}

/// One mesh's vertex records, its index list, where each primitive lies in it, and each
/// primitive's trimmed face ids (in order of first appearance).
type MeshBuffers = (Vec<Vertex>, Vec<u32>, Vec<PrimitiveRange>, Vec<Vec<u32>>);

/// The vertex records (each with its face id), the indices and the primitive ranges of
/// `mesh`; in each primitive the triangles of faces `trimmed` says the trim back-end draws
/// come after the others (each part in the vertex cache's order).
fn mesh_buffers(mesh: &SceneMesh, trimmed: &dyn Fn(u32) -> bool) -> MeshBuffers {
    let mut face_of_vertex = vec![0u32; mesh.positions.len()];
    let mut all = Vec::new();
    let mut prims = Vec::new();
    let mut faces = Vec::new();
    for prim in &mesh.primitives {
        for (t, tri) in prim.indices.chunks_exact(3).enumerate() {
            let id = prim.face_ids.get(t).copied().unwrap_or(0);
            for &i in tri {
                if let Some(f) = face_of_vertex.get_mut(i as usize) {
                    *f = id;
                }
            }
        }
        let first = all.len();
        let last = mesh.positions.len().saturating_sub(1) as u32;
        let mut face_ids: Vec<u32> = Vec::new();
        let mut seen = rustc_hash::FxHashSet::default();
        let mut kept: Vec<u32> = Vec::with_capacity(prim.indices.len());
        let mut cut: Vec<u32> = Vec::new();
        for (t, tri) in prim.indices.chunks_exact(3).enumerate() {
            let id = prim.face_ids.get(t).copied().unwrap_or(0);
            let tri = tri.iter().map(|&i| i.min(last));
            if trimmed(id) {
                if seen.insert(id) {
                    face_ids.push(id);
                }
                cut.extend(tri);
            } else {
                kept.extend(tri);
            }
        }
        // The trim back-end's records of a primitive in ascending face id: the exact crack
        // fill finds a pixel's face among its call's by binary search (`crack.wgsl`).
        face_ids.sort_unstable();
        vertex_cache::optimize(&mut kept);
        vertex_cache::optimize(&mut cut);
        prims.push(PrimitiveRange {
            first: first as u32,
            count: (kept.len() + cut.len()) as u32,
            untrimmed: kept.len() as u32,
            material: prim.material,
            surfaces: (0, 0),
        });
        faces.push(face_ids);
        all.extend(kept);
        all.extend(cut);
    }
    let verts = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, &position)| Vertex {
            position,
            normal: mesh.normals.get(i).copied().unwrap_or([0.0, 0.0, 1.0]),
            face_id: face_of_vertex[i],
            uv: mesh.surface_uv.get(i).copied().unwrap_or([0.0; 2]),
        })
        .collect();
    (verts, all, prims, faces)
}

/// The centre of `mesh`'s bounding box (its vertices and lines; zero when it has none): the
/// origin its geometry is stored from ([`MeshRanges::origin`]).
fn mesh_origin(mesh: &SceneMesh) -> DVec3 {
    let (lo, hi) = mesh
        .positions
        .iter()
        .chain(mesh.lines.iter().flatten())
        .map(|p| DVec3::from(p.map(f64::from)))
        .filter(|p| p.is_finite())
        .fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
    if lo.x <= hi.x {
        0.5 * (lo + hi)
    } else {
        DVec3::ZERO
    }
}

/// The (position, normal, (u, v)) of the vertices of face `id`'s triangles in `range` of a
/// mesh's indices.
fn face_points<'m>(
    verts: &'m [Vertex],
    all: &'m [u32],
    range: &PrimitiveRange,
    id: u32,
) -> impl Iterator<Item = ([f32; 3], [f32; 3], [f32; 2])> + 'm {
    let span = &all[(range.first + range.untrimmed) as usize..(range.first + range.count) as usize];
    span.iter()
        .filter_map(move |&i| verts.get(i as usize))
        .filter(move |v| v.face_id == id)
        .map(|v| (v.position, v.normal, v.uv))
}

/// Appends segments `(a, b, id, kind, faces)` and returns their (first, count).
fn append(
    segments: &mut Vec<Segment>,
    items: impl Iterator<Item = ([f32; 3], [f32; 3], u32, u32, [u32; 2])>,
) -> (u32, u32) {
    let first = segments.len() as u32;
    // Each segment's place in its polyline (an edge's, or a wire's consecutive pieces): 0
    // where the one before is of another item or does not end where it starts. The edges
    // pass sums the screen lengths of those before it for the hidden-line dashes.
    let mut previous: Option<(u32, u32, [f32; 3], u32)> = None;
    segments.extend(items.map(|(a, b, id, kind, faces)| {
        let place = match previous {
            Some((pid, pkind, pb, k)) if pid == id && pkind == kind && pb == a => k + 1,
            _ => 0,
        };
        previous = Some((id, kind, b, place));
        Segment {
            a: [a[0], a[1], a[2], f32::from_bits(id)],
            b: [b[0], b[1], b[2], f32::from_bits(kind)],
            faces,
            pad: [place, 0],
        }
    }));
    (first, segments.len() as u32 - first)
}

/// What one frame draws: the draw records (runs of instances placed relative to the camera,
/// with the view's colours) and their calls, the mesh draw calls split into opaque and
/// see-through, and the segment calls.
pub(crate) struct FrameScene<'a> {
    pub geometry: &'a PreparedScene,
    pub instances: FrameInstances,
    pub materials: wgpu::Buffer,
    /// Opaque triangles, drawn into the visibility buffer.
    pub calls: Vec<DrawCall>,
    /// Triangles of see-through instances, blended after shading.
    pub transparent: Vec<DrawCall>,
    /// Lines and edges of visible instances.
    pub edge_calls: Vec<EdgeCall>,
    /// B-Rep edges and vertices of visible runs, for the pick pass.
    pub pick_runs: Vec<PickRun>,
    /// Visible analytic primitives, for the analytic back-end.
    pub primitives: FramePrimitives,
    /// The trimmed faces' tessellation tasks and draws, if the frame has any.
    pub trim: Option<FrameTrim>,
}

/// The records of a trimmed call (`(record, nearest distance from the eye)`) grouped in
/// distance bands, each with its nearest distance: the trim back-end tessellates a call's
/// faces for its nearest instance, so one call over a large assembly of repeated parts would
/// draw its farthest copies with the grids of its nearest. A band holds the records whose
/// nearest distance lies within a factor of two (`[2^k, 2^(k+1))`), so no copy gets more
/// than twice the pixel accuracy it needs (its grid √2 finer each way, at most); the records
/// an eye is inside of form a band of their own. An orthographic view's grids do not depend
/// on the distance: one band.
pub(crate) fn distance_bands(
    records: &[(Draw, f64)],
    orthographic: bool,
) -> Vec<(Vec<usize>, f64)> {
    let key = |near: f64| {
        if orthographic {
            0
        } else if !near.is_finite() || near <= 0.0 {
            i32::MIN
        } else {
            near.log2().floor().clamp(-1000.0, 1000.0) as i32
        }
    };
    let mut bands: BTreeMap<i32, (Vec<usize>, f64)> = BTreeMap::new();
    for (k, &(_, near)) in records.iter().enumerate() {
        let band = bands
            .entry(key(near))
            .or_insert((Vec::new(), f64::INFINITY));
        band.0.push(k);
        band.1 = band.1.min(near);
    }
    bands.into_values().collect()
}

/// A visible run's base draw record, the material of its view colour, if any, and its
/// bounding sphere relative to the eye.
type RunRecord = (Draw, Option<u32>, (DVec3, f64));

/// The records of one frame and the calls that draw them, while they are built.
#[derive(Default)]
struct FrameCalls {
    draws: Vec<Draw>,
    headers: Vec<Call>,
    calls: Vec<DrawCall>,
    transparent: Vec<DrawCall>,
    edge_calls: Vec<EdgeCall>,
    pick_runs: Vec<PickRun>,
    /// Triangles the calls draw, all instances counted.
    triangles: u64,
    /// The trim back-end's tessellation tasks and indirect draws.
    trim_tasks: Vec<TrimTask>,
    trim_draws: Vec<TrimDraw>,
}

impl FrameCalls {
    /// A call slot over `instances` instances: the records from `record` on, each drawn
    /// once per local of `list`, and for a segment call its `segments` (first, count).
    fn slot(
        &mut self,
        (record, instances): (u32, u32),
        (locals_first, locals_count): (u32, u32),
        segments: [u32; 2],
    ) -> u32 {
        self.headers.push(Call {
            record,
            locals_first,
            locals_count,
            instances,
            range: segments,
            pad: [0; 2],
        });
        self.headers.len() as u32 - 1
    }

    /// The trim back-end's draws of surfaces `(first, count)` over a mesh call's instances
    /// (`records`: first record and instances; `locals`: its local list), nearest `near`
    /// from the eye: a call slot and a task per face, in draws of at most
    /// [`FACES_PER_DRAW`] faces.
    fn trim_calls(
        &mut self,
        (first, count): (u32, u32),
        (record, instances): (u32, u32),
        (locals_first, locals_count): (u32, u32),
        near: f32,
    ) {
        for chunk in (0..count).step_by(FACES_PER_DRAW as usize) {
            let faces = (count - chunk).min(FACES_PER_DRAW);
            let task_first = self.trim_tasks.len() as u32;
            let slot = self.slot(
                (record, instances),
                (locals_first, locals_count),
                [first + chunk, task_first],
            );
            self.trim_tasks.extend((0..faces).map(|k| TrimTask {
                surface: first + chunk + k,
                record,
                locals_first,
                locals_count,
                instances,
                slot: k,
                near,
                pad: 0,
            }));
            self.trim_draws.push(TrimDraw {
                slot,
                faces,
                task_first,
            });
        }
    }
}

impl<'a> FrameScene<'a> {
    /// The draw records of `geometry` seen by `camera` in `state`; B-Rep edges are drawn when
    /// `with_edges` (wire bodies always).
    /// The records go into the frame's kept `buffers`.
    pub fn new(
        gpu: &crate::Gpu,
        (layout, binds): (&InstanceLayout, &BindCache),
        buffers: &mut FrameBuffers,
        geometry: &'a PreparedScene,
        (camera, state, aspect): (&Camera, &ViewState, f64),
        with_edges: bool,
    ) -> Result<FrameScene<'a>, RenderError> {
        let mut materials = geometry.materials.clone();
        let rotation = DMat3::from_mat4(camera.view_rotation());
        let placements = &geometry.placements;
        // Visible runs grouped by mesh and local list, each with its base record and colour:
        // the runs of one group are drawn by one instanced call per primitive (an assembly of
        // thousands of repeated parts costs a few calls, not thousands).
        let mut groups: BTreeMap<(usize, usize), Vec<RunRecord>> = BTreeMap::new();
        let mut coverage = ImageCoverage::new(camera);
        let mut visible = 0usize;
        for run in &placements.runs {
            // A run of several placements takes the style of its first (a view styles the
            // instances of a factored sub-assembly together).
            let style = state
                .instances
                .get(run.instance as usize)
                .copied()
                .unwrap_or(InstanceStyle::default());
            if !style.visible {
                continue;
            }
            // A colour of the view replaces the part's materials with one of its own.
            let colour_material = style.colour.map(|c| {
                materials.push(Material {
                    base_color: c,
                    params: DEFAULT_MATERIAL.params,
                });
                materials.len() as u32 - 1
            });
            let ranges = &geometry.meshes[run.mesh];
            let list = placements.lists[run.list];
            // The mesh's stored geometry is relative to its origin (zero under local lists,
            // whose placements come after the record's).
            let world = run.world * DAffine3::from_translation(ranges.origin);
            let mut spheres = SphereUnion::default();
            if run.list == 0 {
                coverage.add(world, ranges.sphere);
                spheres.add(world, ranges.sphere);
            } else {
                debug_assert_eq!(ranges.origin, DVec3::ZERO);
                for l in placements.list(list) {
                    let world = run.world * l.affine();
                    coverage.add(world, ranges.sphere);
                    spheres.add(world, ranges.sphere);
                }
            }
            visible += list.count as usize;
            // A mirroring placement turns the winding over, as does a mesh wound inside out.
            let flags = ranges.solid.map_or(0, |inside_out| {
                let mirrored = run.world.matrix3.determinant() < 0.0;
                DRAW_CLOSED
                    | if inside_out != mirrored {
                        DRAW_INSIDE_OUT
                    } else {
                        0
                    }
            });
            let record = placement(camera, rotation, world, (run.instance, flags));
            groups.entry((run.mesh, run.list)).or_default().push((
                record(geometry.default_material()),
                colour_material,
                spheres.around(camera.eye),
            ));
        }
        // Refused before anything is drawn: a frame covering the image thousands of times
        // over would run for hours on a software rasterizer.
        if coverage.total > MAX_IMAGE_COVERAGE {
            return Err(RenderError::Overdrawn {
                coverage: coverage.total,
                instances: visible,
                limit: MAX_IMAGE_COVERAGE,
            });
        }
        let mut out = FrameCalls::default();
        for (&(mesh, list_index), group) in &groups {
            let ranges = &geometry.meshes[mesh];
            let list = placements.lists[list_index];
            // (see-through, wound inside out) of each call of a primitive: the opaque records
            // of a closed solid without local placements are split by winding so that each
            // call can cull its back faces (the setup and binning of half the triangles, on a
            // CPU rasterizer).
            let parts: &[(bool, Option<bool>)] = if ranges.solid.is_some() && list_index == 0 {
                &[(false, Some(false)), (false, Some(true)), (true, None)]
            } else {
                &[(false, None), (true, None)]
            };
            let locals = (list.first, list.count);
            // Runs on the identity list are drawn once each by their own record.
            let direct = |first: u32| (list_index == 0).then_some(first);
            let n = group.len() as u32;
            let instances = n * list.count;
            // One record per run for its segments (the default material's).
            let own = out.draws.len() as u32;
            out.draws.extend(group.iter().map(|(d, _, _)| *d));
            // Each segment call has its own slot: the edges' compute rasterizer reads its
            // segments there.
            let segment_call = |out: &mut FrameCalls, (first, count): (u32, u32)| {
                if count > 0 {
                    let slot = out.slot((own, instances), locals, [first, count]);
                    out.edge_calls.push(EdgeCall {
                        first,
                        count,
                        slot,
                        instances,
                        direct: direct(own),
                    });
                }
            };
            segment_call(&mut out, ranges.lines);
            if with_edges {
                segment_call(&mut out, ranges.edges);
            }
            if ranges.edges.1 + ranges.points.1 > 0 {
                out.pick_runs
                    .extend(group.iter().map(|&(record, _, sphere)| PickRun {
                        record,
                        sphere,
                        locals,
                        edges: ranges.edges,
                        points: ranges.points,
                    }));
            }
            // The run's nearest distance from the eye (camera-relative spheres).
            let near = group
                .iter()
                .map(|(_, _, (c, r))| c.length() - r)
                .fold(f64::INFINITY, f64::min);
            for range in &ranges.primitives {
                let (first, count, material) = (range.first, range.count, range.material);
                if count == 0 {
                    continue;
                }
                let own_material = material
                    .filter(|&m| m + 1 < geometry.materials.len())
                    .map_or(geometry.default_material(), |m| m as u32);
                // Opaque runs first, then see-through ones, each a contiguous run of records.
                let resolved: Vec<(Draw, bool, f64)> = group
                    .iter()
                    .map(|&(d, colour, (c, r))| {
                        let m = colour.unwrap_or(own_material);
                        let see_through = materials[m as usize].base_color[3] < SEE_THROUGH_BELOW;
                        (Draw { material: m, ..d }, see_through, c.length() - r)
                    })
                    .collect();
                for &(see_through, inside_out) in parts {
                    let chosen: Vec<(Draw, f64)> = resolved
                        .iter()
                        .filter(|(d, t, _)| {
                            *t == see_through
                                && inside_out
                                    .is_none_or(|i| i == ((d.flags & DRAW_INSIDE_OUT) != 0))
                        })
                        .map(|&(d, _, near)| (d, near))
                        .collect();
                    let start = out.draws.len() as u32;
                    out.draws.extend(chosen.iter().map(|(d, _)| *d));
                    let records = chosen.len() as u32;
                    if records == 0 {
                        continue;
                    }
                    let trimmed = !see_through && range.surfaces.1 > 0;
                    if trimmed {
                        let bands = distance_bands(&chosen, camera.is_orthographic());
                        if bands.len() == 1 {
                            out.trim_calls(
                                range.surfaces,
                                (start, records * list.count),
                                locals,
                                near as f32,
                            );
                        } else {
                            // Each band's records again, contiguous, so that its call's
                            // instances are the band's alone.
                            for (band, band_near) in bands {
                                let first = out.draws.len() as u32;
                                out.draws.extend(band.iter().map(|&k| chosen[k].0));
                                out.trim_calls(
                                    range.surfaces,
                                    (first, band.len() as u32 * list.count),
                                    locals,
                                    band_near as f32,
                                );
                            }
                        }
                    }
                    let call = DrawCall {
                        mesh,
                        first,
                        count,
                        untrimmed: if trimmed { range.untrimmed } else { count },
                        slot: out.slot((start, records * list.count), locals, [0; 2]),
                        instances: records * list.count,
                        direct: direct(start),
                        cull: inside_out.map(|i| {
                            if i {
                                wgpu::Face::Front
                            } else {
                                wgpu::Face::Back
                            }
                        }),
                    };
                    out.triangles += u64::from(count / 3) * u64::from(call.instances);
                    if see_through {
                        out.transparent.push(call);
                    } else {
                        out.calls.push(call);
                    }
                }
            }
        }
        if out.triangles > MAX_FRAME_TRIANGLES {
            return Err(RenderError::TooManyTriangles {
                triangles: out.triangles,
                limit: MAX_FRAME_TRIANGLES,
            });
        }
        let instances = FrameInstances::kept(
            gpu,
            (layout, binds),
            buffers,
            (&out.headers, &out.draws),
            &geometry.locals,
        )?;
        let primitives = geometry.frame_primitives(
            gpu,
            (
                &mut buffers.primitives,
                &mut buffers.see_through_primitives,
                &mut buffers.primitive_planes,
            ),
            (camera, aspect, state),
            &mut materials,
        )?;
        buffers
            .materials
            .write(gpu, bytemuck::cast_slice(&materials))?;
        Ok(FrameScene {
            geometry,
            instances,
            materials: buffers.materials.buffer().clone(),
            calls: out.calls,
            transparent: out.transparent,
            edge_calls: out.edge_calls,
            pick_runs: out.pick_runs,
            primitives,
            trim: FrameTrim::new(&gpu.device, &out.trim_tasks, out.trim_draws),
        })
    }
}

/// `records` written into `buffers` (grown by copies of its first's kind as needed) in chunks
/// of at most the device's storage binding size: each chunk's buffer and record count (none
/// when there is no record).
fn write_chunks(
    gpu: &crate::Gpu,
    buffers: &mut Vec<GrowingBuffer>,
    records: &[crate::layout::Primitive],
) -> Result<Vec<(wgpu::Buffer, u32)>, RenderError> {
    let limit = buffer_limit(&gpu.device.limits(), wgpu::BufferUsages::STORAGE);
    let per_chunk =
        (limit / std::mem::size_of::<crate::layout::Primitive>() as u64).max(1) as usize;
    let mut out = Vec::new();
    for (k, chunk) in records.chunks(per_chunk).enumerate() {
        if buffers.len() <= k {
            let more = buffers[0].sibling(&gpu.device);
            buffers.push(more);
        }
        buffers[k].write(gpu, bytemuck::cast_slice(chunk))?;
        out.push((buffers[k].buffer().clone(), chunk.len() as u32));
    }
    Ok(out)
}

/// A sphere around placed bounding spheres (the box of their boxes' centre, the farthest
/// sphere's reach): loose, but it holds every one of them.
#[derive(Default)]
struct SphereUnion {
    placed: Vec<(DVec3, f64)>,
}

impl SphereUnion {
    /// Adds the mesh-local sphere (`centre`, `radius`) placed by `world`.
    fn add(&mut self, world: DAffine3, sphere: (DVec3, f64)) {
        self.placed.push(placed_sphere(world, sphere));
    }

    /// The union's sphere, its centre relative to `eye`.
    fn around(&self, eye: DVec3) -> (DVec3, f64) {
        let lo = self
            .placed
            .iter()
            .fold(DVec3::INFINITY, |a, (c, r)| a.min(*c - *r));
        let hi = self
            .placed
            .iter()
            .fold(DVec3::NEG_INFINITY, |a, (c, r)| a.max(*c + *r));
        if !(lo.is_finite() && hi.is_finite()) {
            return (DVec3::ZERO, f64::INFINITY);
        }
        let centre = 0.5 * (lo + hi);
        let radius = self
            .placed
            .iter()
            .map(|(c, r)| (*c - centre).length() + r)
            .fold(0.0, f64::max);
        (centre - eye, radius)
    }
}

/// The draw record maker of one instance placed by `world`, relative to the camera's eye (in
/// `f64`, so parts far from the origin keep their precision), with the mesh's `flags`
/// ([`DRAW_CLOSED`], [`DRAW_INSIDE_OUT`]).
fn placement(
    camera: &Camera,
    rotation: DMat3,
    world: DAffine3,
    (instance, flags): (u32, u32),
) -> impl Fn(u32) -> Draw {
    let linear = world.matrix3;
    // Normals transform by the inverse transpose, then into view space.
    let normal = normal_columns(rotation * normal_matrix(linear));
    let translation: DVec3 = world.translation - camera.eye;
    let model = glam::DMat4::from_cols(
        linear.x_axis.extend(0.0),
        linear.y_axis.extend(0.0),
        linear.z_axis.extend(0.0),
        translation.extend(1.0),
    )
    .as_mat4();
    move |material: u32| Draw {
        model: model.to_cols_array_2d(),
        normal,
        material,
        instance,
        flags,
        pad: 0,
    }
}

/// The largest buffer of `usage` the adapter's `limits` allow, in bytes: storage and
/// uniform buffers are bound whole, so their binding limit applies too.
pub(crate) fn buffer_limit(limits: &wgpu::Limits, usage: wgpu::BufferUsages) -> u64 {
    let mut limit = limits.max_buffer_size;
    if usage.contains(wgpu::BufferUsages::STORAGE) {
        limit = limit.min(limits.max_storage_buffer_binding_size);
    }
    if usage.contains(wgpu::BufferUsages::UNIFORM) {
        limit = limit.min(limits.max_uniform_buffer_binding_size);
    }
    limit
}

/// [`buffer`], or [`RenderError::TooLarge`] when `bytes` exceed what the device allows for
/// `usage`: wgpu would make an invalid buffer and panic when filling it (2·10⁶ instances'
/// draw records of a 2·10⁶-part assembly).
pub(crate) fn checked_buffer(
    device: &wgpu::Device,
    label: &'static str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> Result<wgpu::Buffer, RenderError> {
    let limit = buffer_limit(&device.limits(), usage);
    let len = bytes.len() as u64;
    if len > limit {
        return Err(RenderError::TooLarge {
            what: label,
            bytes: len,
            limit,
        });
    }
    Ok(buffer(device, label, bytes, usage))
}

/// A buffer initialised with `bytes` (at least 16 bytes, as wgpu requires non-empty buffers).
pub(crate) fn buffer(
    device: &wgpu::Device,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let padded;
    let contents = if bytes.is_empty() {
        padded = [0u8; 32];
        &padded[..]
    } else {
        bytes
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage,
    })
}

#[cfg(test)]
mod tests {
    use super::{buffer_limit, distance_bands};
    use crate::layout::Draw;

    /// A trimmed call's records are split by distance within a factor of two, each band
    /// keeping its nearest distance; the eye's own records and an orthographic view's are
    /// not split by distance.
    #[test]
    fn trimmed_records_are_banded_by_distance() {
        let records: Vec<(Draw, f64)> = [3.0, 1.5, 2.5, 40.0, -1.0, 33.0, 7.9]
            .iter()
            .map(|&near| (Draw::default(), near))
            .collect();
        let bands = distance_bands(&records, false);
        let got: Vec<(Vec<usize>, f64)> = bands;
        assert_eq!(
            got,
            vec![
                (vec![4], -1.0),
                (vec![1], 1.5),
                (vec![0, 2], 2.5),
                (vec![6], 7.9),
                (vec![3, 5], 33.0),
            ]
        );
        // Every record in exactly one band, within a factor of two of the band's nearest.
        for (band, near) in distance_bands(&records, false) {
            for k in band {
                let d = records[k].1;
                assert!(d >= near && (near <= 0.0 || d < 2.0 * near), "{d} {near}");
            }
        }
        let ortho = distance_bands(&records, true);
        assert_eq!(ortho.len(), 1);
        assert_eq!(ortho[0].0.len(), records.len());
    }

    /// Storage buffers are bound whole: the binding limit, not the buffer limit, caps them
    /// (wgpu's defaults: 128 MiB against 256 MiB), so 2·10⁶ draw records of 128 bytes are
    /// refused before wgpu makes an invalid buffer.
    #[test]
    fn storage_buffers_are_capped_by_their_binding_limit() {
        let limits = wgpu::Limits::default();
        let storage = buffer_limit(&limits, wgpu::BufferUsages::STORAGE);
        assert_eq!(storage, limits.max_storage_buffer_binding_size);
        assert!(storage < limits.max_buffer_size);
        assert_eq!(
            buffer_limit(&limits, wgpu::BufferUsages::VERTEX),
            limits.max_buffer_size
        );
        let records = 2_000_000 * std::mem::size_of::<crate::layout::Draw>() as u64;
        assert!(records > storage, "{records}");
    }
}
