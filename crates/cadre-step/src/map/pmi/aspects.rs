//! Shape aspects: the faces each one names, and whether OCCT's XCAF reader finds a shape for
//! a semantic item (it makes a dimension or tolerance label only then, and `cadre info`
//! counts as OCCT does).
//!
//! A shape aspect names geometry through an `ITEM_IDENTIFIED_REPRESENTATION_USAGE` (AP242
//! writes a `GEOMETRIC_ITEM_SPECIFIC_USAGE` per item, or a plain usage whose item is a
//! `SET_REPRESENTATION_ITEM` of several), through a property definition of it and that
//! property's shape representation (AP214), or groups other aspects: a composite through
//! `SHAPE_ASPECT_RELATIONSHIP`s, a derived aspect (centre of symmetry, ...) through
//! `SHAPE_ASPECT_DERIVING_RELATIONSHIP`s.

use super::super::access::Attrs;
use super::super::context::Mapper;
use super::super::error::MapError;
use super::MAX_DEPTH;
use crate::syntax::{Instance, Param};
use cadre_brep::FaceId;
use std::collections::{HashMap, HashSet};

/// `SHAPE_ASPECT` subtypes that are derived from others (ISO 10303-47): OCCT follows their
/// deriving relationship instead of their own usages.
const DERIVED: &[&str] = &[
    "DERIVED_SHAPE_ASPECT",
    "APEX",
    "CENTRE_OF_SYMMETRY",
    "EXTENSION",
    "GEOMETRIC_ALIGNMENT",
    "PARALLEL_OFFSET",
    "PERPENDICULAR_TO",
    "TANGENT",
];

/// Datum features and targets: OCCT takes them as they are, without following relationships.
const DATUM_ASPECTS: &[&str] = &[
    "DATUM_FEATURE",
    "DATUM_TARGET",
    "PLACED_DATUM_TARGET_FEATURE",
];

/// `SHAPE_ASPECT_RELATIONSHIP` and the subtypes that group aspects.
const RELATIONSHIPS: &[&str] = &[
    "SHAPE_ASPECT_RELATIONSHIP",
    "SHAPE_ASPECT_DERIVING_RELATIONSHIP",
    "FEATURE_FOR_DATUM_TARGET_RELATIONSHIP",
];

/// What the file says about its shape aspects.
pub(super) struct Aspects {
    /// The faces each aspect's usages name.
    faces_of: HashMap<u64, Vec<FaceId>>,
    /// Every relationship, relating → related (deriving ones included).
    related: HashMap<u64, Vec<u64>>,
    /// Aspects a `GEOMETRIC_ITEM_SPECIFIC_USAGE` ties to an item of the shape.
    specific_usage: HashSet<u64>,
    /// Relating → related of the relationships OCCT follows from a composite (not
    /// dimensional locations, not to a `DATUM`).
    children: HashMap<u64, Vec<u64>>,
    /// A derived aspect → the aspect its first deriving relationship names.
    derived_from: HashMap<u64, u64>,
}

impl Aspects {
    /// Reads every usage and relationship of the file.
    pub(super) fn new(m: &Mapper<'_>) -> Aspects {
        // An edge stands for the faces it bounds (a diameter on a hole's circular edge).
        let mut faces_of_edge: HashMap<cadre_brep::EdgeId, Vec<FaceId>> = HashMap::new();
        for (k, f) in m.model.faces.iter().enumerate() {
            for lp in &f.loops {
                if let cadre_brep::LoopKind::Edges(edges) = &lp.kind {
                    for oe in edges {
                        faces_of_edge
                            .entry(oe.edge)
                            .or_default()
                            .push(FaceId(k as u32));
                    }
                }
            }
        }
        let keys = || std::iter::once(0).chain(m.contexts.values().map(|(_, k)| *k));
        let faces_of_item = |item: u64| -> Vec<FaceId> {
            if let Some(f) = keys().find_map(|k| m.faces.get(&(item, k)).copied()) {
                return vec![f];
            }
            keys()
                .find_map(|k| m.edges.get(&(item, k)))
                .and_then(|e| faces_of_edge.get(e).cloned())
                .unwrap_or_default()
        };
        let mut faces_of: HashMap<u64, Vec<FaceId>> = HashMap::new();
        let mut specific_usage = HashSet::new();
        let mut usages = m
            .file
            .ids_with_keyword("ITEM_IDENTIFIED_REPRESENTATION_USAGE");
        usages.extend(m.file.ids_with_keyword("GEOMETRIC_ITEM_SPECIFIC_USAGE"));
        for id in usages {
            let Ok(inst) = m.inst(id) else { continue };
            let Ok(a) = Attrs::first(&inst) else { continue };
            // (name, description, definition, used_representation, identified_item)
            let Some(aspect) = a.opt_ref(2) else { continue };
            let mut items = Vec::new();
            if let Some(p) = a.params.get(4) {
                super::refs_in(p, &mut items, 0);
            }
            let specific = inst.has("GEOMETRIC_ITEM_SPECIFIC_USAGE");
            for item in items {
                faces_of
                    .entry(aspect)
                    .or_default()
                    .extend(faces_of_item(item));
                if specific && is_shape_item(m, item) {
                    specific_usage.insert(aspect);
                }
            }
        }
        // AP214 ties an aspect to its faces through a property definition of it and that
        // property's shape representation.
        for id in m.file.ids_with_keyword("SHAPE_DEFINITION_REPRESENTATION") {
            let Ok(inst) = m.inst(id) else { continue };
            let Ok(a) = Attrs::first(&inst) else { continue };
            // (definition, used_representation)
            let (Some(definition), Some(representation)) = (a.opt_ref(0), a.opt_ref(1)) else {
                continue;
            };
            if !m.file.has_keyword(definition, "PROPERTY_DEFINITION") {
                continue;
            }
            // PROPERTY_DEFINITION(name, description, definition)
            let Some(aspect) = m
                .inst(definition)
                .ok()
                .and_then(|d| Attrs::first(&d).ok().and_then(|d| d.opt_ref(2)))
            else {
                continue;
            };
            let is_aspect = ["PRODUCT_DEFINITION_SHAPE", "PRODUCT_DEFINITION"]
                .iter()
                .all(|k| !m.file.has_keyword(aspect, k));
            if !is_aspect {
                continue;
            }
            let items = m
                .inst(representation)
                .ok()
                .and_then(|r| super::representation_items(&r))
                .unwrap_or_default();
            for item in items {
                faces_of
                    .entry(aspect)
                    .or_default()
                    .extend(faces_of_item(item));
            }
        }
        let mut related: HashMap<u64, Vec<u64>> = HashMap::new();
        let mut children: HashMap<u64, Vec<u64>> = HashMap::new();
        let mut derived_from: HashMap<u64, u64> = HashMap::new();
        let mut relationships: Vec<u64> = RELATIONSHIPS
            .iter()
            .flat_map(|k| m.file.ids_with_keyword(k))
            .collect();
        relationships.sort_unstable();
        relationships.dedup();
        for id in relationships {
            let Ok(inst) = m.inst(id) else { continue };
            let Ok(a) =
                Attrs::of(&inst, "SHAPE_ASPECT_RELATIONSHIP").or_else(|_| Attrs::first(&inst))
            else {
                continue;
            };
            // (name, description, relating, related)
            let (Some(relating), Some(other)) = (a.opt_ref(2), a.opt_ref(3)) else {
                continue;
            };
            related.entry(relating).or_default().push(other);
            let location = inst.records.iter().any(|r| r.keyword.contains("LOCATION"));
            if !location && !m.file.has_keyword(other, "DATUM") {
                children.entry(relating).or_default().push(other);
            }
            if inst.has("SHAPE_ASPECT_DERIVING_RELATIONSHIP") {
                derived_from.entry(relating).or_insert(other);
            }
        }
        Aspects {
            faces_of,
            related,
            specific_usage,
            children,
            derived_from,
        }
    }

    /// The faces of `aspect` and of the aspects grouped under it.
    pub(super) fn of(&self, aspect: u64) -> Vec<FaceId> {
        let mut out = Vec::new();
        let mut stack = vec![(aspect, 0)];
        let mut seen = HashSet::new();
        while let Some((a, depth)) = stack.pop() {
            if depth > MAX_DEPTH || !seen.insert(a) {
                continue;
            }
            out.extend(self.faces_of.get(&a).into_iter().flatten());
            stack.extend(
                self.related
                    .get(&a)
                    .into_iter()
                    .flatten()
                    .map(|&r| (r, depth + 1)),
            );
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Whether OCCT's XCAF reader makes a label for the dimension or tolerance `#id`: its
    /// reader knows no complex dimension instance, and it keeps an item only when one of the
    /// shape aspects it refers to (a tolerance on a dimension: the dimension's) reaches the
    /// shape through a `GEOMETRIC_ITEM_SPECIFIC_USAGE` — composites through their
    /// relationships, derived aspects through their deriving relationship, as
    /// `STEPCAFControl_Reader`'s `collectShapeAspect` walks them. Files that tie PMI to the
    /// shape otherwise (AP214's property definitions, plain usages of item sets) get no label.
    pub(super) fn xcaf_labels(&self, m: &Mapper<'_>, id: u64) -> bool {
        let Ok(inst) = m.inst(id) else { return false };
        let dimension = is_dimension(&inst);
        if dimension && inst.records.len() > 1 {
            return false;
        }
        let refs = inst
            .records
            .iter()
            .flat_map(|r| r.params.iter().filter_map(Param::as_ref_id));
        for r in refs {
            let mut aspects = vec![r];
            if !dimension
                && let Ok(d) = m.inst(r)
                && is_dimension(&d)
            {
                // A tolerance on a dimension: the shape aspects of the dimension.
                aspects = d
                    .records
                    .iter()
                    .flat_map(|rec| rec.params.iter().filter_map(Param::as_ref_id))
                    .collect();
            }
            if aspects
                .into_iter()
                .any(|a| self.reaches_shape(m, a, 0, &mut HashSet::new()))
            {
                return true;
            }
        }
        false
    }

    /// Whether `aspect` reaches an item of the shape the way OCCT walks it.
    fn reaches_shape(
        &self,
        m: &Mapper<'_>,
        aspect: u64,
        depth: u32,
        seen: &mut HashSet<u64>,
    ) -> bool {
        if depth > MAX_DEPTH || !seen.insert(aspect) {
            return false;
        }
        let is = |kinds: &[&str]| kinds.iter().any(|k| m.file.has_keyword(aspect, k));
        if is(DERIVED) {
            return self
                .derived_from
                .get(&aspect)
                .is_some_and(|&d| self.reaches_shape(m, d, depth + 1, seen));
        }
        if !is(DATUM_ASPECTS)
            && let Some(children) = self.children.get(&aspect)
        {
            return children
                .iter()
                .any(|&c| self.reaches_shape(m, c, depth + 1, seen));
        }
        self.specific_usage.contains(&aspect)
    }
}

/// Whether an instance is a dimension (size or location, linear or angular, any subtype).
fn is_dimension(inst: &Instance<'_>) -> bool {
    inst.records.iter().any(|r| {
        [
            "DIMENSIONAL_SIZE",
            "DIMENSIONAL_LOCATION",
            "ANGULAR_SIZE",
            "ANGULAR_LOCATION",
        ]
        .iter()
        .any(|k| r.keyword.starts_with(k))
            || r.keyword == "DIRECTED_DIMENSIONAL_LOCATION"
    })
}

/// Whether OCCT would find a shape for a usage's item: not a bare placement or direction.
fn is_shape_item(m: &Mapper<'_>, item: u64) -> bool {
    !["AXIS2_PLACEMENT_3D", "AXIS2_PLACEMENT_2D", "DIRECTION"]
        .iter()
        .any(|k| m.file.has_keyword(item, k))
}

/// The shape aspects a semantic item applies to.
pub(super) fn aspects_of(m: &Mapper<'_>, id: u64) -> Vec<u64> {
    let Ok(inst) = m.inst(id) else {
        return Vec::new();
    };
    let first = inst.records.first().map_or("", |r| r.keyword);
    if first.starts_with("DIMENSIONAL_SIZE") || first == "ANGULAR_SIZE" {
        return Attrs::first(&inst)
            .ok()
            .and_then(|a| a.opt_ref(0))
            .into_iter()
            .collect();
    }
    if let Ok(a) = Attrs::of(&inst, "DIMENSIONAL_LOCATION")
        .or_else(|_| Attrs::of(&inst, "SHAPE_ASPECT_RELATIONSHIP"))
        .or_else(|_| {
            Attrs::first(&inst)
                .map_err(|_| ())
                .and_then(|a| {
                    if a.keyword.contains("LOCATION") {
                        Ok(a)
                    } else {
                        Err(())
                    }
                })
                .map_err(|_| MapError::new(id, ""))
        })
    {
        return [a.opt_ref(2), a.opt_ref(3)].into_iter().flatten().collect();
    }
    if let Ok(a) = Attrs::of(&inst, "GEOMETRIC_TOLERANCE").or_else(|e| {
        // A simple instance of a subtype lists the inherited attributes first.
        Attrs::first(&inst)
            .ok()
            .filter(|a| a.keyword.ends_with("_TOLERANCE") && a.params.len() >= 4)
            .ok_or(e)
    }) {
        // (name, description, magnitude, toleranced_shape_aspect)
        return a.opt_ref(3).into_iter().collect();
    }
    // A datum feature or target is a shape aspect itself.
    vec![id]
}
