//! Units of a representation context, as read from STEP.

/// A representation context's units. Geometry is converted to millimetres and radians when
/// mapped; these values say what the file used.
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// Millimetres per file length unit (1 for mm, 25.4 for inch, 1000 for metre).
    pub length_to_mm: f64,
    /// Name of the length unit, e.g. `"mm"`, `"inch"`.
    pub length_name: String,
    /// Radians per file plane-angle unit (1 for radian, π/180 for degree).
    pub angle_to_rad: f64,
    /// Name of the plane-angle unit, e.g. `"radian"`, `"degree"`.
    pub angle_name: String,
    /// Distance uncertainty in mm, when the context declares one.
    pub uncertainty_mm: Option<f64>,
}

impl Default for Units {
    /// Millimetres and radians: what ISO 10303 assumes when a context says nothing.
    fn default() -> Self {
        Self {
            length_to_mm: 1.0,
            length_name: "mm".into(),
            angle_to_rad: 1.0,
            angle_name: "radian".into(),
            uncertainty_mm: None,
        }
    }
}
