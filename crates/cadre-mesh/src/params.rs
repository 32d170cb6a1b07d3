//! Tessellation tolerances, named like OCCT's `BRepMesh_IncrementalMesh` parameters.

/// How finely to tessellate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshParams {
    /// Largest allowed distance between a triangle (or edge segment) and the exact surface
    /// (curve), in model units (mm). Always absolute here; see [`Deflection`] for the relative
    /// form the command line accepts.
    pub deflection: f64,
    /// Largest allowed angle, in radians, between the exact normals at the corners of a
    /// triangle (and between the tangents at the ends of an edge segment).
    pub angle: f64,
    /// Upper bound on the points one face may receive, so a pathological face cannot exhaust
    /// memory; a face that reaches it is meshed coarser and reported.
    pub max_face_points: usize,
}

impl Default for MeshParams {
    /// 0.01 mm and 0.5 rad, OCCT's usual angular setting.
    fn default() -> Self {
        Self {
            deflection: 0.01,
            angle: 0.5,
            max_face_points: 500_000,
        }
    }
}

/// Linear deflection as given by a user: absolute, or relative to the model's bounding-box
/// diagonal (OCCT's "relative" mode, e.g. 0.001 × diagonal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Deflection {
    /// Millimetres.
    Absolute(f64),
    /// Fraction of the bounding-box diagonal.
    Relative(f64),
}

impl Deflection {
    /// The absolute deflection for a model whose bounding-box diagonal is `diagonal`.
    /// A degenerate (zero or non-finite) diagonal falls back to 1 mm so the result is usable.
    pub fn resolve(self, diagonal: f64) -> f64 {
        match self {
            Deflection::Absolute(d) => d,
            Deflection::Relative(r) => {
                let diag = if diagonal.is_finite() && diagonal > 0.0 {
                    diagonal
                } else {
                    1.0
                };
                r * diag
            }
        }
    }
}
