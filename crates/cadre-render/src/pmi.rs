//! A model's product manufacturing information drawn over it: graphic annotations as
//! polylines of the lines pass (their curve style's width in model units, at least a
//! pixel), filled areas and texts by the text pass, and saved views as cameras.
//!
//! PMI is drawn on top of the part, as CAD systems show it in their saved views (an
//! annotation plane often cuts through the part it annotates). A colour too close to the
//! background (the NIST files draw their PMI in white) is replaced by [`PMI_COLOUR`], and
//! the replacement counted, so a PMI view on a white page stays readable.

use crate::lines::{Cap, Hidden, Join, LineSet, LineStyle, LineWidth, Polyline, Stipple};
use crate::text::{Fill, Label, LabelSet, TextDepth};
use crate::{Camera, Projection};
use cadre_brep::pmi::{Pmi, SavedView};
use glam::DVec3;

/// Colour of annotations whose own colour would not show on the background (sRGB): the
/// dark blue engineering drawings use for PMI.
pub const PMI_COLOUR: [f32; 4] = [0.05, 0.15, 0.55, 1.0];

/// Width of annotation curves whose style gives none: ISO 128's thin line, 0.13 mm (on
/// screen at least a pixel: the lines pass keeps one).
const DEFAULT_WIDTH: f64 = 0.13;

/// The overlay of some of a model's annotations.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PmiOverlay {
    /// Their polylines.
    pub lines: LineSet,
    /// Their filled areas and texts.
    pub labels: LabelSet,
    /// How many annotations are drawn.
    pub annotations: usize,
    /// How many of them had their colour replaced for contrast with the background.
    pub recoloured: usize,
}

/// Whether two sRGB colours are too close to tell apart (luminance within 0.15).
fn too_close(a: [f32; 3], b: [f32; 4]) -> bool {
    let luminance = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    (luminance(a) - luminance([b[0], b[1], b[2]])).abs() < 0.15
}

/// The overlay of `pmi`'s annotations (those of `view` only, when given) on a `background`
/// (sRGB): one line style per annotation (its width and colour), its fills and texts.
pub fn overlay(pmi: &Pmi, view: Option<&SavedView>, background: [f32; 4]) -> PmiOverlay {
    let shown: Vec<usize> = match view {
        Some(v) => v.annotations.clone(),
        None => (0..pmi.annotations.len()).collect(),
    };
    let mut out = PmiOverlay::default();
    for k in shown {
        let Some(a) = pmi.annotations.get(k) else {
            continue;
        };
        let own = a.colour.map(|c| [c.r, c.g, c.b]);
        let colour = match own {
            Some(c) if !too_close(c, background) => [c[0], c[1], c[2], 1.0],
            Some(_) => {
                out.recoloured += 1;
                PMI_COLOUR
            }
            None => PMI_COLOUR,
        };
        let style = out.lines.styles.len() as u32;
        out.lines.styles.push(LineStyle {
            colour,
            width: LineWidth::World(a.width.filter(|w| *w > 0.0).unwrap_or(DEFAULT_WIDTH)),
            stipple: Stipple::SOLID,
            join: Join::Round,
            cap: Cap::Round,
            hidden: Hidden::Show,
        });
        for line in &a.polylines {
            out.lines.polylines.push(Polyline {
                points: line.iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect(),
                style,
                colours: Vec::new(),
            });
        }
        let point = |p: cadre_geom::Vec3| DVec3::new(p.x, p.y, p.z);
        out.labels.fills.extend(a.fills.iter().map(|t| Fill {
            corners: t.map(point),
            colour,
            depth: TextDepth::OnTop,
        }));
        for t in &a.texts {
            let mut label = Label::in_plane(
                t.text.clone(),
                point(t.origin),
                (point(t.x_axis), point(t.y_axis)),
                t.height,
            );
            label.colour = colour;
            label.depth = TextDepth::OnTop;
            out.labels.labels.push(label);
        }
        out.annotations += 1;
    }
    out
}

/// The camera of a saved view for an image of `aspect`: the view's direction and up, its
/// projection (parallel or central), fitted to the box `lo`..`hi` (the part and the view's
/// annotations). The file's view window is not kept: files write a window of their own
/// page size (1 m for the NIST views of a 300 mm part), which would show the part small and
/// off centre.
pub fn saved_view_camera(view: &SavedView, (lo, hi): (DVec3, DVec3), aspect: f64) -> Camera {
    let v = |p: cadre_geom::Vec3| DVec3::new(p.x, p.y, p.z);
    // The view looks along its direction: the eye is on the other side.
    let to_eye = -v(view.direction);
    let camera = Camera::fit_along(lo, hi, (to_eye, v(view.up)), view.parallel, aspect);
    debug_assert!(matches!(
        (camera.projection, view.parallel),
        (Projection::Orthographic { .. }, true) | (Projection::Perspective { .. }, false)
    ));
    camera
}

/// The box of a set of annotations' geometry.
pub fn overlay_bounds(overlay: &PmiOverlay) -> Option<(DVec3, DVec3)> {
    [overlay.lines.bounds(), overlay.labels.bounds()]
        .into_iter()
        .flatten()
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_brep::pmi::{Annotation, AnnotationKind};
    use cadre_brep::style::Rgb;
    use cadre_geom::Vec3;

    fn annotation(colour: Option<Rgb>) -> Annotation {
        Annotation {
            step_id: 7,
            name: "Flatness.1".into(),
            kind: AnnotationKind::Tessellated,
            polylines: vec![vec![Vec3::ZERO, Vec3::X], vec![Vec3::Y, Vec3::ONE, Vec3::Z]],
            fills: vec![[Vec3::ZERO, Vec3::X, Vec3::Y]],
            texts: Vec::new(),
            width: Some(0.13),
            colour,
            plane: None,
            faces: Vec::new(),
            semantic: None,
            tessellated: true,
        }
    }

    #[test]
    fn annotations_become_styled_polylines_and_fills_and_white_on_white_is_recoloured() {
        let pmi = Pmi {
            annotations: vec![
                annotation(Some(Rgb::new(1.0, 1.0, 1.0))),
                annotation(Some(Rgb::new(1.0, 0.0, 0.0))),
                annotation(None),
            ],
            ..Pmi::default()
        };
        let white = [1.0, 1.0, 1.0, 1.0];
        let out = overlay(&pmi, None, white);
        assert_eq!(out.annotations, 3);
        assert_eq!(out.lines.polylines.len(), 6);
        assert_eq!(out.lines.styles.len(), 3);
        assert_eq!(out.labels.fills.len(), 3);
        assert_eq!(out.recoloured, 1);
        assert_eq!(out.lines.styles[0].colour, PMI_COLOUR);
        assert_eq!(out.lines.styles[1].colour, [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(out.lines.styles[0].width, LineWidth::World(0.13));
        // On black, white is kept.
        let on_black = overlay(&pmi, None, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(on_black.recoloured, 0);
        assert_eq!(on_black.lines.styles[0].colour, [1.0, 1.0, 1.0, 1.0]);
        // A saved view shows its own annotations only.
        let view = SavedView {
            step_id: 1,
            name: "MBD_A".into(),
            origin: Vec3::ZERO,
            direction: -Vec3::Z,
            up: Vec3::Y,
            parallel: true,
            eye: Vec3::ZERO,
            window: (100.0, 100.0),
            window_centre: Vec3::ZERO,
            view_plane_distance: 1.0,
            front_clip: None,
            back_clip: None,
            clip_planes: Vec::new(),
            annotations: vec![1],
        };
        let one = overlay(&pmi, Some(&view), white);
        assert_eq!(one.annotations, 1);
        assert_eq!(one.lines.styles[0].colour, [1.0, 0.0, 0.0, 1.0]);
        // Looking along −z: the eye is above, +y up.
        let camera = saved_view_camera(&view, (DVec3::splat(-1.0), DVec3::splat(1.0)), 1.0);
        assert!(camera.eye.z > camera.target.z);
        assert!(camera.is_orthographic());
    }
}
