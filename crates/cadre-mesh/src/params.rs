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

impl MeshParams {
    /// Tolerances of a deflection `relative` to `model`'s diagonal
    /// ([`crate::deflection_diagonal`]) and an `angle` in radians, as `cadre mesh
    /// --deflection-rel` resolves them.
    pub fn relative(model: &cadre_brep::Model, relative: f64, angle: f64) -> MeshParams {
        MeshParams {
            deflection: Deflection::Relative(relative).resolve(crate::deflection_diagonal(model)),
            angle,
            ..MeshParams::default()
        }
    }
}

/// The finest deflection a relative one resolves to, in mm: the kernel's accuracy
/// (`Accuracy::default().distance`).
pub const MIN_RELATIVE_DEFLECTION: f64 = 1e-7;

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
                // Never finer than the kernel's accuracy: a degenerate box (a model whose
                // extent is not known from its vertices) must not ask for a deflection no
                // geometry is exact to, which only runs refinement into its point budget.
                (r * diag).max(MIN_RELATIVE_DEFLECTION)
            }
        }
    }
}

#[cfg(test)]
mod floor_tests {
    use super::{Deflection, MIN_RELATIVE_DEFLECTION};

    /// A relative deflection of a degenerate diagonal stops at the kernel's accuracy; an
    /// ordinary one is untouched, and an absolute one is the user's to choose.
    #[test]
    fn relative_deflection_is_never_finer_than_the_accuracy() {
        let r = Deflection::Relative(0.001);
        assert_eq!(r.resolve(5e-15), MIN_RELATIVE_DEFLECTION);
        assert_eq!(r.resolve(100.0), 0.1);
        assert_eq!(Deflection::Absolute(1e-9).resolve(5e-15), 1e-9);
        assert_eq!(
            MIN_RELATIVE_DEFLECTION,
            cadre_geom::Accuracy::default().distance
        );
    }
}
