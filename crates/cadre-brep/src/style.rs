//! Presentation: colours and transparency from STEP styled items.

/// A colour with components in [0, 1], as STEP's `COLOUR_RGB` gives them (sRGB-encoded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
}

impl Rgb {
    /// Builds a colour, clamping each component into [0, 1] (non-finite becomes 0).
    pub fn new(r: f64, g: f64, b: f64) -> Self {
        let c = |x: f64| {
            if x.is_finite() {
                x.clamp(0.0, 1.0) as f32
            } else {
                0.0
            }
        };
        Self {
            r: c(r),
            g: c(g),
            b: c(b),
        }
    }

    /// The colour of a STEP `DRAUGHTING_PRE_DEFINED_COLOUR` name (ISO 10303-46 list).
    pub fn predefined(name: &str) -> Option<Self> {
        let (r, g, b) = match name.to_ascii_lowercase().as_str() {
            "red" => (1.0, 0.0, 0.0),
            "green" => (0.0, 1.0, 0.0),
            "blue" => (0.0, 0.0, 1.0),
            "yellow" => (1.0, 1.0, 0.0),
            "magenta" => (1.0, 0.0, 1.0),
            "cyan" => (0.0, 1.0, 1.0),
            "black" => (0.0, 0.0, 0.0),
            "white" => (1.0, 1.0, 1.0),
            _ => return None,
        };
        Some(Self::new(r, g, b))
    }
}

/// The appearance assigned to a solid, shell, face or part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Style {
    /// Surface colour, `None` when not given.
    pub color: Option<Rgb>,
    /// Transparency in [0, 1] (0 opaque), from `SURFACE_STYLE_TRANSPARENT`.
    pub transparency: f32,
    /// Curve colour for edges and wires, when given.
    pub curve_color: Option<Rgb>,
    /// Whether the item is hidden (`INVISIBILITY`).
    pub invisible: bool,
}

impl Style {
    /// Fills the fields this style lacks from `under` (a style given at a coarser level).
    pub fn over(self, under: Style) -> Style {
        Style {
            color: self.color.or(under.color),
            transparency: if self.color.is_some() || self.transparency > 0.0 {
                self.transparency
            } else {
                under.transparency
            },
            curve_color: self.curve_color.or(under.curve_color),
            invisible: self.invisible || under.invisible,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finer_style_wins_and_inherits_missing_fields() {
        let face = Style {
            color: Some(Rgb::new(1.0, 0.0, 0.0)),
            ..Style::default()
        };
        let solid = Style {
            color: Some(Rgb::new(0.0, 0.0, 1.0)),
            transparency: 0.5,
            curve_color: Some(Rgb::new(0.0, 1.0, 0.0)),
            invisible: false,
        };
        let s = face.over(solid);
        assert_eq!(s.color, face.color);
        assert_eq!(s.curve_color, solid.curve_color);
        // A face that sets its own colour sets its own (opaque) transparency too.
        assert_eq!(s.transparency, 0.0);
        let bare = Style::default().over(solid);
        assert_eq!(bare.transparency, 0.5);
    }

    #[test]
    fn colours_are_clamped_and_predefined_names_known() {
        let c = Rgb::new(2.0, -1.0, f64::NAN);
        assert_eq!((c.r, c.g, c.b), (1.0, 0.0, 0.0));
        assert_eq!(Rgb::predefined("Yellow"), Some(Rgb::new(1.0, 1.0, 0.0)));
        assert_eq!(Rgb::predefined("chartreuse"), None);
    }
}
