//! Product manufacturing information (AP242, and the draughting annotations of AP203/AP214):
//! graphic annotations, annotation planes, saved views and semantic PMI, into
//! [`cadre_brep::Pmi`].
//!
//! Graphic PMI is read as the file draws it: a `TESSELLATED_ANNOTATION_OCCURRENCE`'s curve
//! sets, the polylines and curves of `ANNOTATION_*_OCCURRENCE`s, `DRAUGHTING_CALLOUT`s
//! (their contents drawn as one annotation), `ANNOTATION_PLACEHOLDER_OCCURRENCE`s (their
//! leader and text box), `TEXT_LITERAL`s; each with its `CURVE_STYLE` (width, colour), its
//! annotation plane, and the faces a `DRAUGHTING_MODEL_ITEM_ASSOCIATION` ties it to. Saved
//! views are `CAMERA_MODEL_D3`s: the camera placement's axis is the direction of view and
//! its y axis is up on screen (read off the NIST test files, whose annotation planes face
//! their views' cameras only so). Every annotation that cannot be drawn is a warning naming
//! it; the others still load.

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use super::geometry::{S3, curve};
use aspects::{Aspects, aspects_of};
use cadre_brep::FaceId;
use cadre_brep::pmi::{
    Annotation, AnnotationKind, AnnotationPlane, AnnotationText, DimensionKind, SavedView,
    SemanticItem,
};
use cadre_brep::style::Rgb;
use cadre_geom::{Curve, Vec3};
use std::collections::{HashMap, HashSet};

mod aspects;
mod symbols;

/// How deep annotation geometry may nest (callout → occurrence → set → set → curve).
const MAX_DEPTH: u32 = 12;
/// Points a curved annotation curve is sampled with.
const CURVE_SAMPLES: usize = 48;
/// Lettering height of a text literal whose style gives none (ISO 3098's usual 3.5 mm).
const DEFAULT_TEXT_HEIGHT: f64 = 3.5;
/// The widest line of ISO 128-20's series, mm: a curve style wider than this is not a line
/// width a drawing uses (one corpus file gives a leader 25.4 mm, which would paint a blob).
const WIDEST_LINE: f64 = 2.0;
/// Most points one annotation may hold (a corrupt index list is not followed further).
const MAX_POINTS: usize = 1 << 24;

/// The keywords of top-level annotations, and their kind.
const OCCURRENCES: &[(&str, AnnotationKind)] = &[
    ("DRAUGHTING_CALLOUT", AnnotationKind::Callout),
    (
        "TESSELLATED_ANNOTATION_OCCURRENCE",
        AnnotationKind::Tessellated,
    ),
    ("ANNOTATION_CURVE_OCCURRENCE", AnnotationKind::Occurrence),
    ("ANNOTATION_TEXT_OCCURRENCE", AnnotationKind::Occurrence),
    ("ANNOTATION_SYMBOL_OCCURRENCE", AnnotationKind::Occurrence),
    (
        "ANNOTATION_FILL_AREA_OCCURRENCE",
        AnnotationKind::Occurrence,
    ),
    ("ANNOTATION_OCCURRENCE", AnnotationKind::Occurrence),
    (
        "ANNOTATION_PLACEHOLDER_OCCURRENCE",
        AnnotationKind::Placeholder,
    ),
];

/// Geometric tolerance entity types (ISO 10303-47), as `GEOMETRIC_TOLERANCE` subtypes.
const TOLERANCE_TYPES: &[&str] = &[
    "ANGULARITY_TOLERANCE",
    "CIRCULAR_RUNOUT_TOLERANCE",
    "COAXIALITY_TOLERANCE",
    "CONCENTRICITY_TOLERANCE",
    "CYLINDRICITY_TOLERANCE",
    "FLATNESS_TOLERANCE",
    "LINE_PROFILE_TOLERANCE",
    "PARALLELISM_TOLERANCE",
    "PERPENDICULARITY_TOLERANCE",
    "POSITION_TOLERANCE",
    "ROUNDNESS_TOLERANCE",
    "STRAIGHTNESS_TOLERANCE",
    "SURFACE_PROFILE_TOLERANCE",
    "SYMMETRY_TOLERANCE",
    "TOTAL_RUNOUT_TOLERANCE",
];

/// What an annotation's geometry collects while it is read.
#[derive(Default)]
struct Drawing {
    tessellated: bool,
    polylines: Vec<Vec<Vec3>>,
    fills: Vec<[Vec3; 3]>,
    texts: Vec<AnnotationText>,
    points: usize,
}

/// Reads the file's PMI into `m.model.pmi`.
pub fn map_pmi(m: &mut Mapper<'_>) {
    let models = draughting_models(m);
    let context_of: HashMap<u64, u64> = models
        .iter()
        .flat_map(|d| d.items.iter().map(|&i| (i, d.context)))
        .collect();
    map_planes(m, &context_of);
    map_annotations(m, &context_of);
    map_semantic(m);
    link_faces(m);
    map_views(m, &models);
    assign_parts(m);
}

/// The part each annotation (and saved view) belongs to: that of the faces it applies to,
/// else the one part whose representation shares its draughting model's context, else none
/// (world coordinates).
fn assign_parts(m: &mut Mapper<'_>) {
    let face_part = cadre_brep::pmi::face_parts(&m.model);
    // Contexts used by exactly one part's representations.
    let mut context_parts: HashMap<u64, HashSet<cadre_brep::PartId>> = HashMap::new();
    for (&rep, &part) in &m.rep_parts {
        if let Ok(inst) = m.inst(rep)
            && let Ok(a) = Attrs::first(&inst)
            && let Some(ctx) = a.opt_ref(2)
        {
            context_parts.entry(ctx).or_default().insert(part);
        }
    }
    let context_of: HashMap<u64, u64> = draughting_models(m)
        .iter()
        .flat_map(|d| d.items.iter().map(|&i| (i, d.context)))
        .collect();
    let by_context = |id: u64| {
        let parts = context_parts.get(context_of.get(&id)?)?;
        (parts.len() == 1)
            .then(|| parts.iter().next().copied())
            .flatten()
    };
    let parts: Vec<Option<cadre_brep::PartId>> = m
        .model
        .pmi
        .annotations
        .iter()
        .map(|a| {
            a.faces
                .iter()
                .find_map(|f| face_part.get(f).copied())
                .or_else(|| by_context(a.step_id))
        })
        .collect();
    for (a, part) in m.model.pmi.annotations.iter_mut().zip(&parts) {
        a.part = *part;
    }
    for view in &mut m.model.pmi.views {
        view.part = view
            .annotations
            .iter()
            .find_map(|&k| parts.get(k).copied().flatten())
            .or_else(|| by_context(view.step_id));
    }
}

/// A draughting model: its id, name, items and representation context.
struct DraughtingModel {
    name: String,
    items: Vec<u64>,
    context: u64,
}

/// Every representation with a `DRAUGHTING_MODEL` record (saved views are such models,
/// often complex instances).
fn draughting_models(m: &Mapper<'_>) -> Vec<DraughtingModel> {
    let mut out = Vec::new();
    for id in m.file.ids_with_keyword("DRAUGHTING_MODEL") {
        let Ok(inst) = m.inst(id) else { continue };
        // A complex instance keeps the attributes in its REPRESENTATION record.
        let Ok(a) = Attrs::of(&inst, "REPRESENTATION").or_else(|_| Attrs::first(&inst)) else {
            continue;
        };
        let (Ok(items), Ok(context)) = (a.refs(1), a.r#ref(2)) else {
            continue;
        };
        out.push(DraughtingModel {
            name: a.str_or_empty(0),
            items,
            context,
        });
    }
    out
}

/// The annotation planes, and which annotations lie in each.
fn map_planes(m: &mut Mapper<'_>, context_of: &HashMap<u64, u64>) {
    for id in m.file.ids_with_keyword("ANNOTATION_PLANE") {
        let saved = m.enter_context(context_of.get(&id).copied());
        let plane = annotation_plane(m, id);
        m.restore_units(saved);
        match plane {
            Ok(p) => m.model.pmi.planes.push(p),
            Err(e) => m.report(&e),
        }
    }
}

fn annotation_plane(m: &Mapper<'_>, id: u64) -> MapResult<AnnotationPlane> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "ANNOTATION_PLANE").or_else(|_| Attrs::first(&inst))?;
    let item = a.r#ref(2)?;
    // The plane's item is a PLANE (through its placement) or a placement itself.
    let placement = if m.is(item, "PLANE") {
        let p = m.inst(item)?;
        Attrs::first(&p)?.r#ref(1)?
    } else {
        item
    };
    let frame = m.placement3(placement)?;
    Ok(AnnotationPlane {
        step_id: id,
        name: a.str_or_empty(0),
        origin: frame.origin,
        normal: frame.z,
        x_axis: frame.x,
    })
}

/// The plane each annotation lies in: the planes' element lists.
fn plane_of_annotations(m: &Mapper<'_>) -> HashMap<u64, usize> {
    let mut out = HashMap::new();
    for (k, plane) in m.model.pmi.planes.iter().enumerate() {
        let Ok(inst) = m.inst(plane.step_id) else {
            continue;
        };
        let Ok(a) = Attrs::of(&inst, "ANNOTATION_PLANE").or_else(|_| Attrs::first(&inst)) else {
            continue;
        };
        for e in a.refs(3).unwrap_or_default() {
            out.entry(e).or_insert(k);
        }
    }
    out
}

/// Top-level annotations: callouts, and occurrences that are not a callout's contents.
fn map_annotations(m: &mut Mapper<'_>, context_of: &HashMap<u64, u64>) {
    let mut inside_callout = HashSet::new();
    for id in m.file.ids_with_keyword("DRAUGHTING_CALLOUT") {
        let Ok(inst) = m.inst(id) else { continue };
        if let Ok(a) = Attrs::of(&inst, "DRAUGHTING_CALLOUT") {
            // A complex callout's own record holds only the contents.
            let i = if a.params.len() == 1 { 0 } else { 1 };
            inside_callout.extend(a.refs(i).unwrap_or_default());
        }
    }
    let planes = plane_of_annotations(m);
    let mut seen = HashSet::new();
    let mut ids: Vec<(u64, AnnotationKind)> = Vec::new();
    for &(keyword, kind) in OCCURRENCES {
        for id in m.file.ids_with_keyword(keyword) {
            if !inside_callout.contains(&id) && seen.insert(id) {
                ids.push((id, kind));
            }
        }
    }
    ids.sort_unstable_by_key(|(id, _)| *id);
    for (id, kind) in ids {
        // A callout's plane may be given for one of its contents only.
        let saved = m.enter_context(context_of.get(&id).copied());
        let result = annotation(m, id, kind);
        m.restore_units(saved);
        match result {
            Ok(mut a) => {
                a.plane = planes.get(&id).copied();
                if a.is_empty() {
                    m.warn(
                        id,
                        "annotation has nothing cadre can draw (no polyline, curve or text)",
                    );
                }
                m.model.pmi.annotations.push(a);
            }
            Err(e) => m.report(&e),
        }
    }
}

fn annotation(m: &mut Mapper<'_>, id: u64, kind: AnnotationKind) -> MapResult<Annotation> {
    let inst = m.inst(id)?;
    let a = Attrs::first(&inst)?;
    let name = inst
        .records
        .iter()
        .find_map(|r| r.params.first().and_then(|p| p.as_str()))
        .unwrap_or("")
        .to_string();
    let mut drawing = Drawing::default();
    let (mut width, mut colour) = (None, None);
    if kind == AnnotationKind::Callout {
        let rec = Attrs::of(&inst, "DRAUGHTING_CALLOUT").unwrap_or(a);
        let i = if rec.params.len() == 1 { 0 } else { 1 };
        for content in rec.refs(i)? {
            let (w, c) = occurrence(m, content, &mut drawing, 0)?;
            width = width.or(w);
            colour = colour.or(c);
        }
    } else {
        (width, colour) = occurrence(m, id, &mut drawing, 0)?;
    }
    if let Some(w) = width
        && w > WIDEST_LINE
    {
        m.warn(
            id,
            format!(
                "curve width {w} mm is wider than ISO 128's widest line ({WIDEST_LINE} mm): \
                 drawn {WIDEST_LINE} mm wide"
            ),
        );
        width = Some(WIDEST_LINE);
    }
    Ok(Annotation {
        step_id: id,
        name,
        kind,
        polylines: drawing.polylines,
        fills: drawing.fills,
        texts: drawing.texts,
        width,
        colour,
        plane: None,
        faces: Vec::new(),
        semantic: None,
        tessellated: drawing.tessellated,
        part: None,
    })
}

/// Reads an occurrence (`STYLED_ITEM` subtype: name, styles, item) into `drawing`; returns
/// its curve style's width and colour.
fn occurrence(
    m: &mut Mapper<'_>,
    id: u64,
    drawing: &mut Drawing,
    depth: u32,
) -> MapResult<(Option<f64>, Option<Rgb>)> {
    if depth > MAX_DEPTH {
        return Err(MapError::new(id, "annotation nests too deep"));
    }
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "STYLED_ITEM").or_else(|_| Attrs::first(&inst))?;
    // Simple: (name, styles, item, ...); a complex STYLED_ITEM record: (styles, item).
    let o = usize::from(!(inst.complex && a.params.len() == 2));
    if m.is(id, "DRAUGHTING_CALLOUT") {
        let rec = Attrs::of(&inst, "DRAUGHTING_CALLOUT")?;
        let i = if rec.params.len() == 1 { 0 } else { 1 };
        let mut style = (None, None);
        for content in rec.refs(i)? {
            let s = occurrence(m, content, drawing, depth + 1)?;
            style = (style.0.or(s.0), style.1.or(s.1));
        }
        return Ok(style);
    }
    let styles = a.refs(o).unwrap_or_default();
    let (width, colour, text_height) = curve_style(m, &styles);
    let item = a.r#ref(o + 1)?;
    geometry(m, item, drawing, text_height, depth + 1)?;
    Ok((width, colour))
}

/// The width, colour and text height a list of presentation style assignments gives.
fn curve_style(m: &Mapper<'_>, styles: &[u64]) -> (Option<f64>, Option<Rgb>, Option<f64>) {
    let (mut width, mut colour, mut height) = (None, None, None);
    let mut stack: Vec<(u64, u32)> = styles.iter().map(|&s| (s, 0)).collect();
    while let Some((id, depth)) = stack.pop() {
        if depth > MAX_DEPTH {
            continue;
        }
        let Ok(inst) = m.inst(id) else { continue };
        let Ok(a) = Attrs::first(&inst) else { continue };
        match a.keyword {
            "PRESENTATION_STYLE_ASSIGNMENT" | "PRESENTATION_STYLE_BY_CONTEXT" => {
                stack.extend(
                    a.refs(0)
                        .unwrap_or_default()
                        .into_iter()
                        .map(|s| (s, depth + 1)),
                );
            }
            "CURVE_STYLE" => {
                width = width.or_else(|| measure(m, a.params.get(2)?));
                if colour.is_none()
                    && let Some(c) = a.opt_ref(3)
                {
                    colour = rgb(m, c);
                }
            }
            "TEXT_STYLE" | "TEXT_STYLE_WITH_BOX_CHARACTERISTICS" => {
                // (name, character_appearance[, characteristics]): BOX_HEIGHT among them.
                for p in a.params.get(2).and_then(|p| p.as_list()).unwrap_or(&[]) {
                    if let crate::syntax::Param::Typed { keyword, value } = p
                        && keyword.eq_ignore_ascii_case("BOX_HEIGHT")
                    {
                        height = height.or(value.as_f64().map(|h| h * m.units.length_to_mm));
                    }
                }
            }
            _ => {}
        }
    }
    (width, colour, height)
}

/// A length given inline (`POSITIVE_LENGTH_MEASURE(0.13)`) or as a measure with unit, mm.
fn measure(m: &Mapper<'_>, p: &crate::syntax::Param<'_>) -> Option<f64> {
    if let Some(v) = p.as_f64() {
        return Some(v * m.units.length_to_mm);
    }
    let id = p.as_ref_id()?;
    // A measure with its own length unit is in that unit, whatever the context's.
    if let Some(mm) = super::units::length_mm(m, id) {
        return Some(mm);
    }
    let inst = m.inst(id).ok()?;
    let value = inst
        .records
        .iter()
        .find_map(|r| r.params.iter().find_map(|q| q.as_f64()))?;
    Some(value * m.units.length_to_mm)
}

/// A colour (RGB or a pre-defined draughting colour).
fn rgb(m: &Mapper<'_>, id: u64) -> Option<Rgb> {
    let inst = m.inst(id).ok()?;
    if let Some(rec) = inst.record("COLOUR_RGB") {
        let v: Vec<f64> = rec.params.iter().filter_map(|p| p.as_f64()).collect();
        if let [r, g, b] = v[..] {
            return Some(Rgb::new(r, g, b));
        }
    }
    let rec = inst.record("DRAUGHTING_PRE_DEFINED_COLOUR")?;
    Rgb::predefined(rec.params.first()?.as_str()?)
}

/// Reads an annotation's geometry item into `drawing`.
fn geometry(
    m: &mut Mapper<'_>,
    id: u64,
    drawing: &mut Drawing,
    text_height: Option<f64>,
    depth: u32,
) -> MapResult<()> {
    if depth > MAX_DEPTH {
        return Err(MapError::new(id, "annotation geometry nests too deep"));
    }
    let inst = m.inst(id)?;
    if let Ok(set) = Attrs::of(&inst, "TESSELLATED_GEOMETRIC_SET") {
        // Simple: (name, children); a complex instance's own record: (children).
        let children = set.refs(usize::from(!inst.complex))?;
        drawing.tessellated = true;
        let mut own = Drawing::default();
        for c in children {
            geometry(m, c, &mut own, text_height, depth + 1)?;
        }
        // A repositioned set's points are in its location's coordinates.
        if let Ok(r) = Attrs::of(&inst, "REPOSITIONED_TESSELLATED_ITEM") {
            let f = m.placement3(r.r#ref(0)?)?;
            let place = |p: Vec3| f.origin + f.x * p.x + f.y * p.y + f.z * p.z;
            for line in &mut own.polylines {
                line.iter_mut().for_each(|p| *p = place(*p));
            }
            for t in &mut own.fills {
                t.iter_mut().for_each(|p| *p = place(*p));
            }
            for t in &mut own.texts {
                t.origin = place(t.origin);
                t.x_axis = f.x * t.x_axis.x + f.y * t.x_axis.y + f.z * t.x_axis.z;
                t.y_axis = f.x * t.y_axis.x + f.y * t.y_axis.y + f.z * t.y_axis.z;
            }
        }
        for line in own.polylines {
            push(drawing, line, id)?;
        }
        drawing.texts.extend(own.texts);
        drawing.fills.extend(own.fills);
        return Ok(());
    }
    let a = Attrs::first(&inst)?;
    match a.keyword {
        "TESSELLATED_CURVE_SET" => curve_set(m, &a, drawing)?,
        "TRIANGULATED_SURFACE_SET"
        | "COMPLEX_TRIANGULATED_SURFACE_SET"
        | "TRIANGULATED_FACE"
        | "COMPLEX_TRIANGULATED_FACE" => {
            let mesh = super::tessellated::triangles(m, id)?;
            drawing.points += mesh.positions.len();
            if drawing.points > MAX_POINTS {
                return Err(MapError::new(
                    id,
                    "annotation has more points than cadre reads",
                ));
            }
            let at = |i: u32| mesh.positions[i as usize];
            drawing.fills.extend(
                mesh.triangles
                    .iter()
                    .map(|t| [at(t[0]), at(t[1]), at(t[2])]),
            );
        }
        "GEOMETRIC_SET" | "GEOMETRIC_CURVE_SET" | "ANNOTATION_FILL_AREA" => {
            let elements = a.refs(1)?;
            // A placeholder's set: its placement, text box and leader.
            let placement = elements
                .iter()
                .copied()
                .find(|&e| m.is(e, "AXIS2_PLACEMENT_3D"));
            for e in elements {
                if m.is(e, "AXIS2_PLACEMENT_3D") {
                    continue;
                }
                if m.is(e, "PLANAR_BOX") {
                    planar_box(m, e, placement, drawing)?;
                } else {
                    geometry(m, e, drawing, text_height, depth + 1)?;
                }
            }
        }
        "COMPOSITE_TEXT"
        | "COMPOSITE_TEXT_WITH_ASSOCIATED_CURVES"
        | "COMPOSITE_TEXT_WITH_BLANKING_BOX"
        | "COMPOSITE_TEXT_WITH_DELINEATION"
        | "COMPOSITE_TEXT_WITH_EXTENT" => {
            for t in a.refs(1)? {
                geometry(m, t, drawing, text_height, depth + 1)?;
            }
        }
        "TEXT_LITERAL"
        | "TEXT_LITERAL_WITH_EXTENT"
        | "TEXT_LITERAL_WITH_ASSOCIATED_CURVES"
        | "TEXT_LITERAL_WITH_BLANKING_BOX"
        | "TEXT_LITERAL_WITH_DELINEATION"
        | "DIMENSION_TEXT_ASSOCIATIVITY" => {
            // (name, literal, placement, alignment, path, font)
            let frame = m.placement3(a.r#ref(2)?)?;
            drawing.texts.push(AnnotationText {
                text: a.str_or_empty(1),
                origin: frame.origin,
                x_axis: frame.x,
                y_axis: frame.y,
                height: text_height.unwrap_or(DEFAULT_TEXT_HEIGHT),
                alignment: cadre_brep::pmi::TextAlignment::parse(&a.str_or_empty(3)),
            });
        }
        "PLANAR_BOX" => planar_box(m, id, None, drawing)?,
        "DEFINED_SYMBOL" => {
            let a = Attrs::of(&inst, "DEFINED_SYMBOL")?;
            symbols::defined_symbol(m, id, &a, drawing)?;
        }
        "MAPPED_ITEM" | "ANNOTATION_SYMBOL" | "ANNOTATION_TEXT" => {
            symbols::mapped_symbol(m, id, drawing, text_height, depth)?;
        }
        keyword if keyword.ends_with("_OCCURRENCE") || keyword == "DRAUGHTING_CALLOUT" => {
            occurrence(m, id, drawing, depth + 1)?;
        }
        _ => {
            let c = curve::<S3>(m, id)?;
            let points = sample(&c).ok_or_else(|| {
                MapError::new(id, format!("{}: unbounded annotation curve", a.keyword))
            })?;
            push(drawing, points, id)?;
        }
    }
    Ok(())
}

/// A `TESSELLATED_CURVE_SET`'s line strips (1-based indices into its coordinates).
fn curve_set(m: &Mapper<'_>, a: &Attrs<'_, '_>, drawing: &mut Drawing) -> MapResult<()> {
    let coords = super::tessellated::coordinates(m, a.r#ref(1)?)?;
    for strip in a.list(2)? {
        let indices = strip
            .as_list()
            .ok_or_else(|| a.err("line strip is not a list"))?;
        let mut points = Vec::with_capacity(indices.len());
        for i in indices {
            let i = i
                .as_i64()
                .and_then(|v| usize::try_from(v).ok())
                .filter(|&v| v >= 1 && v <= coords.len())
                .ok_or_else(|| {
                    a.err(format!(
                        "point index out of the {} coordinates",
                        coords.len()
                    ))
                })?;
            points.push(coords[i - 1]);
        }
        push(drawing, points, a.id)?;
    }
    Ok(())
}

/// A placeholder's text box: a rectangle `size_in_x` × `size_in_y` from its placement
/// (the box's own, else the set's).
fn planar_box(
    m: &Mapper<'_>,
    id: u64,
    set_placement: Option<u64>,
    drawing: &mut Drawing,
) -> MapResult<()> {
    let inst = m.inst(id)?;
    let a = Attrs::first(&inst)?;
    let l = m.units.length_to_mm;
    let (w, h) = (a.f64(1)? * l, a.f64(2)? * l);
    let placement = a
        .opt_ref(3)
        .or(set_placement)
        .ok_or_else(|| a.err("no placement"))?;
    if !m.is(placement, "AXIS2_PLACEMENT_3D") {
        return Ok(());
    }
    let f = m.placement3(placement)?;
    let corner = |u: f64, v: f64| f.origin + f.x * u + f.y * v;
    push(
        drawing,
        vec![
            corner(0.0, 0.0),
            corner(w, 0.0),
            corner(w, h),
            corner(0.0, h),
            corner(0.0, 0.0),
        ],
        id,
    )
}

/// Adds a polyline (two points at least) to `drawing`, refusing absurd totals.
fn push(drawing: &mut Drawing, points: Vec<Vec3>, id: u64) -> MapResult<()> {
    drawing.points += points.len();
    if drawing.points > MAX_POINTS {
        return Err(MapError::new(
            id,
            "annotation has more points than cadre reads",
        ));
    }
    if points.len() >= 2 {
        drawing.polylines.push(points);
    }
    Ok(())
}

/// Points along a bounded curve: a polyline's own, else evenly in its parameter range.
fn sample(c: &Curve<Vec3>) -> Option<Vec<Vec3>> {
    if let Curve::Polyline(points) = c {
        return Some(points.clone());
    }
    let (t0, t1) = c.start_end_params().or_else(|| c.domain())?;
    if !(t0.is_finite() && t1.is_finite()) {
        return None;
    }
    let n = if matches!(c, Curve::Line { .. }) {
        1
    } else {
        CURVE_SAMPLES
    };
    Some(
        (0..=n)
            .map(|i| c.eval(t0 + (t1 - t0) * i as f64 / n as f64))
            .collect(),
    )
}

/// Semantic PMI: dimensions, geometric tolerances, datum features and datum targets.
fn map_semantic(m: &mut Mapper<'_>) {
    let mut items: Vec<(u64, SemanticItem)> = Vec::new();
    for (keyword, kind) in [
        ("DIMENSIONAL_SIZE", DimensionKind::Size),
        ("ANGULAR_SIZE", DimensionKind::Size),
        ("DIMENSIONAL_SIZE_WITH_PATH", DimensionKind::Size),
        ("DIMENSIONAL_SIZE_WITH_DATUM_FEATURE", DimensionKind::Size),
        ("DIMENSIONAL_LOCATION", DimensionKind::Location),
        ("ANGULAR_LOCATION", DimensionKind::Location),
        ("DIMENSIONAL_LOCATION_WITH_PATH", DimensionKind::Location),
        ("DIRECTED_DIMENSIONAL_LOCATION", DimensionKind::Location),
    ] {
        for id in m.file.ids_with_keyword(keyword) {
            let Ok(inst) = m.inst(id) else { continue };
            // Complex instances list every supertype's record: read each instance once,
            // under its first keyword met here.
            if items.iter().any(|(i, _)| *i == id) {
                continue;
            }
            let Ok(a) = Attrs::of(&inst, keyword) else {
                continue;
            };
            let name = match kind {
                // (applies_to, name)
                DimensionKind::Size => a.str_or_empty(1),
                // (name, description, relating, related)
                DimensionKind::Location => a.str_or_empty(0),
            };
            items.push((
                id,
                SemanticItem::Dimension {
                    step_id: id,
                    kind,
                    name,
                    value: None,
                    limits: None,
                    tolerance: None,
                    faces: Vec::new(),
                },
            ));
        }
    }
    let mut tolerances: HashSet<u64> = HashSet::new();
    for keyword in TOLERANCE_TYPES
        .iter()
        .copied()
        .chain(["GEOMETRIC_TOLERANCE"])
    {
        tolerances.extend(m.file.ids_with_keyword(keyword));
    }
    let zones = tolerance_zones(m);
    let projected = projected_lengths(m);
    for id in tolerances {
        let Ok(inst) = m.inst(id) else { continue };
        let kind = inst
            .records
            .iter()
            .map(|r| r.keyword)
            .find(|k| TOLERANCE_TYPES.contains(k))
            .unwrap_or("GEOMETRIC_TOLERANCE")
            .to_string();
        // (name, description, magnitude, toleranced_shape_aspect): a complex instance's
        // GEOMETRIC_TOLERANCE record, or a simple instance of a subtype.
        let magnitude = Attrs::of(&inst, "GEOMETRIC_TOLERANCE")
            .or_else(|_| Attrs::first(&inst))
            .ok()
            .and_then(|a| a.params.get(2).and_then(|p| measure(m, p)));
        // A complex instance's own record holds the datum references; a simple instance of
        // a tolerance with datums lists them after the four inherited attributes.
        let datum_refs = match Attrs::of(&inst, "GEOMETRIC_TOLERANCE_WITH_DATUM_REFERENCE") {
            Ok(a) if inst.complex => a.refs(0).ok(),
            _ if !inst.complex => Attrs::first(&inst)
                .ok()
                .filter(|a| a.params.len() >= 5)
                .and_then(|a| a.refs(4).ok()),
            _ => None,
        };
        let datums = datum_refs
            .map(|refs| refs.iter().flat_map(|&r| datum_letters(m, r, 0)).collect())
            .unwrap_or_default();
        items.push((
            id,
            SemanticItem::Tolerance {
                step_id: id,
                kind,
                magnitude,
                datums,
                modifiers: tolerance_modifiers(&inst),
                zone: zones.get(&id).cloned(),
                zone_values: cadre_brep::pmi::ZoneValues {
                    projected: projected.get(&id).copied(),
                    ..zone_values(m, &inst)
                },
                faces: Vec::new(),
            },
        ));
    }
    // A datum feature's letter: that of the datum of the same name (AP214), else its name.
    let mut letter_of_name: HashMap<String, String> = HashMap::new();
    for id in m.file.ids_with_keyword("DATUM") {
        if let Ok(inst) = m.inst(id)
            && let Ok(a) = Attrs::of(&inst, "DATUM")
        {
            letter_of_name.insert(a.str_or_empty(0), a.str_or_empty(4));
        }
    }
    for id in m.file.ids_with_keyword("DATUM_FEATURE") {
        let name = m
            .inst(id)
            .ok()
            .and_then(|i| Attrs::first(&i).ok().map(|a| a.str_or_empty(0)))
            .unwrap_or_default();
        let label = letter_of_name
            .get(&name)
            .filter(|l| !l.is_empty())
            .cloned()
            .unwrap_or(name);
        items.push((
            id,
            SemanticItem::Datum {
                step_id: id,
                label,
                faces: Vec::new(),
            },
        ));
    }
    let mut targets: HashSet<u64> = m
        .file
        .ids_with_keyword("DATUM_TARGET")
        .into_iter()
        .collect();
    targets.extend(m.file.ids_with_keyword("PLACED_DATUM_TARGET_FEATURE"));
    // A target's datum: the DATUM a shape aspect relationship relates it to.
    let mut datum_of_target: HashMap<u64, String> = HashMap::new();
    for id in m.file.ids_with_keyword("SHAPE_ASPECT_RELATIONSHIP") {
        let Ok(inst) = m.inst(id) else { continue };
        let Ok(a) = Attrs::of(&inst, "SHAPE_ASPECT_RELATIONSHIP") else {
            continue;
        };
        // (name, description, relating, related)
        if let (Some(target), Some(datum)) = (a.opt_ref(2), a.opt_ref(3))
            && m.is(datum, "DATUM")
            && let Ok(d) = m.inst(datum)
            && let Ok(d) = Attrs::of(&d, "DATUM")
        {
            datum_of_target.insert(target, d.str_or_empty(4));
        }
    }
    for id in targets {
        // (name, description, of_shape, product_definitional, target_id) for both the
        // target and a placed target feature.
        let number = m
            .inst(id)
            .ok()
            .and_then(|i| {
                let a = Attrs::of(&i, "DATUM_TARGET")
                    .or_else(|_| Attrs::first(&i))
                    .ok()?;
                Some(a.str_or_empty(4))
            })
            .unwrap_or_default();
        let letter = datum_of_target.get(&id).cloned().unwrap_or_default();
        items.push((
            id,
            SemanticItem::DatumTarget {
                step_id: id,
                label: format!("{letter}{number}"),
                faces: Vec::new(),
            },
        ));
    }
    items.sort_unstable_by_key(|(id, _)| *id);
    dimension_values(m, &mut items);
    m.model.pmi.semantic.items = items.into_iter().map(|(_, item)| item).collect();
}

/// The datum letters a datum reference, datum system or compartment names, in order.
fn datum_letters(m: &Mapper<'_>, id: u64, depth: u32) -> Vec<String> {
    if depth > MAX_DEPTH {
        return Vec::new();
    }
    let Ok(inst) = m.inst(id) else {
        return Vec::new();
    };
    if let Ok(a) = Attrs::of(&inst, "DATUM") {
        // (name, description, of_shape, product_definitional, identification)
        return vec![a.str_or_empty(4)];
    }
    let Ok(a) = Attrs::first(&inst) else {
        return Vec::new();
    };
    match a.keyword {
        // (precedence, referenced_datum)
        "DATUM_REFERENCE" => a
            .opt_ref(1)
            .map(|d| datum_letters(m, d, depth + 1))
            .unwrap_or_default(),
        // AP214: (precedence, referenced_datum, modifier)
        "REFERENCED_MODIFIED_DATUM" => {
            let mut letters = a
                .opt_ref(1)
                .map(|d| datum_letters(m, d, depth + 1))
                .unwrap_or_default();
            let modifier = a.enumeration(2).map(str::to_ascii_lowercase);
            append_symbols(&mut letters, modifier.iter().map(String::as_str));
            letters
        }
        // (name, description, of_shape, product_definitional, constituents)
        "DATUM_SYSTEM" => a
            .refs(4)
            .unwrap_or_default()
            .iter()
            .flat_map(|&c| datum_letters(m, c, depth + 1))
            .collect(),
        // (..., base, modifiers): the base is a datum or a list of reference elements.
        "DATUM_REFERENCE_COMPARTMENT" | "DATUM_REFERENCE_ELEMENT" => {
            let base = a.params.get(4);
            let refs: Vec<u64> = match base {
                Some(p) => p
                    .as_ref_id()
                    .into_iter()
                    .chain(
                        p.as_list()
                            .unwrap_or(&[])
                            .iter()
                            .filter_map(|q| q.as_ref_id()),
                    )
                    .collect(),
                None => Vec::new(),
            };
            let mut letters: Vec<String> = refs
                .iter()
                .flat_map(|&r| datum_letters(m, r, depth + 1))
                .collect();
            let modifiers = a.params.get(5).map(enum_names).unwrap_or_default();
            append_symbols(&mut letters, modifiers.iter().map(String::as_str));
            letters
        }
        _ => Vec::new(),
    }
}

/// Appends the symbols of `modifiers` (ISO 10303-47 names) to the last of `letters`.
fn append_symbols<'n>(letters: &mut [String], modifiers: impl Iterator<Item = &'n str>) {
    if let Some(last) = letters.last_mut() {
        for symbol in modifiers.filter_map(cadre_brep::pmi::modifier_symbol) {
            last.push_str(symbol);
        }
    }
}

/// The enumeration values in a parameter (an aggregate of them, typed ones such as
/// `SIMPLE_DATUM_REFERENCE_MODIFIER(.X.)` included), lower case.
fn enum_names(p: &crate::syntax::Param<'_>) -> Vec<String> {
    use crate::syntax::Param;
    match p {
        Param::Enum(e) => vec![e.to_ascii_lowercase()],
        Param::Typed { value, .. } => enum_names(value),
        Param::List(items) => items.iter().flat_map(enum_names).collect(),
        _ => Vec::new(),
    }
}

/// A geometric tolerance's modifiers (`GEOMETRIC_TOLERANCE_WITH_MODIFIERS`' set, AP214's
/// `MODIFIED_GEOMETRIC_TOLERANCE`), ISO 10303-47 names in lower case, AP214's material
/// conditions read as the requirements.
fn tolerance_modifiers(inst: &crate::syntax::Instance<'_>) -> Vec<String> {
    let mut out = Vec::new();
    for keyword in [
        "GEOMETRIC_TOLERANCE_WITH_MODIFIERS",
        "MODIFIED_GEOMETRIC_TOLERANCE",
    ] {
        if let Some(rec) = inst.record(keyword) {
            // The type's own attribute is the last (a simple instance lists the inherited
            // ones before it).
            out.extend(rec.params.last().map(enum_names).unwrap_or_default());
        }
    }
    out.iter()
        .map(|n| match n.as_str() {
            "maximum_material_condition" => "maximum_material_requirement".to_string(),
            "least_material_condition" => "least_material_requirement".to_string(),
            _ => n.clone(),
        })
        .collect()
}

/// A tolerance's unequally disposed displacement, unit basis and maximum (the last
/// attribute of their records: a complex instance's own, a simple instance's after the
/// inherited ones).
fn zone_values(m: &Mapper<'_>, inst: &crate::syntax::Instance<'_>) -> cadre_brep::pmi::ZoneValues {
    let last = |keyword: &str| {
        inst.record(keyword)
            .and_then(|r| r.params.last())
            .and_then(|p| measure(m, p))
    };
    cadre_brep::pmi::ZoneValues {
        projected: None,
        unequally_disposed: last("UNEQUALLY_DISPOSED_GEOMETRIC_TOLERANCE"),
        per_unit: last("GEOMETRIC_TOLERANCE_WITH_DEFINED_UNIT"),
        maximum: last("GEOMETRIC_TOLERANCE_WITH_MAXIMUM_TOLERANCE"),
    }
}

/// The projected length of each tolerance whose zone a `PROJECTED_ZONE_DEFINITION` projects
/// (tolerance id → mm).
fn projected_lengths(m: &Mapper<'_>) -> HashMap<u64, f64> {
    let mut out = HashMap::new();
    for id in m.file.ids_with_keyword("PROJECTED_ZONE_DEFINITION") {
        let Ok(inst) = m.inst(id) else { continue };
        let Ok(a) = Attrs::first(&inst) else { continue };
        // (zone, boundaries, projection_end, projected_length)
        let (Some(zone), Some(length)) =
            (a.opt_ref(0), a.params.get(3).and_then(|p| measure(m, p)))
        else {
            continue;
        };
        let Some((tolerances, _)) = tolerance_zone(m, zone) else {
            continue;
        };
        for t in tolerances {
            out.entry(t).or_insert(length);
        }
    }
    out
}

/// The tolerance zone form each tolerance's `TOLERANCE_ZONE` gives (tolerance id → form
/// name, lower case).
fn tolerance_zones(m: &Mapper<'_>) -> HashMap<u64, String> {
    let mut out = HashMap::new();
    for id in m.file.ids_with_keyword("TOLERANCE_ZONE") {
        let Some((tolerances, form)) = tolerance_zone(m, id) else {
            continue;
        };
        let form = form
            .and_then(|f| m.inst(f).ok())
            .and_then(|f| Attrs::first(&f).ok().map(|f| f.str_or_empty(0)))
            .unwrap_or_default()
            .to_lowercase();
        if form.is_empty() {
            continue;
        }
        for t in tolerances {
            out.entry(t).or_insert_with(|| form.clone());
        }
    }
    out
}

/// A `TOLERANCE_ZONE`'s defining tolerances and its form: (name, description, of_shape,
/// product_definitional, defining_tolerance, form) in a simple instance, (defining_tolerance,
/// form) in a complex one's own record.
fn tolerance_zone(m: &Mapper<'_>, id: u64) -> Option<(Vec<u64>, Option<u64>)> {
    let inst = m.inst(id).ok()?;
    let a = Attrs::of(&inst, "TOLERANCE_ZONE").ok()?;
    let at = if a.params.len() > 2 { 4 } else { 0 };
    let mut tolerances = Vec::new();
    if let Some(p) = a.params.get(at) {
        refs_in(p, &mut tolerances, 0);
    }
    Some((tolerances, a.opt_ref(at + 1)))
}

/// Each dimension's nominal value (its `DIMENSIONAL_CHARACTERISTIC_REPRESENTATION`) and
/// plus-minus deviations (`PLUS_MINUS_TOLERANCE`).
/// The instances a parameter names: a reference, or the members of an aggregate or a typed
/// one such as `SET_REPRESENTATION_ITEM((#1,#2))` (an identified item, a value range).
fn refs_in(p: &crate::syntax::Param<'_>, out: &mut Vec<u64>, depth: u32) {
    use crate::syntax::Param;
    if depth > MAX_DEPTH {
        return;
    }
    match p {
        Param::Ref(id) => out.push(*id),
        Param::Typed { value, .. } => refs_in(value, out, depth + 1),
        Param::List(items) => {
            for i in items {
                refs_in(i, out, depth + 1);
            }
        }
        _ => {}
    }
}

/// A representation's items: `(name, items, context)` of its REPRESENTATION record in a
/// complex instance (whose other records may be empty), else of its only record.
fn representation_items(rep: &crate::syntax::Instance<'_>) -> Option<Vec<u64>> {
    Attrs::of(rep, "REPRESENTATION")
        .or_else(|_| Attrs::first(rep))
        .ok()?
        .refs(1)
        .ok()
}

/// A measure representation item's value — a length in mm, an angle in radians, by its own
/// unit, else the context's — and its name (`nominal value`, `lower limit`, ...).
fn measure_item(m: &Mapper<'_>, id: u64) -> Option<(f64, String)> {
    let v = m.inst(id).ok()?;
    // The name is the first string of a REPRESENTATION_ITEM record (the complex form) or of
    // a simple MEASURE_REPRESENTATION_ITEM.
    let name = v
        .records
        .iter()
        .filter(|r| {
            r.keyword == "REPRESENTATION_ITEM" || r.keyword == "MEASURE_REPRESENTATION_ITEM"
        })
        .find_map(|r| r.params.first().and_then(|p| p.as_str()))
        .unwrap_or("")
        .to_string();
    let value = v.records.iter().find_map(|r| {
        // MEASURE_WITH_UNIT(value, unit) in a complex instance; a simple
        // MEASURE_REPRESENTATION_ITEM(name, value, unit).
        let at = match r.keyword {
            "MEASURE_WITH_UNIT" => 0,
            "MEASURE_REPRESENTATION_ITEM" if r.params.len() >= 3 => 1,
            _ => return None,
        };
        let p = r.params.get(at)?;
        let angle = matches!(p, crate::syntax::Param::Typed { keyword, .. }
            if keyword.contains("ANGLE"));
        let scale = r
            .params
            .get(at + 1)
            .and_then(|u| u.as_ref_id())
            .and_then(|u| super::units::base_size(m, u))
            .unwrap_or(if angle {
                m.units.angle_to_rad
            } else {
                m.units.length_to_mm
            });
        Some(p.as_f64()? * scale)
    })?;
    Some((value, name))
}

fn dimension_values(m: &Mapper<'_>, items: &mut [(u64, SemanticItem)]) {
    let index: HashMap<u64, usize> = items
        .iter()
        .enumerate()
        .map(|(k, (id, _))| (*id, k))
        .collect();
    for id in m
        .file
        .ids_with_keyword("DIMENSIONAL_CHARACTERISTIC_REPRESENTATION")
    {
        let Some((dimension, value, limits)) = m.inst(id).ok().and_then(|inst| {
            let a = Attrs::first(&inst).ok()?;
            let rep = m.inst(a.r#ref(1).ok()?).ok()?;
            let members = representation_items(&rep)?;
            let mut value = None;
            let (mut lower, mut upper) = (None, None);
            for &i in &members {
                if m.is(i, "VALUE_RANGE") {
                    // VALUE_RANGE(name, SET_REPRESENTATION_ITEM((lower, upper))): a limits
                    // dimension.
                    let range = m.inst(i).ok()?;
                    let mut bounds = Vec::new();
                    if let Some(p) = Attrs::first(&range).ok()?.params.get(1) {
                        refs_in(p, &mut bounds, 0);
                    }
                    for b in bounds {
                        if let Some((v, name)) = measure_item(m, b) {
                            if name.contains("upper") {
                                upper = Some(v);
                            } else if name.contains("lower") {
                                lower = Some(v);
                            }
                        }
                    }
                } else if let Some((v, name)) = measure_item(m, i)
                    && (name == "nominal value" || members.len() == 1)
                {
                    value = Some(v);
                }
            }
            let limits = lower.zip(upper);
            (value.is_some() || limits.is_some()).then_some((a.r#ref(0).ok()?, value, limits))
        }) else {
            continue;
        };
        if let Some(&k) = index.get(&dimension)
            && let SemanticItem::Dimension {
                value: v,
                limits: l,
                ..
            } = &mut items[k].1
        {
            *v = value;
            *l = limits;
        }
    }
    for id in m.file.ids_with_keyword("PLUS_MINUS_TOLERANCE") {
        let Some((dimension, bounds)) = m.inst(id).ok().and_then(|inst| {
            let a = Attrs::first(&inst).ok()?;
            let range = m.inst(a.r#ref(0).ok()?).ok()?;
            let r = Attrs::first(&range).ok()?;
            let bound = |i: usize| measure(m, r.params.get(i)?);
            Some((a.r#ref(1).ok()?, (bound(1)?, bound(0)?)))
        }) else {
            continue;
        };
        if let Some(&k) = index.get(&dimension)
            && let SemanticItem::Dimension { tolerance, .. } = &mut items[k].1
        {
            *tolerance = Some(bounds);
        }
    }
}

/// Ties annotations and semantic items to faces, and annotations to semantic items, through
/// `DRAUGHTING_MODEL_ITEM_ASSOCIATION`s (definition → identified annotation).
fn link_faces(m: &mut Mapper<'_>) {
    let aspects = Aspects::new(m);
    let semantic_index: HashMap<u64, usize> = m
        .model
        .pmi
        .semantic
        .items
        .iter()
        .enumerate()
        .map(|(k, item)| (item.step_id(), k))
        .collect();
    // The semantic items applying to each shape aspect.
    let mut semantic_of_aspect: HashMap<u64, usize> = HashMap::new();
    let mut item_faces: Vec<Vec<FaceId>> = Vec::new();
    for (k, item) in m.model.pmi.semantic.items.iter().enumerate() {
        let mut faces = Vec::new();
        for aspect in aspects_of(m, item.step_id()) {
            semantic_of_aspect.entry(aspect).or_insert(k);
            faces.extend(aspects.of(aspect));
        }
        faces.sort_unstable();
        faces.dedup();
        item_faces.push(faces);
    }
    let unlabelled: Vec<u64> = m
        .model
        .pmi
        .semantic
        .items
        .iter()
        .filter(|i| {
            matches!(
                i,
                SemanticItem::Dimension { .. } | SemanticItem::Tolerance { .. }
            )
        })
        .map(SemanticItem::step_id)
        .filter(|&id| !aspects.xcaf_labels(m, id))
        .collect();
    m.model.pmi.semantic.xcaf_unlabelled = unlabelled;
    for (item, faces) in m.model.pmi.semantic.items.iter_mut().zip(item_faces) {
        match item {
            SemanticItem::Dimension { faces: f, .. }
            | SemanticItem::Tolerance { faces: f, .. }
            | SemanticItem::Datum { faces: f, .. }
            | SemanticItem::DatumTarget { faces: f, .. } => *f = faces,
        }
    }
    let annotation_index: HashMap<u64, usize> = m
        .model
        .pmi
        .annotations
        .iter()
        .enumerate()
        .map(|(k, a)| (a.step_id, k))
        .collect();
    // Callout contents stand for their callout.
    let mut callout_of: HashMap<u64, usize> = HashMap::new();
    for (k, a) in m.model.pmi.annotations.iter().enumerate() {
        if a.kind != AnnotationKind::Callout {
            continue;
        }
        if let Ok(inst) = m.inst(a.step_id)
            && let Ok(rec) = Attrs::of(&inst, "DRAUGHTING_CALLOUT")
        {
            let i = if rec.params.len() == 1 { 0 } else { 1 };
            for c in rec.refs(i).unwrap_or_default() {
                callout_of.insert(c, k);
            }
        }
    }
    let mut dmias = m.file.ids_with_keyword("DRAUGHTING_MODEL_ITEM_ASSOCIATION");
    dmias.extend(
        m.file
            .ids_with_keyword("DRAUGHTING_MODEL_ITEM_ASSOCIATION_WITH_PLACEHOLDER"),
    );
    dmias.sort_unstable();
    dmias.dedup();
    for id in dmias {
        let Ok(inst) = m.inst(id) else { continue };
        let Ok(a) = Attrs::first(&inst) else { continue };
        // (name, description, definition, used_representation, identified_item[, placeholder])
        let Some(definition) = a.opt_ref(2) else {
            continue;
        };
        let targets = [a.opt_ref(4), a.opt_ref(5)];
        let semantic = semantic_index
            .get(&definition)
            .copied()
            .or_else(|| semantic_of_aspect.get(&definition).copied());
        let faces = match semantic {
            Some(k) => m.model.pmi.semantic.items[k].faces().to_vec(),
            None => aspects.of(definition),
        };
        for target in targets.into_iter().flatten() {
            let Some(&k) = annotation_index
                .get(&target)
                .or_else(|| callout_of.get(&target))
            else {
                continue;
            };
            let annotation = &mut m.model.pmi.annotations[k];
            annotation.faces.extend_from_slice(&faces);
            annotation.faces.sort_unstable();
            annotation.faces.dedup();
            if annotation.semantic.is_none() {
                annotation.semantic = semantic;
            }
        }
    }
}

/// Saved views: each camera model, and the annotations of the draughting model holding it.
fn map_views(m: &mut Mapper<'_>, models: &[DraughtingModel]) {
    let annotation_index: HashMap<u64, usize> = m
        .model
        .pmi
        .annotations
        .iter()
        .enumerate()
        .map(|(k, a)| (a.step_id, k))
        .collect();
    let mut cameras = m.file.ids_with_keyword("CAMERA_MODEL_D3");
    cameras.extend(m.file.ids_with_keyword("CAMERA_MODEL_D3_MULTI_CLIPPING"));
    cameras.sort_unstable();
    cameras.dedup();
    for id in cameras {
        let holder = models.iter().find(|d| d.items.contains(&id));
        let saved = m.enter_context(holder.map(|d| d.context));
        let view = saved_view(m, id);
        m.restore_units(saved);
        let mut view = match view {
            Ok(v) => v,
            Err(e) => {
                m.report(&e);
                continue;
            }
        };
        view.drawing = holder.is_none();
        if let Some(d) = holder {
            if view.name.trim().is_empty() {
                view.name = d.name.clone();
            }
            let plane_ids: HashSet<u64> = m.model.pmi.planes.iter().map(|p| p.step_id).collect();
            let mut shown: Vec<usize> = Vec::new();
            for &item in &d.items {
                if let Some(&k) = annotation_index.get(&item) {
                    shown.push(k);
                } else if plane_ids.contains(&item) {
                    // An annotation plane in the view shows all its annotations.
                    let plane = m.model.pmi.planes.iter().position(|p| p.step_id == item);
                    shown.extend(
                        m.model
                            .pmi
                            .annotations
                            .iter()
                            .enumerate()
                            .filter(|(_, a)| a.plane.is_some() && a.plane == plane)
                            .map(|(k, _)| k),
                    );
                }
            }
            shown.sort_unstable();
            shown.dedup();
            view.annotations = shown;
        }
        if view.name.trim().is_empty() {
            view.name = format!("#{id}");
        }
        m.model.pmi.views.push(view);
    }
}

fn saved_view(m: &Mapper<'_>, id: u64) -> MapResult<SavedView> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "CAMERA_MODEL_D3").or_else(|_| Attrs::first(&inst))?;
    let frame = m.placement3(a.r#ref(1)?)?;
    let volume = m.inst(a.r#ref(2)?)?;
    let v = Attrs::of(&volume, "VIEW_VOLUME")?;
    let l = m.units.length_to_mm;
    let parallel = v
        .enumeration(0)
        .is_some_and(|e| e.eq_ignore_ascii_case("PARALLEL"));
    let local = |p: Vec3| frame.origin + frame.x * p.x + frame.y * p.y + frame.z * p.z;
    let eye = local(m.point3(v.r#ref(1)?)?);
    let view_plane = v.f64(2)? * l;
    let front = v
        .bool_or(4, false)
        .then(|| v.f64(3).map(|d| d * l))
        .transpose()?;
    let back = v
        .bool_or(6, false)
        .then(|| v.f64(5).map(|d| d * l))
        .transpose()?;
    let window = m.inst(v.r#ref(8)?)?;
    let w = Attrs::first(&window)?;
    let size = (w.f64(1)? * l, w.f64(2)? * l);
    // The window's placement is in the camera's coordinates; its centre is half its size
    // from its corner.
    let window_centre = match w.opt_ref(3).map(|p| m.placement3(p)) {
        Some(Ok(f)) => local(f.origin + f.x * (0.5 * size.0) + f.y * (0.5 * size.1)),
        _ => local(Vec3::new(0.0, 0.0, view_plane)),
    };
    let mut clip_planes = Vec::new();
    if let Ok(c) = Attrs::of(&inst, "CAMERA_MODEL_D3_MULTI_CLIPPING") {
        let list = c.refs(c.params.len().saturating_sub(1)).unwrap_or_default();
        for plane in list {
            if !m.is(plane, "PLANE") {
                m.note(plane, "only planes are read as a saved view's clipping");
                continue;
            }
            let p = m.inst(plane)?;
            let f = m.placement3(Attrs::first(&p)?.r#ref(1)?)?;
            clip_planes.push((f.origin, f.z));
        }
    }
    Ok(SavedView {
        step_id: id,
        name: a.str_or_empty(0),
        origin: frame.origin,
        direction: frame.z,
        up: frame.y,
        parallel,
        eye,
        window: size,
        window_centre,
        view_plane_distance: view_plane,
        front_clip: front,
        back_clip: back,
        clip_planes,
        annotations: Vec::new(),
        part: None,
        drawing: false,
    })
}
