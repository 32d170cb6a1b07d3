//! Units of representation contexts: length (SI prefixes, inch and other conversion-based
//! units), plane angle (radian, degree), and the distance uncertainty.

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use crate::syntax::Instance;
use cadre_brep::Units;

/// Multiplier of an SI prefix (`.MILLI.` → 1e-3).
fn si_prefix(prefix: Option<&str>) -> f64 {
    match prefix {
        Some("EXA") => 1e18,
        Some("PETA") => 1e15,
        Some("TERA") => 1e12,
        Some("GIGA") => 1e9,
        Some("MEGA") => 1e6,
        Some("KILO") => 1e3,
        Some("HECTO") => 1e2,
        Some("DECA") => 1e1,
        Some("DECI") => 1e-1,
        Some("CENTI") => 1e-2,
        Some("MILLI") => 1e-3,
        Some("MICRO") => 1e-6,
        Some("NANO") => 1e-9,
        Some("PICO") => 1e-12,
        Some("FEMTO") => 1e-15,
        Some("ATTO") => 1e-18,
        _ => 1.0,
    }
}

/// What a unit measures, as far as the mapper cares.
#[derive(Clone, Copy, Debug, PartialEq)]
enum UnitKind {
    Length,
    Angle,
    Other,
}

/// A unit's kind, its size in base units (mm for lengths, radians for angles), and a name.
fn unit(m: &Mapper<'_>, id: u64, depth: u32) -> MapResult<(UnitKind, f64, String)> {
    if depth > 8 {
        return Err(MapError::new(
            id,
            "unit conversions nest too deep (cyclic?)",
        ));
    }
    let inst = m.inst(id)?;
    let kind = if inst.has("LENGTH_UNIT") {
        UnitKind::Length
    } else if inst.has("PLANE_ANGLE_UNIT") {
        UnitKind::Angle
    } else {
        UnitKind::Other
    };
    if let Some(rec) = inst.record("SI_UNIT") {
        // Complex form: SI_UNIT(prefix, name); simple form: SI_UNIT(*, prefix, name).
        let p = &rec.params;
        let (prefix, name) = match p.len() {
            2 => (p[0].as_enum(), p[1].as_enum()),
            n if n >= 3 => (p[1].as_enum(), p[2].as_enum()),
            _ => return Err(MapError::new(id, "SI_UNIT: expected prefix and name")),
        };
        let factor = si_prefix(prefix);
        return match name {
            Some("METRE") => Ok((
                UnitKind::Length,
                factor * 1000.0,
                format!(
                    "{}metre",
                    prefix.map(|s| s.to_lowercase()).unwrap_or_default()
                ),
            )),
            Some("RADIAN") => Ok((UnitKind::Angle, factor, "radian".into())),
            Some(other) => Ok((kind, factor, other.to_lowercase())),
            None => Err(MapError::new(id, "SI_UNIT without a unit name")),
        };
    }
    if let Some(rec) = inst.record("CONVERSION_BASED_UNIT") {
        let a = Attrs {
            id,
            keyword: rec.keyword,
            params: &rec.params,
        };
        let name = a.str_or_empty(0);
        let measure = a.r#ref(1)?;
        let (value, base) = measure_with_unit(m, measure)?;
        let (base_kind, base_size, _) = unit(m, base, depth + 1)?;
        let kind = if kind == UnitKind::Other {
            base_kind
        } else {
            kind
        };
        return Ok((kind, value * base_size, name.to_lowercase()));
    }
    Err(MapError::new(
        id,
        "unit is neither SI_UNIT nor CONVERSION_BASED_UNIT",
    ))
}

/// A length given by the `*_MEASURE_WITH_UNIT` `#id`, in mm by its own unit (a width in mm in
/// an inch file is mm); `None` when it is not a length or its unit cannot be read.
pub(super) fn length_mm(m: &Mapper<'_>, id: u64) -> Option<f64> {
    let (value, unit_id) = measure_with_unit(m, id).ok()?;
    match unit(m, unit_id, 0).ok()? {
        (UnitKind::Length, size, _) => Some(value * size),
        _ => None,
    }
}

/// The size of unit `#id` in mm (a length unit) or radians (an angle unit); `None` for
/// another kind of unit or one that cannot be read.
pub(super) fn base_size(m: &Mapper<'_>, id: u64) -> Option<f64> {
    match unit(m, id, 0).ok()? {
        (UnitKind::Length | UnitKind::Angle, size, _) => Some(size),
        _ => None,
    }
}

/// `(value, unit id)` of a `*_MEASURE_WITH_UNIT`.
fn measure_with_unit(m: &Mapper<'_>, id: u64) -> MapResult<(f64, u64)> {
    let inst = m.inst(id)?;
    let rec = inst
        .records
        .iter()
        .find(|r| r.keyword.ends_with("MEASURE_WITH_UNIT"))
        .ok_or_else(|| MapError::new(id, "expected a MEASURE_WITH_UNIT"))?;
    let a = Attrs {
        id,
        keyword: rec.keyword,
        params: &rec.params,
    };
    Ok((a.f64(0)?, a.r#ref(1)?))
}

/// The references in a context record's list (units, uncertainties): the last list parameter,
/// which is the only one in the complex form and follows the name in the simple form.
fn listed_refs<'r>(rec: &'r crate::syntax::Record<'_>) -> impl Iterator<Item = u64> + 'r {
    rec.params
        .iter()
        .rev()
        .find_map(|p| p.as_list())
        .unwrap_or(&[])
        .iter()
        .filter_map(|p| p.as_ref_id())
}

/// Reads the units of a representation context.
fn context_units(m: &Mapper<'_>, inst: &Instance<'_>) -> (Units, Vec<super::MapError>) {
    let mut units = Units::default();
    let mut errors = Vec::new();
    if let Some(rec) = inst.record("GLOBAL_UNIT_ASSIGNED_CONTEXT") {
        for unit_id in listed_refs(rec) {
            match unit(m, unit_id, 0) {
                Ok((UnitKind::Length, size, name)) if size > 0.0 && size.is_finite() => {
                    units.length_to_mm = size;
                    units.length_name = match name.as_str() {
                        "millimetre" => "mm".into(),
                        "centimetre" => "cm".into(),
                        "metre" => "m".into(),
                        _ => name,
                    };
                }
                Ok((UnitKind::Angle, size, name)) if size > 0.0 && size.is_finite() => {
                    units.angle_to_rad = size;
                    units.angle_name = name;
                }
                Ok(_) => {}
                Err(e) => errors.push(e),
            }
        }
    }
    if let Some(rec) = inst.record("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT") {
        for uid in listed_refs(rec) {
            if let Ok((value, _)) = measure_with_unit(m, uid) {
                // Uncertainties are lengths in the context's length unit.
                units.uncertainty_mm = Some(value * units.length_to_mm);
            }
        }
    }
    (units, errors)
}

impl Mapper<'_> {
    /// Makes the units of context `ctx` the ones in force; returns the previous ones so the
    /// caller can restore them with [`Mapper::restore_units`].
    pub fn enter_context(&mut self, ctx: Option<u64>) -> (cadre_brep::Units, u32) {
        let previous = (self.units.clone(), self.units_key);
        let Some(ctx) = ctx else { return previous };
        if !self.contexts.contains_key(&ctx) {
            let (units, errors) = match self.inst(ctx) {
                Ok(inst) => context_units(self, &inst),
                Err(e) => (Units::default(), vec![e]),
            };
            for e in &errors {
                self.report(e);
            }
            // Contexts with identical units share cache keys, so geometry shared between
            // them is mapped once.
            let key = self
                .contexts
                .values()
                .find(|(u, _)| *u == units)
                .map(|(_, k)| *k)
                .unwrap_or(self.contexts.len() as u32 + 1);
            if self.contexts.is_empty() {
                self.model.units = units.clone();
            }
            self.contexts.insert(ctx, (units, key));
        }
        let (units, key) = self.contexts[&ctx].clone();
        self.units = units;
        self.units_key = key;
        previous
    }

    /// Restores units saved by [`Mapper::enter_context`].
    pub fn restore_units(&mut self, saved: (cadre_brep::Units, u32)) {
        self.units = saved.0;
        self.units_key = saved.1;
    }
}
