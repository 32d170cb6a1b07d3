//! A model's product manufacturing information drawn over it: graphic annotations as
//! polylines of the lines pass (their curve style's width in model units, at least a
//! pixel), filled areas and texts by the text pass, and saved views as cameras.
//!
//! PMI is drawn on top of the part, as CAD systems show it in their saved views (an
//! annotation plane often cuts through the part it annotates). A colour too close to the
//! background (the NIST files draw their PMI in white) is replaced by [`PMI_COLOUR`], and
//! the replacement counted, so a PMI view on a white page stays readable.

use crate::lines::{Cap, Hidden, Join, LineSet, LineStyle, LineWidth, Polyline, Stipple};
use crate::text::leaders::{CalloutStyle, PartAnchor};
use crate::text::{Fill, Label, LabelSet, TextDepth};
use crate::{Camera, Projection, SectionPlane};
use cadre_brep::FaceId;
use cadre_brep::pmi::{DimensionKind, Pmi, SavedView, SemanticItem};
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

/// Where each part is placed in the world: an annotation in a part's coordinates is drawn
/// once per placement of that part (PMI belongs to the part: every bolt of an assembly
/// shows its tolerances).
#[derive(Clone, Debug, Default)]
pub struct Placements {
    of_part: std::collections::HashMap<cadre_brep::PartId, Vec<glam::DAffine3>>,
}

impl Placements {
    /// The placements of every part of `model` (one per path from a root).
    pub fn of(model: &cadre_brep::Model) -> Placements {
        let mut of_part: std::collections::HashMap<_, Vec<_>> = Default::default();
        model.visit_instances(|v| {
            of_part.entry(v.part).or_default().push(v.transform);
        });
        Placements { of_part }
    }

    /// The placements of `part`: the identity for none (world coordinates) or a part never
    /// placed (its own coordinates).
    pub fn get(&self, part: Option<cadre_brep::PartId>) -> Vec<glam::DAffine3> {
        part.and_then(|p| self.of_part.get(&p))
            .filter(|v| !v.is_empty())
            .cloned()
            .unwrap_or_else(|| vec![glam::DAffine3::IDENTITY])
    }
}

/// The overlay of `pmi`'s annotations (those of `view` only, when given) on a `background`
/// (sRGB), each drawn at every placement of its part: one line style per annotation (its
/// width and colour), its fills and texts.
pub fn overlay(
    pmi: &Pmi,
    view: Option<&SavedView>,
    background: [f32; 4],
    placements: &Placements,
) -> PmiOverlay {
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
            follows_view: false,
        });
        for placement in placements.get(a.part) {
            let point = |p: cadre_geom::Vec3| placement.transform_point3(DVec3::new(p.x, p.y, p.z));
            let vector =
                |p: cadre_geom::Vec3| placement.transform_vector3(DVec3::new(p.x, p.y, p.z));
            for line in &a.polylines {
                out.lines.polylines.push(Polyline {
                    points: line.iter().map(|p| point(*p)).collect(),
                    style,
                    colours: Vec::new(),
                });
            }
            out.labels.fills.extend(a.fills.iter().map(|t| Fill {
                corners: t.map(point),
                colour,
                depth: TextDepth::OnTop,
            }));
            for t in &a.texts {
                let mut label = Label::in_plane(
                    t.text.clone(),
                    point(t.origin),
                    (vector(t.x_axis), vector(t.y_axis)),
                    t.height,
                );
                label.colour = colour;
                label.depth = TextDepth::OnTop;
                label.align = match t.alignment.horizontal {
                    1 => cadre_text::Align::Centre,
                    2 => cadre_text::Align::Right,
                    _ => cadre_text::Align::Left,
                };
                label.baseline = match t.alignment.vertical {
                    1 => cadre_text::Baseline::Top,
                    2 => cadre_text::Baseline::Middle,
                    3 => cadre_text::Baseline::Bottom,
                    _ => cadre_text::Baseline::Alphabetic,
                };
                out.labels.labels.push(label);
            }
        }
        out.annotations += 1;
    }
    out
}

/// The GD&T symbol of a geometric tolerance's entity type (ASME Y14.5 / ISO 1101).
pub fn tolerance_symbol(kind: &str) -> &'static str {
    match kind {
        "FLATNESS_TOLERANCE" => "⏥",
        "STRAIGHTNESS_TOLERANCE" => "⏤",
        "ROUNDNESS_TOLERANCE" => "○",
        "CYLINDRICITY_TOLERANCE" => "⌭",
        "LINE_PROFILE_TOLERANCE" => "⌒",
        "SURFACE_PROFILE_TOLERANCE" => "⌓",
        "ANGULARITY_TOLERANCE" => "∠",
        "PERPENDICULARITY_TOLERANCE" => "⟂",
        "PARALLELISM_TOLERANCE" => "∥",
        "POSITION_TOLERANCE" => "⌖",
        "CONCENTRICITY_TOLERANCE" | "COAXIALITY_TOLERANCE" => "◎",
        "SYMMETRY_TOLERANCE" => "⌯",
        "CIRCULAR_RUNOUT_TOLERANCE" => "↗",
        "TOTAL_RUNOUT_TOLERANCE" => "⌰",
        _ => "?",
    }
}

/// A length or deviation as drawings write it: up to four decimals, no trailing zeros.
fn number(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.replace('-', "−")
    }
}

/// The text a semantic item is drawn with when the file gives it no presentation: a
/// dimension's value with its symbol and deviations, a tolerance's feature-control frame
/// (symbol, value, datums between bars), a datum's letter.
pub fn semantic_text(item: &SemanticItem) -> String {
    match item {
        SemanticItem::Dimension {
            name,
            value,
            limits,
            tolerance,
            kind,
            ..
        } => {
            let lower = name.to_lowercase();
            let angular = lower.contains("angle") || lower.contains("angular");
            let show = |v: f64| {
                if angular {
                    format!("{}°", number(v.to_degrees()))
                } else {
                    number(v)
                }
            };
            // The symbol before the value (ISO 129): diameter, radius.
            let symbol = if lower.contains("diameter") || lower.contains("diametral") {
                "⌀"
            } else if lower.contains("radius") || lower.contains("radial") {
                "R"
            } else {
                ""
            };
            let mut text = match (value, limits) {
                (Some(v), _) => format!("{symbol}{}", show(*v)),
                // A limits dimension: lower–upper.
                (None, Some((lo, hi))) => format!("{symbol}{}–{}", show(*lo), show(*hi)),
                (None, None) => match kind {
                    DimensionKind::Size => format!("size ({name})"),
                    DimensionKind::Location => format!("location ({name})"),
                },
            };
            match tolerance {
                Some((upper, lower)) if (upper + lower).abs() < 1e-12 => {
                    text += &format!(" ±{}", number(*upper));
                }
                Some((upper, lower)) => {
                    text += &format!(" +{}/{}", number(*upper), number(*lower));
                }
                None => {}
            }
            text
        }
        SemanticItem::Tolerance {
            kind,
            magnitude,
            datums,
            modifiers,
            zone,
            zone_values,
            ..
        } => {
            let mut cells = vec![tolerance_symbol(kind).to_string()];
            // The value cell: the zone's diameter sign, the value, its modifiers' symbols.
            let mut value = match zone.as_deref() {
                Some(z) if z.contains("spherical") => "S⌀".to_string(),
                Some(z) if z.contains("cylindrical") || z.contains("circular") => "⌀".into(),
                _ => String::new(),
            };
            value += &magnitude.map_or_else(|| "?".into(), number);
            if let Some(u) = zone_values.per_unit {
                value += &format!("/{}", number(u));
            }
            if let Some(d) = zone_values.unequally_disposed {
                value += &format!(" Ⓤ{}", number(d));
            }
            for symbol in modifiers
                .iter()
                .filter_map(|m| cadre_brep::pmi::modifier_symbol(m))
            {
                value.push(' ');
                value += symbol;
            }
            if let Some(l) = zone_values.projected {
                value += &format!(" Ⓟ{}", number(l));
            }
            if let Some(max) = zone_values.maximum {
                value += &format!(" ({} MAX)", number(max));
            }
            cells.push(value);
            cells.extend(datums.iter().filter(|d| !d.is_empty()).cloned());
            cells.join(" | ")
        }
        SemanticItem::Datum { label, .. } | SemanticItem::DatumTarget { label, .. } => {
            label.clone()
        }
    }
}

/// The camera of a saved view for an image of `aspect`: the view's direction and up, its
/// projection (parallel or central), fitted to the box `lo`..`hi` (the part and the view's
/// annotations). The file's view window is not kept: files write a window of their own
/// page size (1 m for the NIST views of a 300 mm part), which would show the part small and
/// off centre.
pub fn saved_view_camera(
    view: &SavedView,
    (lo, hi): (DVec3, DVec3),
    aspect: f64,
    placements: &Placements,
) -> Camera {
    // The camera's directions turn with the first placement of its part.
    let placement = placements.get(view.part)[0];
    let v = |p: cadre_geom::Vec3| placement.transform_vector3(DVec3::new(p.x, p.y, p.z));
    // The view looks along its direction: the eye is on the other side.
    let to_eye = -v(view.direction);
    let camera = Camera::fit_along(lo, hi, (to_eye, v(view.up)), view.parallel, aspect);
    debug_assert!(matches!(
        (camera.projection, view.parallel),
        (Projection::Orthographic { .. }, true) | (Projection::Perspective { .. }, false)
    ));
    camera
}

/// The anchors of the generated callouts of `model`'s semantic PMI without a presentation:
/// each item's text ([`semantic_text`]) and [`faces_anchor`] of its faces at the first
/// placement of their part (faces are in their part's coordinates), in the PMI style. Lay
/// them out for a view with [`crate::text::leaders::callout_labels`] (with the part names,
/// to keep the two sets of boxes apart).
pub fn semantic_anchors(model: &cadre_brep::Model, placements: &Placements) -> Vec<PartAnchor> {
    let face_part = cadre_brep::pmi::face_parts(model);
    anchors_of(&model.pmi, |faces| {
        let part = faces.first().and_then(|f| face_part.get(f).copied());
        Some(placements.get(part)[0].transform_point3(faces_anchor(model, faces)?))
    })
}

/// The callout anchors of the semantic items no annotation presents, each at the point
/// `anchor_of` gives for its faces (items whose faces give none are left out).
fn anchors_of(pmi: &Pmi, anchor_of: impl Fn(&[FaceId]) -> Option<DVec3>) -> Vec<PartAnchor> {
    let presented: std::collections::HashSet<usize> =
        pmi.annotations.iter().filter_map(|a| a.semantic).collect();
    let mut out = Vec::new();
    for (k, item) in pmi.semantic.items.iter().enumerate() {
        if presented.contains(&k) {
            continue;
        }
        let Some(point) = anchor_of(item.faces()) else {
            continue;
        };
        out.push(PartAnchor {
            name: semantic_text(item),
            point,
            style: CalloutStyle::PMI,
        });
    }
    out
}

/// Where a callout's leader points for `faces`: the point sampled on them (their edges, and
/// their surface where it bulges past its edges) nearest the centre of their box — on a face,
/// where the box's centre of a hole or a boss would be in the air. `None` without a face.
pub fn faces_anchor(model: &cadre_brep::Model, faces: &[FaceId]) -> Option<DVec3> {
    let mut total = cadre_geom::BoundingBox::EMPTY;
    let mut samples = Vec::new();
    for &f in faces {
        let face = model.faces.get(f.index())?;
        let (b, s) = cadre_brep::bounds::face_bounds(model, face, cadre_geom::Accuracy::default());
        total = total.union(&b);
        samples.extend(s);
    }
    if total.is_empty() {
        return None;
    }
    let c = 0.5 * (total.min + total.max);
    let nearest = samples
        .into_iter()
        .filter(|p| p.is_finite())
        .min_by(|a, b| {
            (*a - c)
                .length_squared()
                .total_cmp(&(*b - c).length_squared())
        })
        .unwrap_or(c);
    Some(DVec3::new(nearest.x, nearest.y, nearest.z))
}

/// The section planes that clip a saved view (`CAMERA_MODEL_D3_MULTI_CLIPPING`'s planes, in
/// world coordinates through the first placement of the view's part; the first
/// [`crate::MAX_SECTIONS`] of them are applied). Each cuts away the half-space its
/// plane's normal points to, as [`SectionPlane`] does: the one file in the corpus with a
/// clipped view (bug32745_pmi1, view `03`) looks along +y at a plane through the part whose
/// normal is −y, towards the camera, and only so does the view show the section it was saved
/// for rather than the outside of the near half.
pub fn saved_view_sections(view: &SavedView, placements: &Placements) -> Vec<SectionPlane> {
    let placement = placements.get(view.part)[0];
    view.clip_planes
        .iter()
        .map(|&(point, normal)| {
            let p = placement.transform_point3(DVec3::new(point.x, point.y, point.z));
            let n = placement.transform_vector3(DVec3::new(normal.x, normal.y, normal.z));
            SectionPlane::through(p, n)
        })
        .collect()
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
            part: None,
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
        let here = Placements::default();
        let out = overlay(&pmi, None, white, &here);
        assert_eq!(out.annotations, 3);
        assert_eq!(out.lines.polylines.len(), 6);
        assert_eq!(out.lines.styles.len(), 3);
        assert_eq!(out.labels.fills.len(), 3);
        assert_eq!(out.recoloured, 1);
        assert_eq!(out.lines.styles[0].colour, PMI_COLOUR);
        assert_eq!(out.lines.styles[1].colour, [1.0, 0.0, 0.0, 1.0]);
        assert_eq!(out.lines.styles[0].width, LineWidth::World(0.13));
        // On black, white is kept.
        let on_black = overlay(&pmi, None, [0.0, 0.0, 0.0, 1.0], &here);
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
            part: None,
            drawing: false,
        };
        let one = overlay(&pmi, Some(&view), white, &here);
        assert_eq!(one.annotations, 1);
        assert_eq!(one.lines.styles[0].colour, [1.0, 0.0, 0.0, 1.0]);
        // Looking along −z: the eye is above, +y up.
        let camera = saved_view_camera(&view, (DVec3::splat(-1.0), DVec3::splat(1.0)), 1.0, &here);
        assert!(camera.eye.z > camera.target.z);
        assert!(camera.is_orthographic());
    }

    #[test]
    fn a_saved_views_clipping_planes_cut_away_the_side_their_normal_points_to() {
        let view = SavedView {
            step_id: 1,
            name: "03".into(),
            origin: Vec3::new(0.0, -65.0, 0.0),
            direction: Vec3::Y,
            up: Vec3::Z,
            parallel: true,
            eye: Vec3::ZERO,
            window: (22.0, 22.0),
            window_centre: Vec3::ZERO,
            view_plane_distance: 65.0,
            front_clip: None,
            back_clip: None,
            clip_planes: vec![(Vec3::ZERO, -Vec3::Y)],
            annotations: Vec::new(),
            part: None,
            drawing: false,
        };
        let here = Placements::default();
        let cut = saved_view_sections(&view, &here);
        assert_eq!(cut.len(), 1);
        // The camera is on −y looking along +y: the near half goes, the far half stays.
        assert!(cut[0].keeps(DVec3::new(0.0, 1.0, 0.0)));
        assert!(!cut[0].keeps(DVec3::new(0.0, -1.0, 0.0)));
        // In an assembly the plane moves with the view's part.
        let part = cadre_brep::PartId(0);
        let moved = Placements {
            of_part: [(
                part,
                vec![glam::DAffine3::from_translation(DVec3::new(0.0, 10.0, 0.0))],
            )]
            .into_iter()
            .collect(),
        };
        let cut = saved_view_sections(
            &SavedView {
                part: Some(part),
                ..view.clone()
            },
            &moved,
        );
        assert!(cut[0].keeps(DVec3::new(0.0, 11.0, 0.0)));
        assert!(!cut[0].keeps(DVec3::new(0.0, 9.0, 0.0)));
        // Negative control: a view without clipping cuts nothing.
        let open = SavedView {
            clip_planes: Vec::new(),
            ..view
        };
        assert!(saved_view_sections(&open, &here).is_empty());
    }

    #[test]
    fn an_annotation_is_drawn_at_every_placement_of_its_part() {
        use cadre_brep::{Model, Occurrence, Part, PartId};
        // A root placing part 1 twice, 10 and 20 mm along x.
        let occ = |x: f64| Occurrence {
            part: PartId(1),
            transform: glam::DAffine3::from_translation(DVec3::new(x, 0.0, 0.0)),
            name: String::new(),
            step_id: 0,
        };
        let model = Model {
            parts: vec![
                Part {
                    children: vec![occ(10.0), occ(20.0)],
                    ..Part::default()
                },
                Part::default(),
            ],
            roots: vec![PartId(0)],
            ..Model::default()
        };
        let mut a = annotation(None);
        a.part = Some(PartId(1));
        let pmi = Pmi {
            annotations: vec![a],
            ..Pmi::default()
        };
        let out = overlay(&pmi, None, [1.0; 4], &Placements::of(&model));
        assert_eq!(out.annotations, 1);
        assert_eq!(out.lines.polylines.len(), 4, "two polylines, twice");
        let starts: Vec<f64> = out.lines.polylines.iter().map(|p| p.points[0].x).collect();
        assert_eq!(starts, [10.0, 10.0, 20.0, 20.0]);
        assert_eq!(out.labels.fills.len(), 2);
        // Unplaced (no part): drawn once where it is.
        let mut loose = pmi.clone();
        loose.annotations[0].part = None;
        let once = overlay(&loose, None, [1.0; 4], &Placements::of(&model));
        assert_eq!(once.lines.polylines.len(), 2);
        assert_eq!(once.lines.polylines[0].points[0].x, 0.0);
    }

    #[test]
    fn semantic_items_read_as_drawings_write_them() {
        let dim = |name: &str, value: f64, tolerance| SemanticItem::Dimension {
            step_id: 1,
            kind: DimensionKind::Size,
            name: name.into(),
            value: Some(value),
            limits: None,
            tolerance,
            faces: vec![FaceId(0)],
        };
        let limits = SemanticItem::Dimension {
            step_id: 3,
            kind: DimensionKind::Size,
            name: "diametral size dimension".into(),
            value: None,
            limits: Some((24.13, 26.67)),
            tolerance: None,
            faces: vec![FaceId(0)],
        };
        assert_eq!(semantic_text(&limits), "⌀24.13–26.67");
        assert_eq!(
            semantic_text(&dim("diameter", 6.5, Some((0.2, -0.1)))),
            "⌀6.5 +0.2/−0.1"
        );
        assert_eq!(
            semantic_text(&dim("radius", 5.0, Some((0.05, -0.05)))),
            "R5 ±0.05"
        );
        assert_eq!(
            semantic_text(&dim("linear distance", 25.125, None)),
            "25.125"
        );
        assert_eq!(
            semantic_text(&dim("angular size", std::f64::consts::FRAC_PI_6, None)),
            "30°"
        );
        let tol = SemanticItem::Tolerance {
            step_id: 2,
            kind: "POSITION_TOLERANCE".into(),
            magnitude: Some(0.1),
            datums: vec!["A".into(), "B".into()],
            modifiers: Vec::new(),
            zone: None,
            zone_values: Default::default(),
            faces: vec![FaceId(0)],
        };
        assert_eq!(semantic_text(&tol), "⌖ | 0.1 | A | B");
        // A cylindrical zone, at maximum material, to datum A at maximum material too.
        let mut modified = tol.clone();
        if let SemanticItem::Tolerance {
            modifiers,
            zone,
            datums,
            ..
        } = &mut modified
        {
            *modifiers = vec!["maximum_material_requirement".into(), "all_around".into()];
            *zone = Some("cylindrical or circular".into());
            datums[0] = "AⓂ".into();
        }
        assert_eq!(semantic_text(&modified), "⌖ | ⌀0.1 Ⓜ | AⓂ | B");
        // Projected 10 mm, per 25 mm, unequally disposed by 0.02, at most 0.2.
        if let SemanticItem::Tolerance { zone_values, .. } = &mut modified {
            *zone_values = cadre_brep::pmi::ZoneValues {
                projected: Some(10.0),
                unequally_disposed: Some(0.02),
                per_unit: Some(25.0),
                maximum: Some(0.2),
            };
        }
        assert_eq!(
            semantic_text(&modified),
            "⌖ | ⌀0.1/25 Ⓤ0.02 Ⓜ Ⓟ10 (0.2 MAX) | AⓂ | B"
        );
        // Items presented by an annotation get no callout; the others do, with a leader.
        let mut pmi = Pmi::default();
        pmi.semantic.items = vec![dim("diameter", 6.5, None), tol];
        let mut presenting = annotation(None);
        presenting.semantic = Some(0);
        pmi.annotations.push(presenting);
        let set = anchors_of(&pmi, |_| Some(DVec3::ZERO));
        assert_eq!(set.len(), 1);
        assert_eq!(set[0].name, "⌖ | 0.1 | A | B");
        assert_eq!(
            (set[0].point, set[0].style),
            (DVec3::ZERO, CalloutStyle::PMI)
        );
        // No point for the faces: no callout.
        assert!(anchors_of(&pmi, |_| None).is_empty());
    }
}
