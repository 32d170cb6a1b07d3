//! Triangle meshes that a file carries as tessellated geometry (AP242
//! `TRIANGULATED_FACE`, `COMPLEX_TRIANGULATED_FACE`, `…_SURFACE_SET`).

use cadre_geom::{BoundingBox, Vec3};

/// An indexed triangle mesh in model units (mm).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals when the file gives them (same length as `positions`), else empty.
    pub normals: Vec<Vec3>,
    /// Counter-clockwise triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// How many faces of the file this mesh stands for (one per tessellated face), so counts
    /// match what a CAD kernel reports.
    pub face_count: u32,
    /// Shells this item stands for (1 for a `TESSELLATED_SHELL` or `…_SOLID`).
    pub shell_count: u32,
    /// Solids this item stands for (1 for a `TESSELLATED_SOLID`).
    pub solid_count: u32,
    /// Index of the first triangle of each tessellated face, so faces stay identifiable.
    pub face_starts: Vec<u32>,
    /// STEP instance id of the tessellated item.
    pub step_id: u64,
}

impl TriangleMesh {
    /// Box of the positions.
    pub fn bbox(&self) -> BoundingBox {
        BoundingBox::from_points(self.positions.iter().copied())
    }
}
