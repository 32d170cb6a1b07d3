//! Presentation: colours and transparency from `STYLED_ITEM`s (and over-riding ones) at solid,
//! shell, face, tessellated-item and part level, and `INVISIBILITY`.

use super::access::Attrs;
use super::context::Mapper;
use super::error::MapResult;
use cadre_brep::model::StyleTarget;
use cadre_brep::{Rgb, Style};

/// How deep style definitions may nest (assignment → usage → side style → fill → colour).
const MAX_STYLE_DEPTH: u32 = 12;

fn colour(m: &Mapper<'_>, id: u64) -> MapResult<Option<Rgb>> {
    let inst = m.inst(id)?;
    if let Some(rec) = inst.record("COLOUR_RGB") {
        let a = Attrs {
            id,
            keyword: rec.keyword,
            params: &rec.params,
        };
        // Complex instances may split the name off into a COLOUR_SPECIFICATION record.
        let o = if rec.params.len() >= 4 { 1 } else { 0 };
        return Ok(Some(Rgb::new(a.f64(o)?, a.f64(o + 1)?, a.f64(o + 2)?)));
    }
    if let Some(rec) = inst.record("DRAUGHTING_PRE_DEFINED_COLOUR") {
        let name = rec.params.first().and_then(|p| p.as_str()).unwrap_or("");
        return Ok(Rgb::predefined(name));
    }
    Ok(None)
}

/// Walks a style definition tree, filling `style`.
fn collect(m: &Mapper<'_>, id: u64, style: &mut Style, depth: u32) -> MapResult<()> {
    if depth > MAX_STYLE_DEPTH {
        return Ok(());
    }
    let inst = m.inst(id)?;
    let a = Attrs::first(&inst)?;
    let refs_in = |i: usize| -> Vec<u64> {
        a.params
            .get(i)
            .and_then(|p| p.as_list())
            .unwrap_or(&[])
            .iter()
            .filter_map(|p| p.as_ref_id())
            .collect()
    };
    match a.keyword {
        "PRESENTATION_STYLE_ASSIGNMENT" | "PRESENTATION_STYLE_BY_CONTEXT" => {
            for s in refs_in(0) {
                collect(m, s, style, depth + 1)?;
            }
        }
        "SURFACE_STYLE_USAGE" => {
            if let Some(s) = a.opt_ref(1) {
                collect(m, s, style, depth + 1)?;
            }
        }
        "SURFACE_SIDE_STYLE" => {
            for s in refs_in(1) {
                collect(m, s, style, depth + 1)?;
            }
        }
        "SURFACE_STYLE_FILL_AREA" => {
            if let Some(s) = a.opt_ref(0) {
                collect(m, s, style, depth + 1)?;
            }
        }
        "FILL_AREA_STYLE" => {
            for s in refs_in(1) {
                collect(m, s, style, depth + 1)?;
            }
        }
        "FILL_AREA_STYLE_COLOUR" => {
            if let Some(c) = a.opt_ref(1) {
                style.color = colour(m, c)?.or(style.color);
            }
        }
        "SURFACE_STYLE_RENDERING" | "SURFACE_STYLE_RENDERING_WITH_PROPERTIES" => {
            if style.color.is_none()
                && let Some(c) = a.opt_ref(1)
            {
                style.color = colour(m, c)?;
            }
            for p in refs_in(2) {
                collect(m, p, style, depth + 1)?;
            }
        }
        "SURFACE_STYLE_TRANSPARENT" => {
            style.transparency = a.f64(0)?.clamp(0.0, 1.0) as f32;
        }
        "CURVE_STYLE" => {
            if let Some(c) = a.opt_ref(3) {
                style.curve_color = colour(m, c)?;
            }
        }
        _ => {}
    }
    Ok(())
}

impl Mapper<'_> {
    /// The model element a styled item points at, in any units it was mapped under.
    fn style_target(&self, item: u64) -> Option<StyleTarget> {
        let keys: Vec<u32> = std::iter::once(0)
            .chain(self.contexts.values().map(|(_, k)| *k))
            .collect();
        for k in keys {
            let key = (item, k);
            if let Some(&s) = self.solids.get(&key) {
                return Some(StyleTarget::Solid(s));
            }
            if let Some(&s) = self.shells.get(&key) {
                return Some(StyleTarget::Shell(s));
            }
            if let Some(&f) = self.faces.get(&key) {
                return Some(StyleTarget::Face(f));
            }
            if let Some(&me) = self.meshes.get(&key) {
                return Some(StyleTarget::Mesh(me));
            }
            if let Some(&e) = self.edges.get(&key) {
                return Some(StyleTarget::Edge(e));
            }
        }
        self.rep_parts
            .get(&item)
            .or_else(|| self.product_parts.get(&item))
            .map(|&p| StyleTarget::Part(p))
    }
}

/// Maps every styled item whose target is in the model.
pub fn map_styles(m: &mut Mapper<'_>) {
    // Plain styles first, then over-riding ones so they win.
    let mut plain = m.file.ids_with_keyword("STYLED_ITEM");
    let overriding = {
        let mut o = m.file.ids_with_keyword("OVER_RIDING_STYLED_ITEM");
        o.extend(
            m.file
                .ids_with_keyword("CONTEXT_DEPENDENT_OVER_RIDING_STYLED_ITEM"),
        );
        o
    };
    plain.retain(|id| !overriding.contains(id));
    for id in plain.into_iter().chain(overriding) {
        if let Err(e) = apply_styled_item(m, id) {
            m.report(&e);
        }
    }
    for id in m.file.ids_with_keyword("INVISIBILITY") {
        let Ok(inst) = m.inst(id) else { continue };
        let Ok(a) = Attrs::first(&inst) else { continue };
        for item in a.refs(0).unwrap_or_default() {
            let target_item = m
                .inst(item)
                .ok()
                .and_then(|i| Attrs::first(&i).ok().and_then(|a| a.opt_ref(2)))
                .unwrap_or(item);
            if let Some(t) = m.style_target(target_item) {
                m.model.styles.entry(t).or_default().invisible = true;
            }
        }
    }
}

fn apply_styled_item(m: &mut Mapper<'_>, id: u64) -> MapResult<()> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "STYLED_ITEM").or_else(|_| Attrs::first(&inst))?;
    // Simple instances carry (name, styles, item); in a complex instance the name lives in the
    // REPRESENTATION_ITEM record and STYLED_ITEM holds (styles, item).
    let o = if inst.complex && a.params.len() == 2 {
        0
    } else {
        1
    };
    let item = a.r#ref(o + 1)?;
    let mut style = Style::default();
    for s in a.refs(o)? {
        collect(m, s, &mut style, 0)?;
    }
    if style == Style::default() {
        return Ok(());
    }
    // A style on a mapped item applies to the representation it places.
    let item = if m.is(item, "MAPPED_ITEM") {
        m.inst(item)
            .ok()
            .and_then(|i| Attrs::first(&i).ok()?.opt_ref(1))
            .and_then(|src| {
                m.inst(src)
                    .ok()?
                    .records
                    .first()?
                    .params
                    .get(1)?
                    .as_ref_id()
            })
            .unwrap_or(item)
    } else {
        item
    };
    if let Some(target) = m.style_target(item) {
        let entry = m.model.styles.entry(target).or_default();
        *entry = style.over(*entry);
    }
    Ok(())
}
