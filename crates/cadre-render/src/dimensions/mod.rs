//! Persistent 3D dimensions: the viewer's measurements kept beside the model file and drawn
//! by the renderer (in the viewer and headless, `cadre render --dimensions`), on top of the
//! model, each as its kind is drawn ([`shape`]): a distance as a dimension line with an
//! arrowhead at each end, an edge's length along the edge, a radius from the centre (with a
//! centre mark) to the circle, an angle as an arc between its legs; the value in a box.
//!
//! They are kept in `FILE.dimensions.json` beside the model (`{"dimensions": [{"kind",
//! "value", "text", "points"}]}`), written by the viewer when a measurement is added or
//! deleted and read when the model opens again.

use crate::lines::{Cap, Hidden, Join, LineSet, LineStyle, LineWidth, Polyline, Stipple};
use crate::text::{Fill, Label, LabelSet, TextAnchor, TextDepth};
use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};

pub mod shape;

/// Colour of dimensions (sRGB): the orange-brown of measurement annotations.
pub const DIMENSION_COLOUR: [f32; 4] = [0.72, 0.33, 0.02, 1.0];

/// One dimension.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Dimension {
    /// What was measured: `distance`, `length`, `radius` or `angle`.
    pub kind: String,
    /// The value: mm, or radians for an angle.
    pub value: f64,
    /// The text drawn (e.g. `10.000 mm`).
    pub text: String,
    /// World points it is drawn through, as its kind keeps them ([`shape`]); none: listed
    /// only.
    pub points: Vec<[f64; 3]>,
}

/// The file of a model's dimensions.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DimensionFile {
    /// The dimensions, in the order made.
    pub dimensions: Vec<Dimension>,
}

/// Reading or writing a dimension file.
#[derive(Debug, thiserror::Error)]
pub enum DimensionFileError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not a dimension file.
    #[error("{path}: not a dimension file: {source}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, with its line and column.
        source: serde_json::Error,
    },
}

/// Where a model's dimensions are kept: `FILE.dimensions.json` beside `model`.
pub fn sidecar_path(model: &Path) -> PathBuf {
    let mut name = model.as_os_str().to_owned();
    name.push(".dimensions.json");
    PathBuf::from(name)
}

impl DimensionFile {
    /// Reads `path`; `Ok(None)` when there is no such file.
    pub fn read(path: &Path) -> Result<Option<DimensionFile>, DimensionFileError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => {
                return Err(DimensionFileError::Io {
                    path: path.to_path_buf(),
                    source,
                });
            }
        };
        Self::parse(&text)
            .map(Some)
            .map_err(|source| DimensionFileError::Format {
                path: path.to_path_buf(),
                source,
            })
    }

    /// Reads a dimension file's text (the error names its line and column).
    pub fn parse(text: &str) -> Result<DimensionFile, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// Writes `path` (removing it when there is no dimension left).
    pub fn write(&self, path: &Path) -> Result<(), DimensionFileError> {
        let io = |source| DimensionFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        if self.dimensions.is_empty() {
            return match std::fs::remove_file(path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(io(e)),
                _ => Ok(()),
            };
        }
        let text =
            serde_json::to_string_pretty(self).map_err(|source| DimensionFileError::Format {
                path: path.to_path_buf(),
                source,
            })?;
        std::fs::write(path, text).map_err(io)
    }
}

/// Colour of the selected dimension (sRGB).
pub const SELECTED_COLOUR: [f32; 4] = [0.05, 0.45, 0.9, 1.0];

/// Where dimension `d`'s label stands (`None`: it is not drawn).
fn label_point(d: &Dimension) -> Option<DVec3> {
    shape::shape(&d.kind, &d.points).label_at
}

/// The dimension whose label box holds output pixel `at` (x right, y down) of a `size`
/// view seen by `camera`, labels `text_height` pixels tall; the front-most when several do.
pub fn hit(
    dimensions: &[Dimension],
    camera: &crate::Camera,
    size: (u32, u32),
    text_height: f32,
    at: Vec2,
) -> Option<usize> {
    let (w, h) = (f64::from(size.0.max(1)), f64::from(size.1.max(1)));
    let to_clip = camera.projection_matrix(w / h)
        * camera.view_rotation()
        * glam::DMat4::from_translation(-camera.eye);
    let chain = cadre_text::FontChain::bundled();
    let per_em = text_height / chain.primary().cap_height;
    let margin = crate::text::BOX_MARGIN;
    let mut best: Option<(usize, f64)> = None;
    for (k, d) in dimensions.iter().enumerate() {
        let Some(p) = label_point(d) else { continue };
        let c = to_clip * p.extend(1.0);
        if c.w <= 0.0 {
            continue;
        }
        let anchor = Vec2::new(
            ((0.5 * c.x / c.w + 0.5) * w) as f32,
            ((0.5 - 0.5 * c.y / c.w) * h) as f32 - 1.2 * text_height,
        );
        let text = cadre_text::layout(
            chain,
            cadre_text::Shaper::bundled(),
            &d.text,
            (cadre_text::Align::Centre, cadre_text::Baseline::Middle),
            1.0,
        );
        // The box in pixels (em y up → pixels y down).
        let lo = anchor + Vec2::new(text.min.x - margin, -(text.max.y + margin)) * per_em;
        let hi = anchor + Vec2::new(text.max.x + margin, -(text.min.y - margin)) * per_em;
        let inside = at.x >= lo.x && at.x <= hi.x && at.y >= lo.y && at.y <= hi.y;
        let depth = c.z / c.w;
        if inside && best.is_none_or(|(_, z)| depth > z) {
            best = Some((k, depth));
        }
    }
    best.map(|(k, _)| k)
}

/// The lines, arrowheads and labels of `dimensions` (those with points to be drawn at,
/// [`shape`]), the `selected` one in [`SELECTED_COLOUR`].
pub fn overlay(
    dimensions: &[Dimension],
    text_height: f32,
    selected: Option<usize>,
) -> (LineSet, LabelSet) {
    let mut lines = LineSet {
        polylines: Vec::new(),
        styles: vec![LineStyle {
            colour: DIMENSION_COLOUR,
            width: LineWidth::Pixels(1.5),
            stipple: Stipple::SOLID,
            join: Join::Bevel,
            cap: Cap::Butt,
            hidden: Hidden::Show,
            follows_view: false,
        }],
    };
    lines.styles.push(LineStyle {
        colour: SELECTED_COLOUR,
        width: LineWidth::Pixels(2.5),
        ..lines.styles[0]
    });
    let mut labels = LabelSet::default();
    for (k, d) in dimensions.iter().enumerate() {
        let chosen = selected == Some(k);
        let colour = if chosen {
            SELECTED_COLOUR
        } else {
            DIMENSION_COLOUR
        };
        let drawn = shape::shape(&d.kind, &d.points);
        let Some(middle) = drawn.label_at else {
            continue;
        };
        for points in drawn.lines {
            lines.polylines.push(Polyline {
                points,
                style: u32::from(chosen),
                colours: Vec::new(),
            });
        }
        // Arrowheads 3 × 1 in shape.
        for arrow in drawn.arrows {
            let back = arrow.tip - arrow.pointing * arrow.length;
            let half = arrow.side * arrow.length / 6.0;
            labels.fills.push(Fill {
                corners: [arrow.tip, back + half, back - half],
                colour,
                depth: TextDepth::OnTop,
            });
        }
        let mut label = Label::billboard(d.text.clone(), middle, text_height);
        label.anchor = TextAnchor::Billboard {
            point: middle,
            offset: Vec2::new(0.0, -1.2 * text_height),
        };
        label.align = cadre_text::Align::Centre;
        label.colour = colour;
        label.background = Some([1.0, 1.0, 1.0, 0.85]);
        labels.labels.push(label);
    }
    (lines, labels)
}

/// The short text a dimension is drawn with: its value and unit.
pub fn value_text(kind: &str, value: f64) -> String {
    match kind {
        "angle" => format!("{:.3}°", value.to_degrees()),
        "radius" => format!("R{value:.3} mm"),
        _ => format!("{value:.3} mm"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dimensions_survive_their_file_and_draw_a_line_two_arrows_and_a_label() {
        let file = DimensionFile {
            dimensions: vec![
                Dimension {
                    kind: "distance".into(),
                    value: 10.0,
                    text: value_text("distance", 10.0),
                    points: vec![[0.0, 0.0, 0.0], [0.0, 0.0, 10.0]],
                },
                Dimension {
                    kind: "radius".into(),
                    value: 2.5,
                    text: value_text("radius", 2.5),
                    points: Vec::new(),
                },
            ],
        };
        let dir = std::env::temp_dir().join(format!("cadre-dimensions-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let model = dir.join("part.step");
        let path = sidecar_path(&model);
        assert!(
            path.to_string_lossy()
                .ends_with("part.step.dimensions.json")
        );
        assert_eq!(DimensionFile::read(&path).expect("readable"), None);
        file.write(&path).expect("written");
        assert_eq!(
            DimensionFile::read(&path).expect("readable"),
            Some(file.clone())
        );
        std::fs::write(&path, "{\"dimensions\": [{\"kind\": 3}]}").expect("written");
        let err = DimensionFile::read(&path).expect_err("refused").to_string();
        assert!(
            err.contains("not a dimension file") && err.contains("line 1"),
            "{err}"
        );
        DimensionFile::default().write(&path).expect("removed");
        assert!(!path.exists());
        let _ = std::fs::remove_dir_all(&dir);

        let (lines, labels) = overlay(&file.dimensions, 11.0, None);
        assert_eq!(lines.polylines.len(), 1);
        assert_eq!(lines.polylines[0].style, 0);
        let (chosen, chosen_labels) = overlay(&file.dimensions, 11.0, Some(0));
        assert_eq!(chosen.polylines[0].style, 1);
        assert_eq!(chosen_labels.labels[0].colour, SELECTED_COLOUR);
        assert!(!lines.styles[0].follows_view);
        assert_eq!(labels.fills.len(), 2, "an arrowhead at each end");
        assert_eq!(
            labels.labels.len(),
            1,
            "the radius has no points to draw at"
        );
        assert_eq!(labels.labels[0].text, "10.000 mm");
        // The arrowheads point at the ends: each tip is an end point.
        assert_eq!(labels.fills[0].corners[0], DVec3::ZERO);
        assert_eq!(labels.fills[1].corners[0], DVec3::new(0.0, 0.0, 10.0));
        assert_eq!(value_text("angle", std::f64::consts::FRAC_PI_2), "90.000°");
    }

    #[test]
    fn a_click_on_a_dimensions_label_finds_it() {
        // Looking down at z = 0, 100 units on 200 pixels: the label of the line from
        // (−20, 0) to (20, 0) stands at pixel (100, 100 − 1.2 × 12).
        let camera = crate::Camera {
            eye: DVec3::new(0.0, 0.0, 50.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            projection: crate::Projection::Orthographic { height: 100.0 },
            near: 1.0,
            far: 100.0,
        };
        let dims = vec![
            Dimension {
                kind: "distance".into(),
                value: 40.0,
                text: "40.000 mm".into(),
                points: vec![[-20.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
            },
            Dimension {
                kind: "distance".into(),
                value: 10.0,
                text: "10.000 mm".into(),
                points: vec![[-20.0, -40.0, 0.0], [-10.0, -40.0, 0.0]],
            },
        ];
        let hit_at = |x, y| hit(&dims, &camera, (200, 200), 12.0, Vec2::new(x, y));
        assert_eq!(hit_at(100.0, 85.6), Some(0));
        assert_eq!(hit_at(70.0, 165.6), Some(1));
        // Negative controls: beside the box, and far away.
        assert_eq!(hit_at(100.0, 110.0), None);
        assert_eq!(hit_at(190.0, 10.0), None);
    }
}
