//! A scene's meshes, draws and materials in GPU buffers, placed relative to the camera.

use cadre_mesh::export::Scene;
use glam::{DMat3, DVec3};
use wgpu::util::DeviceExt;

use crate::Camera;
use crate::edges::feature_edges;
use crate::layout::{Draw, Material, Segment, Vertex};

/// Default CAD material (light grey, dielectric, fairly rough) for primitives without one.
const DEFAULT_MATERIAL: Material = Material {
    base_color: [0.62, 0.64, 0.66, 1.0],
    params: [0.0, 0.5, 0.0, 0.0],
};

/// One indexed draw call: `count` indices from `first` of mesh `mesh`, with draw record `draw`.
pub(crate) struct DrawCall {
    pub mesh: usize,
    pub first: u32,
    pub count: u32,
    pub draw: u32,
}

/// One edge draw: `count` segments from `first` of the segment buffer, placed by draw record
/// `draw` (any of the instance's records: they share its model matrix).
pub(crate) struct EdgeCall {
    pub first: u32,
    pub count: u32,
    pub draw: u32,
}

/// GPU buffers of a scene.
pub(crate) struct GpuScene {
    pub vertices: Vec<wgpu::Buffer>,
    pub indices: Vec<wgpu::Buffer>,
    pub draws: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    pub calls: Vec<DrawCall>,
    pub segments: wgpu::Buffer,
    pub edge_calls: Vec<EdgeCall>,
}

impl GpuScene {
    /// Uploads `scene` with every instance placed relative to `camera.eye` (in `f64`); the
    /// B-Rep edges too when `with_edges` (wire bodies always).
    pub fn upload(
        device: &wgpu::Device,
        scene: &Scene,
        camera: &Camera,
        with_edges: bool,
    ) -> GpuScene {
        // Per mesh: its range in the segment buffer.
        let mut segments: Vec<Segment> = Vec::new();
        let mut mesh_segments: Vec<(u32, u32)> = Vec::with_capacity(scene.meshes.len());
        for mesh in &scene.meshes {
            let first = segments.len() as u32;
            segments.extend(mesh.lines.iter().map(|[a, b]| Segment {
                a: [a[0], a[1], a[2], 1.0],
                b: [b[0], b[1], b[2], 1.0],
            }));
            if with_edges {
                segments.extend(feature_edges(mesh).into_iter().map(|[a, b]| Segment {
                    a: [a[0], a[1], a[2], 1.0],
                    b: [b[0], b[1], b[2], 1.0],
                }));
            }
            mesh_segments.push((first, segments.len() as u32 - first));
        }
        let mut edge_calls = Vec::new();
        let mut vertices = Vec::with_capacity(scene.meshes.len());
        let mut indices = Vec::with_capacity(scene.meshes.len());
        // Per mesh: where each primitive starts in the mesh's index buffer.
        let mut starts: Vec<Vec<(u32, u32, Option<usize>)>> = Vec::new();
        for mesh in &scene.meshes {
            let mut face_of_vertex = vec![0u32; mesh.positions.len()];
            let mut all = Vec::new();
            let mut prims = Vec::new();
            for prim in &mesh.primitives {
                for (t, tri) in prim.indices.chunks_exact(3).enumerate() {
                    let id = prim.face_ids.get(t).copied().unwrap_or(0);
                    for &i in tri {
                        if let Some(f) = face_of_vertex.get_mut(i as usize) {
                            *f = id;
                        }
                    }
                }
                prims.push((all.len() as u32, prim.indices.len() as u32, prim.material));
                all.extend(
                    prim.indices
                        .iter()
                        .map(|&i| i.min(mesh.positions.len().saturating_sub(1) as u32)),
                );
            }
            let verts: Vec<Vertex> = mesh
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
            starts.push(prims);
        }
        let mut materials: Vec<Material> = scene
            .materials
            .iter()
            .map(|m| Material {
                base_color: m.base_color,
                params: [m.metallic, m.roughness, 0.0, 0.0],
            })
            .collect();
        let default_material = materials.len() as u32;
        materials.push(DEFAULT_MATERIAL);

        let rotation = DMat3::from_mat4(camera.view_rotation());
        let mut draws = Vec::new();
        let mut calls = Vec::new();
        for (instance, (node, world)) in scene.instances().enumerate() {
            let Some(mesh) = scene.nodes[node].mesh.filter(|&m| m < scene.meshes.len()) else {
                continue;
            };
            let linear = world.matrix3;
            // Normals transform by the inverse transpose; mirrors are fine, singular
            // placements get the plain rotation part.
            let normal = if linear.determinant().abs() > 1e-300 {
                rotation * linear.inverse().transpose()
            } else {
                rotation * linear
            };
            let translation: DVec3 = world.translation - camera.eye;
            let model = glam::DMat4::from_cols(
                linear.x_axis.extend(0.0),
                linear.y_axis.extend(0.0),
                linear.z_axis.extend(0.0),
                translation.extend(1.0),
            )
            .as_mat4();
            let n = normal.as_mat3();
            let record = |material: u32| Draw {
                model: model.to_cols_array_2d(),
                normal: [
                    n.x_axis.extend(0.0).to_array(),
                    n.y_axis.extend(0.0).to_array(),
                    n.z_axis.extend(0.0).to_array(),
                ],
                material,
                instance: instance as u32,
                pad: [0; 2],
            };
            let (seg_first, seg_count) = mesh_segments[mesh];
            if seg_count > 0 {
                edge_calls.push(EdgeCall {
                    first: seg_first,
                    count: seg_count,
                    draw: draws.len() as u32,
                });
                // The instance's own record, whatever its primitives.
                draws.push(record(default_material));
            }
            for &(first, count, material) in &starts[mesh] {
                if count == 0 {
                    continue;
                }
                let material = material
                    .filter(|&m| m < scene.materials.len())
                    .map_or(default_material, |m| m as u32);
                calls.push(DrawCall {
                    mesh,
                    first,
                    count,
                    draw: draws.len() as u32,
                });
                draws.push(record(material));
            }
        }
        if draws.is_empty() {
            // Storage bindings may not be empty.
            draws.push(Draw::default());
        }
        GpuScene {
            vertices,
            indices,
            draws: buffer(
                device,
                "draws",
                bytemuck::cast_slice(&draws),
                wgpu::BufferUsages::STORAGE,
            ),
            materials: buffer(
                device,
                "materials",
                bytemuck::cast_slice(&materials),
                wgpu::BufferUsages::STORAGE,
            ),
            calls,
            segments: buffer(
                device,
                "segments",
                bytemuck::cast_slice(&segments),
                wgpu::BufferUsages::STORAGE,
            ),
            edge_calls,
        }
    }
}

/// A buffer initialised with `bytes` (at least 4 bytes, as wgpu requires non-empty buffers).
fn buffer(
    device: &wgpu::Device,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let padded;
    let contents = if bytes.is_empty() {
        padded = [0u8; 16];
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
