//! Accuracy passed explicitly to geometric algorithms.

/// How accurately an algorithm must answer: an absolute distance in model units (mm) and the
/// number of iterations allowed to reach it.
///
/// [`Accuracy::default`] is 1e-7 mm (OCCT's `Precision::Confusion`) with 32 Newton iterations,
/// which suits parts from micrometres to tens of metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accuracy {
    /// Distance below which two points are the same point (model units).
    pub distance: f64,
    /// Maximum iterations for iterative methods (Newton, subdivision).
    pub max_iterations: u32,
}

impl Default for Accuracy {
    fn default() -> Self {
        Self {
            distance: 1e-7,
            max_iterations: 32,
        }
    }
}

impl Accuracy {
    /// An accuracy of `distance` model units with the default iteration budget.
    pub fn new(distance: f64) -> Self {
        Self {
            distance,
            ..Self::default()
        }
    }
}
