//! Product manufacturing information (PMI): what a STEP AP242 file (or an AP203/AP214 file
//! with draughting annotations) says about tolerances beside the shape.
//!
//! - **Graphic PMI** ([`Annotation`]): the presentation, as the file draws it — polylines
//!   (tessellated curve sets, polylines of annotation curve occurrences and draughting
//!   callouts), text literals, with their curve style (width in model units, colour) and
//!   annotation plane; and the faces each annotation applies to.
//! - **Saved views** ([`SavedView`]): named cameras (direction, up, projection, window,
//!   clipping) with the annotations each shows.
//! - **Semantic PMI** ([`SemanticPmi`]): dimensions, geometric tolerances, datums and datum
//!   targets, counted as OCCT's XCAF document counts them, each with the faces it applies to.
//!
//! Lengths are millimetres, positions in the coordinates of the part the annotations belong
//! to (the file's draughting model shares its shape's context).

use crate::FaceId;
use crate::style::Rgb;
use cadre_geom::Vec3;

/// What kind of presentation an annotation is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnnotationKind {
    /// `TESSELLATED_ANNOTATION_OCCURRENCE`: tessellated curve sets (AP242).
    Tessellated,
    /// `ANNOTATION_CURVE_OCCURRENCE` / `ANNOTATION_OCCURRENCE` / `ANNOTATION_TEXT_OCCURRENCE`.
    Occurrence,
    /// `DRAUGHTING_CALLOUT` (and its dimension-callout subtypes): a group of occurrences.
    Callout,
    /// `ANNOTATION_PLACEHOLDER_OCCURRENCE` (AP242 edition 2): where a viewer puts text.
    Placeholder,
}

/// Which point of a text its placement is (a `TEXT_LITERAL`'s alignment, ISO 10303-46:
/// `baseline left`, `baseline centre`, `top right`, ...).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TextAlignment {
    /// 0 left, 1 centre, 2 right.
    pub horizontal: u8,
    /// 0 baseline, 1 top, 2 middle, 3 bottom.
    pub vertical: u8,
}

impl TextAlignment {
    /// Reads an alignment string; anything unknown is `baseline left`.
    pub fn parse(s: &str) -> TextAlignment {
        let s = s.to_ascii_lowercase();
        let horizontal = if s.contains("centre") || s.contains("center") {
            1
        } else if s.contains("right") {
            2
        } else {
            0
        };
        let vertical = if s.contains("top") {
            1
        } else if s.contains("middle") {
            2
        } else if s.contains("bottom") {
            3
        } else {
            0
        };
        TextAlignment {
            horizontal,
            vertical,
        }
    }
}

/// A text of an annotation: a string lying in a plane of the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct AnnotationText {
    /// The text.
    pub text: String,
    /// Where its baseline starts.
    pub origin: Vec3,
    /// Reading direction (unit).
    pub x_axis: Vec3,
    /// Up direction (unit).
    pub y_axis: Vec3,
    /// Lettering (cap) height, mm.
    pub height: f64,
    /// Which point of the text `origin` is.
    pub alignment: TextAlignment,
}

/// One graphic annotation.
#[derive(Clone, Debug, PartialEq)]
pub struct Annotation {
    /// STEP id of the occurrence.
    pub step_id: u64,
    /// Its name (`Flatness.1`, `Datum A`, ...).
    pub name: String,
    /// Its kind.
    pub kind: AnnotationKind,
    /// Its polylines (each at least two points).
    pub polylines: Vec<Vec<Vec3>>,
    /// Its filled areas (arrowheads, filled lettering) as triangles.
    pub fills: Vec<[Vec3; 3]>,
    /// Its texts.
    pub texts: Vec<AnnotationText>,
    /// Curve width from its curve style, mm (`None`: not given).
    pub width: Option<f64>,
    /// Curve colour from its curve style.
    pub colour: Option<Rgb>,
    /// Index into [`Pmi::planes`] of its annotation plane.
    pub plane: Option<usize>,
    /// The faces it applies to (through its draughting model item association).
    pub faces: Vec<FaceId>,
    /// Index into [`SemanticPmi::items`] of the semantic item it presents, if any.
    pub semantic: Option<usize>,
    /// Whether its geometry is tessellated (AP242 tessellated annotation occurrences).
    pub tessellated: bool,
    /// The part whose coordinates its geometry is in (the part of the faces it applies to);
    /// `None`: the world's (drawn once, unplaced).
    pub part: Option<crate::PartId>,
}

impl Annotation {
    /// How many points its polylines hold.
    pub fn point_count(&self) -> usize {
        self.polylines.iter().map(Vec::len).sum()
    }

    /// Whether it has nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.polylines.is_empty() && self.fills.is_empty() && self.texts.is_empty()
    }
}

/// An annotation plane: where a group of annotations lies, and which way it faces.
#[derive(Clone, Debug, PartialEq)]
pub struct AnnotationPlane {
    /// STEP id.
    pub step_id: u64,
    /// Its name.
    pub name: String,
    /// A point of the plane.
    pub origin: Vec3,
    /// Its normal (unit; the side the annotations are read from).
    pub normal: Vec3,
    /// Its reading direction (unit).
    pub x_axis: Vec3,
}

/// A saved view (`CAMERA_MODEL_D3` and the draughting model that holds it).
#[derive(Clone, Debug, PartialEq)]
pub struct SavedView {
    /// STEP id of the camera model.
    pub step_id: u64,
    /// Its name (`MBD_A`, ...).
    pub name: String,
    /// The view reference point (the camera placement's origin).
    pub origin: Vec3,
    /// Direction of view (unit): the camera placement's axis.
    pub direction: Vec3,
    /// Up on screen (unit): the camera placement's y axis.
    pub up: Vec3,
    /// Parallel (orthographic) projection, else central (perspective).
    pub parallel: bool,
    /// The projection point (the eye of a central projection).
    pub eye: Vec3,
    /// The view window's width and height, mm, in the view plane.
    pub window: (f64, f64),
    /// The view window's centre (in the view plane).
    pub window_centre: Vec3,
    /// Distance of the view plane from the projection point along the view, mm.
    pub view_plane_distance: f64,
    /// Front clipping distance along the view, when clipped.
    pub front_clip: Option<f64>,
    /// Back clipping distance along the view, when clipped.
    pub back_clip: Option<f64>,
    /// Clipping planes (`CAMERA_MODEL_D3_MULTI_CLIPPING`): a point and the normal of the
    /// half-space kept.
    pub clip_planes: Vec<(Vec3, Vec3)>,
    /// Indices into [`Pmi::annotations`] of the annotations it shows.
    pub annotations: Vec<usize>,
    /// The part whose coordinates the camera is in (that of the annotations it shows).
    pub part: Option<crate::PartId>,
    /// A drawing sheet's view of the model (its camera used by a presentation through a
    /// `CAMERA_USAGE`, held by no draughting model) rather than a model-based saved view.
    /// OCCT lists only the latter as views.
    pub drawing: bool,
}

/// Kinds of semantic dimension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DimensionKind {
    /// `DIMENSIONAL_SIZE` (and its subtypes: angular size, with path).
    Size,
    /// `DIMENSIONAL_LOCATION` (angular location, location with path).
    Location,
}

/// One semantic PMI item.
#[derive(Clone, Debug, PartialEq)]
pub enum SemanticItem {
    /// A dimension: its kind, name (`diameter`, `linear distance`, ...) and nominal value
    /// (mm or radians) where the file gives one.
    Dimension {
        /// STEP id.
        step_id: u64,
        /// Size or location.
        kind: DimensionKind,
        /// The dimension's name.
        name: String,
        /// Nominal value.
        value: Option<f64>,
        /// Lower and upper limits, for a limits dimension (a `VALUE_RANGE`).
        limits: Option<(f64, f64)>,
        /// Upper and lower deviation (a plus-minus tolerance).
        tolerance: Option<(f64, f64)>,
        /// The faces it applies to.
        faces: Vec<FaceId>,
    },
    /// A geometric tolerance: its type (`FLATNESS_TOLERANCE`, `POSITION_TOLERANCE`, ...) and
    /// magnitude (mm).
    Tolerance {
        /// STEP id.
        step_id: u64,
        /// The tolerance's entity type.
        kind: String,
        /// Its magnitude, mm.
        magnitude: Option<f64>,
        /// The datums it refers to, by their identifications (`A`, `B`, ...), each followed
        /// by its modifiers' symbols as a feature-control frame writes them (`AⓂ`).
        datums: Vec<String>,
        /// Its modifiers, ISO 10303-47 names in lower case (`maximum_material_requirement`,
        /// `free_state`, ...; AP214's material conditions read as the requirements).
        modifiers: Vec<String>,
        /// The form of its tolerance zone (`cylindrical or circular`, `spherical`, ...) when
        /// a `TOLERANCE_ZONE` gives one: the value is then a diameter.
        zone: Option<String>,
        /// Zone details a frame writes beside the value, mm.
        zone_values: ZoneValues,
        /// The faces it applies to.
        faces: Vec<FaceId>,
    },
    /// A datum feature: its identification (`A`, `B`, ...).
    Datum {
        /// STEP id.
        step_id: u64,
        /// The identification letter(s).
        label: String,
        /// The faces it is on.
        faces: Vec<FaceId>,
    },
    /// A datum target (`A1`, ...).
    DatumTarget {
        /// STEP id.
        step_id: u64,
        /// Its datum's letter and its own number (`A1`), or its number alone.
        label: String,
        /// The faces it is on.
        faces: Vec<FaceId>,
    },
}

/// What a feature-control frame writes beside a tolerance's value (mm each, when given).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ZoneValues {
    /// The length the zone is projected by (`Ⓟ 10`; a projected zone definition).
    pub projected: Option<f64>,
    /// The displacement of an unequally disposed zone (`Ⓤ 0.2`).
    pub unequally_disposed: Option<f64>,
    /// The length of the unit basis the value holds per (`0.05/25`).
    pub per_unit: Option<f64>,
    /// The greatest value the tolerance may take (`0.2 MAX`).
    pub maximum: Option<f64>,
}

/// The symbol a feature-control frame writes for a tolerance or datum reference modifier
/// (ISO 1101; ISO 10303-47 names, lower case), `None` for one it writes in words or not at
/// all (all around and all over go on the leader).
pub fn modifier_symbol(name: &str) -> Option<&'static str> {
    Some(match name {
        "maximum_material_requirement" | "maximum_material_condition" => "Ⓜ",
        "least_material_requirement" | "least_material_condition" => "Ⓛ",
        "regardless_of_feature_size" => "Ⓢ",
        "free_state" => "Ⓕ",
        "tangent_plane" => "Ⓣ",
        "statistical_tolerance" => "⟨ST⟩",
        "reciprocity_requirement" => "Ⓡ",
        "common_zone" => "CZ",
        "separate_requirement" => "SEP REQT",
        "united_feature" => "UF",
        "line_element" => "LE",
        "not_convex" => "NC",
        "any_cross_section" => "ACS",
        "each_radial_element" => "ERE",
        "major_diameter" => "MD",
        "minor_diameter" => "LD",
        "pitch_diameter" => "PD",
        "point" => "PT",
        "contacting_feature" => "CF",
        "distance_variable" => "DV",
        "translation" => "▷",
        "projected" => "Ⓟ",
        _ => return None,
    })
}

impl SemanticItem {
    /// The faces it applies to.
    pub fn faces(&self) -> &[FaceId] {
        match self {
            SemanticItem::Dimension { faces, .. }
            | SemanticItem::Tolerance { faces, .. }
            | SemanticItem::Datum { faces, .. }
            | SemanticItem::DatumTarget { faces, .. } => faces,
        }
    }

    /// The STEP id of the item's entity.
    pub fn step_id(&self) -> u64 {
        match self {
            SemanticItem::Dimension { step_id, .. }
            | SemanticItem::Tolerance { step_id, .. }
            | SemanticItem::Datum { step_id, .. }
            | SemanticItem::DatumTarget { step_id, .. } => *step_id,
        }
    }
}

/// The semantic PMI of a model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SemanticPmi {
    /// Every item, in file order.
    pub items: Vec<SemanticItem>,
    /// The STEP ids of the dimensions and tolerances OCCT's XCAF reader makes no label for
    /// (kept to count as OCCT does: it drops an item no `GEOMETRIC_ITEM_SPECIFIC_USAGE` ties
    /// to the shape, and complex dimension instances). We read and draw them all.
    pub xcaf_unlabelled: Vec<u64>,
}

impl SemanticPmi {
    /// How many dimensions.
    pub fn dimensions(&self) -> usize {
        self.count(|i| matches!(i, SemanticItem::Dimension { .. }))
    }

    /// How many geometric tolerances.
    pub fn tolerances(&self) -> usize {
        self.count(|i| matches!(i, SemanticItem::Tolerance { .. }))
    }

    /// How many datums.
    pub fn datums(&self) -> usize {
        self.count(|i| matches!(i, SemanticItem::Datum { .. }))
    }

    /// How many datum targets.
    pub fn datum_targets(&self) -> usize {
        self.count(|i| matches!(i, SemanticItem::DatumTarget { .. }))
    }

    fn count(&self, f: impl Fn(&SemanticItem) -> bool) -> usize {
        self.items.iter().filter(|i| f(i)).count()
    }

    /// How many of the items `f` picks OCCT's XCAF reader makes a label for.
    fn xcaf_count(&self, f: impl Fn(&SemanticItem) -> bool) -> usize {
        self.items
            .iter()
            .filter(|i| f(i) && !self.xcaf_unlabelled.contains(&i.step_id()))
            .count()
    }
}

/// Everything a model says about its product manufacturing information.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pmi {
    /// Graphic annotations.
    pub annotations: Vec<Annotation>,
    /// Annotation planes.
    pub planes: Vec<AnnotationPlane>,
    /// Saved views.
    pub views: Vec<SavedView>,
    /// Semantic PMI.
    pub semantic: SemanticPmi,
}

/// Which part holds each face of `model` (faces of solids, shells and loose faces).
pub fn face_parts(model: &crate::Model) -> std::collections::HashMap<FaceId, crate::PartId> {
    use crate::Body;
    let mut out = std::collections::HashMap::new();
    for (p, part) in model.parts.iter().enumerate() {
        let id = crate::PartId(p as u32);
        let mut shells = Vec::new();
        for body in &part.bodies {
            match body {
                Body::Solid(s) => {
                    if let Some(solid) = model.solids.get(s.index()) {
                        shells.push(solid.outer);
                        shells.extend(solid.voids.iter().copied());
                    }
                }
                Body::Shell(s) => shells.push(*s),
                Body::Face(f) => {
                    out.entry(*f).or_insert(id);
                }
                _ => {}
            }
        }
        for s in shells {
            for (f, _) in model
                .shells
                .get(s.index())
                .map_or(&[][..], |s| &s.faces[..])
            {
                out.entry(*f).or_insert(id);
            }
        }
    }
    out
}

impl Pmi {
    /// Whether the model has none.
    pub fn is_empty(&self) -> bool {
        self.annotations.is_empty() && self.views.is_empty() && self.semantic.items.is_empty()
    }

    /// The dimensions as OCCT's XCAF document counts them: the semantic dimensions it makes
    /// a label for (see [`SemanticPmi::xcaf_unlabelled`]), and one per tessellated annotation
    /// (OCCT's "dimension presentation" or "common label", whether or not it presents a
    /// semantic item; it reads no other graphic PMI).
    pub fn occt_dimensions(&self) -> usize {
        self.semantic
            .xcaf_count(|i| matches!(i, SemanticItem::Dimension { .. }))
            + self.annotations.iter().filter(|a| a.tessellated).count()
    }

    /// The geometric tolerances as OCCT's XCAF document counts them (those it makes a label
    /// for, see [`SemanticPmi::xcaf_unlabelled`]).
    pub fn occt_tolerances(&self) -> usize {
        self.semantic
            .xcaf_count(|i| matches!(i, SemanticItem::Tolerance { .. }))
    }

    /// The model-based saved views (those of draughting models), as OCCT lists them.
    pub fn saved_views(&self) -> impl Iterator<Item = &SavedView> {
        self.views.iter().filter(|v| !v.drawing)
    }

    /// The saved view named `name` (case-insensitive).
    pub fn view(&self, name: &str) -> Option<&SavedView> {
        self.views
            .iter()
            .find(|v| v.name.eq_ignore_ascii_case(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_alignments_read_as_iso_10303_46_writes_them() {
        let a = |s| {
            let t = TextAlignment::parse(s);
            (t.horizontal, t.vertical)
        };
        assert_eq!(a("baseline left"), (0, 0));
        assert_eq!(a("baseline centre"), (1, 0));
        assert_eq!(a("Baseline Right"), (2, 0));
        assert_eq!(a("top centre"), (1, 1));
        assert_eq!(a("middle right"), (2, 2));
        assert_eq!(a("bottom left"), (0, 3));
        assert_eq!(a("nonsense"), (0, 0));
    }
}
