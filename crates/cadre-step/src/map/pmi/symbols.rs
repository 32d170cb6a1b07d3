//! Pre-defined annotation symbols (ISO 10303-46): the terminators of dimension and leader
//! curves (arrows, dots, slashes, boxes, triangles) that AP203/AP214 draughting writes as a
//! `DEFINED_SYMBOL` of a `PRE_DEFINED_TERMINATOR_SYMBOL` (or `PRE_DEFINED_SYMBOL`) placed by a
//! `SYMBOL_TARGET`.
//!
//! The standard names the symbols but gives no geometry, so the shapes are drawn in the
//! target's frame as the corpus files place them: the symbol's point (an arrow's tip) at the
//! target's origin, pointing along its x axis (an arrow at a dimension curve's start has its
//! x axis pointing away from the curve), `x_scale` its length back along −x and `y_scale` its
//! full width across (one file's 7.5 × 2.5 is the usual 3 : 1 drawing arrow).

use super::super::access::Attrs;
use super::super::context::Mapper;
use super::super::error::{MapError, MapResult};
use super::{Drawing, push};
use cadre_brep::pmi::{AnnotationText, TextAlignment};
use cadre_geom::Vec3;

/// Segments of a dot's or a dimension origin's circle.
const CIRCLE_SEGMENTS: usize = 24;

/// Draws the `DEFINED_SYMBOL` `#id` (attributes `a`: name, definition, target) into `drawing`.
pub(super) fn defined_symbol(
    m: &Mapper<'_>,
    id: u64,
    a: &Attrs<'_, '_>,
    drawing: &mut Drawing,
) -> MapResult<()> {
    // A simple instance starts with its name; a complex one's record has no name.
    let at = usize::from(a.params.len() > 2);
    let definition = a.r#ref(at)?;
    let def = m.inst(definition)?;
    let d = Attrs::first(&def)?;
    let lettered = matches!(
        d.keyword,
        "PRE_DEFINED_DIMENSION_SYMBOL"
            | "PRE_DEFINED_GEOMETRICAL_TOLERANCE_SYMBOL"
            | "PRE_DEFINED_POINT_MARKER_SYMBOL"
    );
    if !lettered
        && !matches!(
            d.keyword,
            "PRE_DEFINED_TERMINATOR_SYMBOL" | "PRE_DEFINED_SYMBOL"
        )
    {
        m.note(
            id,
            format!("{}: only pre-defined symbols are drawn", d.keyword),
        );
        return Ok(());
    }
    let name = d.str_or_empty(0).to_ascii_lowercase();
    let target = m.inst(a.r#ref(at + 1)?)?;
    // (name, placement, x_scale, y_scale)
    let t = Attrs::of(&target, "SYMBOL_TARGET")?;
    let frame = m.placement3(t.r#ref(1)?)?;
    let unit = m.units.length_to_mm;
    let (length, width) = (t.f64(2)? * unit, t.f64(3)? * unit);
    if !(length > 0.0 && width > 0.0) {
        return Err(MapError::new(
            id,
            format!(
                "symbol target #{} has a scale that is not positive",
                target.id
            ),
        ));
    }
    if lettered {
        // A dimension, tolerance or marker symbol is a character: centred on the target,
        // as high as its y scale (the corpus's ± sits so before its dimension's value).
        let Some(text) = symbol_character(&name) else {
            m.note(
                id,
                format!("pre-defined symbol {name:?} is not drawn (no character known for it)"),
            );
            return Ok(());
        };
        drawing.texts.push(AnnotationText {
            text: text.to_string(),
            origin: frame.origin,
            x_axis: frame.x,
            y_axis: frame.y,
            height: width,
            alignment: TextAlignment::parse("middle centre"),
        });
        return Ok(());
    }
    let at = |x: f64, y: f64| frame.origin + frame.x * x + frame.y * y;
    let (l, h) = (length, width / 2.0);
    let arrow = [at(-l, h), at(0.0, 0.0), at(-l, -h)];
    let circle = |r: f64| -> Vec<Vec3> {
        (0..=CIRCLE_SEGMENTS)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / CIRCLE_SEGMENTS as f64;
                at(r * t.cos(), r * t.sin())
            })
            .collect()
    };
    let closed = |p: &[Vec3]| -> Vec<Vec3> { p.iter().chain(p.first()).copied().collect() };
    let square = [at(-h, -h), at(h, -h), at(h, h), at(-h, h)];
    let triangle = [at(0.0, -h), at(0.0, h), at(-l, 0.0)];
    match name.as_str() {
        "filled arrow" => {
            drawing.fills.push(arrow);
            push(drawing, closed(&arrow), id)?;
        }
        "open arrow" | "unfilled arrow" => push(drawing, arrow.to_vec(), id)?,
        "blanked arrow" => push(drawing, closed(&arrow), id)?,
        "dimension origin" | "blanked dot" => push(drawing, circle(h), id)?,
        "filled dot" => {
            let ring = circle(h);
            let centre = at(0.0, 0.0);
            drawing
                .fills
                .extend(ring.windows(2).map(|w| [centre, w[0], w[1]]));
            push(drawing, ring, id)?;
        }
        "slash" => push(drawing, vec![at(-h, -h), at(h, h)], id)?,
        "blanked box" => push(drawing, closed(&square), id)?,
        "filled box" => {
            drawing.fills.push([square[0], square[1], square[2]]);
            drawing.fills.push([square[0], square[2], square[3]]);
            push(drawing, closed(&square), id)?;
        }
        "blanked triangle" => push(drawing, closed(&triangle), id)?,
        "filled triangle" => {
            drawing.fills.push(triangle);
            push(drawing, closed(&triangle), id)?;
        }
        other => m.note(
            id,
            format!("pre-defined symbol {other:?} is not drawn (no shape known for it)"),
        ),
    }
    Ok(())
}

/// The character ISO 1101 / ISO 129 draws for a pre-defined dimension, geometric tolerance
/// or point marker symbol (ISO 10303-46 names), `None` for a name not in the standard.
fn symbol_character(name: &str) -> Option<&'static str> {
    Some(match name {
        // Dimension symbols.
        "arc length" => "⌒",
        "conical taper" => "⌳",
        "counterbore" => "⌴",
        "countersink" => "⌵",
        "depth" => "↧",
        "diameter" => "⌀",
        "plus minus" => "±",
        "radius" => "R",
        "slope" => "⌲",
        "spherical diameter" => "S⌀",
        "spherical radius" => "SR",
        "square" => "□",
        // Geometric tolerance symbols.
        "angularity" => "∠",
        "circular runout" => "↗",
        "circularity" => "○",
        "concentricity" => "◎",
        "cylindricity" => "⌭",
        "flatness" => "⏥",
        "parallelism" => "∥",
        "perpendicularity" => "⟂",
        "position" => "⌖",
        "profile of line" => "⌒",
        "profile of surface" => "⌓",
        "straightness" => "⏤",
        "symmetry" => "⌯",
        "total runout" => "⌰",
        // Point markers.
        "asterisk" => "*",
        "circle" => "○",
        "dot" => "•",
        "plus" => "+",
        "triangle" => "△",
        "x" => "×",
        _ => return None,
    })
}

/// Draws the symbol `MAPPED_ITEM` (or `ANNOTATION_SYMBOL`, `ANNOTATION_TEXT`) `#id`
/// (name, mapping source, mapping target) into `drawing`: the items of the
/// mapped representation, read in its mapping origin's frame, scaled by a `SYMBOL_TARGET`'s
/// x and y scales and placed at the target.
pub(super) fn mapped_symbol(
    m: &mut Mapper<'_>,
    id: u64,
    drawing: &mut Drawing,
    text_height: Option<f64>,
    depth: u32,
) -> MapResult<()> {
    let inst = m.inst(id)?;
    // A complex instance carries the mapping in its MAPPED_ITEM record.
    let a = Attrs::of(&inst, "MAPPED_ITEM").or_else(|_| Attrs::first(&inst))?;
    // A simple instance starts with its name; a complex one's record has the mapping only.
    let at = usize::from(a.params.len() > 2);
    let source = m.inst(a.r#ref(at)?)?;
    // (mapping_origin, mapped_representation)
    let map = Attrs::first(&source)?;
    let origin = m.placement3(map.r#ref(0)?)?;
    let representation = m.inst(map.r#ref(1)?)?;
    // (name, items, context)
    let items = super::representation_items(&representation)
        .ok_or_else(|| MapError::new(representation.id, "symbol representation without items"))?;
    let target_id = a.r#ref(at + 1)?;
    let (target, scale) = if m.is(target_id, "SYMBOL_TARGET") {
        let t = m.inst(target_id)?;
        let t = Attrs::of(&t, "SYMBOL_TARGET")?;
        (m.placement3(t.r#ref(1)?)?, (t.f64(2)?, t.f64(3)?))
    } else {
        (m.placement3(target_id)?, (1.0, 1.0))
    };
    if !(scale.0 > 0.0 && scale.1 > 0.0) {
        return Err(MapError::new(
            id,
            format!("symbol target #{target_id} has a scale that is not positive"),
        ));
    }
    let mut own = Drawing::default();
    for item in items {
        // A placement in a symbol's items is its frame, not something to draw.
        if m.is(item, "AXIS2_PLACEMENT_3D") || m.is(item, "AXIS2_PLACEMENT_2D") {
            continue;
        }
        super::geometry(m, item, &mut own, text_height, depth + 1)?;
    }
    let local = |p: Vec3| {
        let d = p - origin.origin;
        (
            d.dot(origin.x) * scale.0,
            d.dot(origin.y) * scale.1,
            d.dot(origin.z),
        )
    };
    let place = |p: Vec3| {
        let (x, y, z) = local(p);
        target.origin + target.x * x + target.y * y + target.z * z
    };
    let turn = |v: Vec3| {
        let (x, y, z) = (
            v.dot(origin.x) * scale.0,
            v.dot(origin.y) * scale.1,
            v.dot(origin.z),
        );
        target.x * x + target.y * y + target.z * z
    };
    for line in own.polylines {
        push(drawing, line.into_iter().map(place).collect(), id)?;
    }
    drawing
        .fills
        .extend(own.fills.into_iter().map(|t| t.map(place)));
    for mut t in own.texts {
        t.origin = place(t.origin);
        t.x_axis = turn(t.x_axis).normalize_or_zero();
        t.y_axis = turn(t.y_axis).normalize_or_zero();
        t.height *= scale.1;
        drawing.texts.push(t);
    }
    drawing.tessellated |= own.tessellated;
    Ok(())
}
