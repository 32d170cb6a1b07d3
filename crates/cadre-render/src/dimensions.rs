//! Persistent 3D dimensions: the viewer's measurements kept beside the model file and drawn
//! by the renderer (in the viewer and headless, `cadre render --dimensions`): a dimension
//! line between its two points with an arrowhead at each end, and its value in a box at the
//! middle, on top of the model.
//!
//! They are kept in `FILE.dimensions.json` beside the model (`{"dimensions": [{"kind",
//! "value", "text", "points"}]}`), written by the viewer when a measurement is added or
//! deleted and read when the model opens again.

use crate::lines::{Cap, Hidden, Join, LineSet, LineStyle, LineWidth, Polyline, Stipple};
use crate::text::{Fill, Label, LabelSet, TextAnchor, TextDepth};
use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};

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
    /// World points the dimension line joins (none: drawn in the list only).
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
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|source| DimensionFileError::Format {
                path: path.to_path_buf(),
                source,
            })
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

/// The lines, arrowheads and labels of `dimensions` (those with two finite points).
pub fn overlay(dimensions: &[Dimension], text_height: f32) -> (LineSet, LabelSet) {
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
    let mut labels = LabelSet::default();
    for d in dimensions {
        let [a, b] = match d.points[..] {
            [a, b] => [DVec3::from(a), DVec3::from(b)],
            _ => continue,
        };
        if !(a.is_finite() && b.is_finite()) {
            continue;
        }
        let length = a.distance(b);
        let middle = 0.5 * (a + b);
        if length > 0.0 {
            lines.polylines.push(Polyline {
                points: vec![a, b],
                style: 0,
                colours: Vec::new(),
            });
            // Arrowheads a twelfth of the line long (3 × 1 in shape), in the plane of the
            // line and the world axis least along it.
            let along = (b - a) / length;
            let axis = [DVec3::X, DVec3::Y, DVec3::Z]
                .into_iter()
                .min_by(|p, q| along.dot(*p).abs().total_cmp(&along.dot(*q).abs()))
                .unwrap_or(DVec3::Z);
            let side = along.cross(axis).normalize_or(DVec3::Z);
            let size = length / 12.0;
            for (tip, dir) in [(a, along), (b, -along)] {
                let back = tip + dir * size;
                labels.fills.push(Fill {
                    corners: [tip, back + side * size / 6.0, back - side * size / 6.0],
                    colour: DIMENSION_COLOUR,
                    depth: TextDepth::OnTop,
                });
            }
        }
        let mut label = Label::billboard(d.text.clone(), middle, text_height);
        label.anchor = TextAnchor::Billboard {
            point: middle,
            offset: Vec2::new(0.0, -1.2 * text_height),
        };
        label.align = cadre_text::Align::Centre;
        label.colour = DIMENSION_COLOUR;
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

        let (lines, labels) = overlay(&file.dimensions, 11.0);
        assert_eq!(lines.polylines.len(), 1);
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
}
