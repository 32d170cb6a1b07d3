//! Points, directions, placements, curves (3D and parameter-space) and surfaces.
//!
//! Model-space geometry is converted to millimetres and radians as it is mapped. Curves in a
//! surface's parameter space (pcurves) are mapped in the file's raw units first ([`S2`]) and
//! scaled to the surface's own (mm, radian) parameters by [`scale_pcurve`].

use std::f64::consts::PI;

use super::access::Attrs;
use super::context::Mapper;
use super::error::{MapError, MapResult};
use crate::syntax::{Instance, Param};
use cadre_brep::{CurveId, SurfaceId};
use cadre_geom::bspline::{ControlPoint, expand_knots};
use cadre_geom::curve::{CompositeSegment, CurveFrame};
use cadre_geom::{
    Accuracy, BSplineCurve, BSplineSurface, Curve, Curve2, Curve3, Frame, Surface, Transform, Vec2,
    Vec3,
};

/// B-splines with more control points or knots than this in one direction are refused: no real
/// model needs them, and a corrupt count must not allocate without bound.
const MAX_BSPLINE_POINTS: usize = 1 << 20;

/// The dimension a curve is mapped in: model space ([`S3`]) or parameter space ([`S2`]).
pub trait Space {
    /// Point type.
    type P: ControlPoint
        + cadre_geom::point::GeomPoint
        + std::fmt::Debug
        + PartialEq
        + std::ops::Mul<f64, Output = Self::P>
        + std::ops::Add<Output = Self::P>
        + std::ops::Sub<Output = Self::P>;
    /// How many coordinates a point of this space has.
    const DIM: usize;
    /// The point from a coordinate list (2 or 3 values).
    fn from_coords(c: &[f64]) -> Option<Self::P>;
    /// Length unit conversion applied to coordinates and distances.
    fn length(m: &Mapper<'_>) -> f64;
    /// The placement of a conic.
    fn placement(m: &mut Mapper<'_>, id: u64) -> MapResult<CurveFrame<Self::P>>;
    /// Unit length of a point/vector (for normalising directions).
    fn norm(p: Self::P) -> f64;
}

/// Model space: millimetres.
pub struct S3;
/// A surface's parameter space, in the file's raw units.
pub struct S2;

impl Space for S3 {
    type P = Vec3;
    const DIM: usize = 3;
    fn from_coords(c: &[f64]) -> Option<Vec3> {
        match *c {
            [x, y, z, ..] => Some(Vec3::new(x, y, z)),
            [x, y] => Some(Vec3::new(x, y, 0.0)),
            [x] => Some(Vec3::new(x, 0.0, 0.0)),
            [] => None,
        }
    }
    fn length(m: &Mapper<'_>) -> f64 {
        m.units.length_to_mm
    }
    fn placement(m: &mut Mapper<'_>, id: u64) -> MapResult<CurveFrame<Vec3>> {
        if m.is(id, "AXIS2_PLACEMENT_2D") {
            let f = placement_2d(m, id, m.units.length_to_mm)?;
            return Ok(CurveFrame {
                origin: f.origin.extend(0.0),
                x: f.x.extend(0.0),
                y: f.y.extend(0.0),
            });
        }
        Ok(m.placement3(id)?.into())
    }
    fn norm(p: Vec3) -> f64 {
        p.length()
    }
}

impl Space for S2 {
    type P = Vec2;
    const DIM: usize = 2;
    fn from_coords(c: &[f64]) -> Option<Vec2> {
        match *c {
            [x, y, ..] => Some(Vec2::new(x, y)),
            [x] => Some(Vec2::new(x, 0.0)),
            [] => None,
        }
    }
    fn length(_: &Mapper<'_>) -> f64 {
        1.0
    }
    fn placement(m: &mut Mapper<'_>, id: u64) -> MapResult<CurveFrame<Vec2>> {
        placement_2d(m, id, 1.0)
    }
    fn norm(p: Vec2) -> f64 {
        p.length()
    }
}

fn placement_2d(m: &Mapper<'_>, id: u64, scale: f64) -> MapResult<CurveFrame<Vec2>> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "AXIS2_PLACEMENT_2D")?;
    let origin = point::<S2>(m, a.r#ref(1)?)? * scale;
    let x = match a.opt_ref(2) {
        Some(d) => m.direction(d)?.truncate().try_normalize(),
        None => Some(Vec2::X),
    }
    .ok_or_else(|| a.err("reference direction has zero length"))?;
    Ok(CurveFrame {
        origin,
        x,
        y: x.perp(),
    })
}

/// A `CARTESIAN_POINT` in space `S`, scaled by the length unit.
pub fn point<S: Space>(m: &Mapper<'_>, id: u64) -> MapResult<S::P> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "CARTESIAN_POINT")?;
    let c = a.f64s(1)?;
    let p = S::from_coords(&c).ok_or_else(|| a.err("has no coordinates"))?;
    if c.len() < S::DIM {
        // Read as lying in z = 0 (or v = 0), which is what a 2D point placed in a 3D context
        // most likely means, but the geometry may not be where its author meant it.
        let missing = if S::DIM - c.len() == 1 {
            "z"
        } else {
            "y and z"
        };
        m.note(
            id,
            format!(
                "CARTESIAN_POINT has {} coordinate(s) where {} are needed; {missing} = 0 assumed",
                c.len(),
                S::DIM
            ),
        );
    }
    Ok(p * S::length(m))
}

impl Mapper<'_> {
    /// A `CARTESIAN_POINT` in model space (mm).
    pub fn point3(&self, id: u64) -> MapResult<Vec3> {
        point::<S3>(self, id)
    }

    /// A `DIRECTION` (not normalised; 2D directions get z = 0).
    pub fn direction(&self, id: u64) -> MapResult<Vec3> {
        let inst = self.inst(id)?;
        let a = Attrs::of(&inst, "DIRECTION")?;
        let c = a.f64s(1)?;
        S3::from_coords(&c).ok_or_else(|| a.err("has no components"))
    }

    /// An `AXIS2_PLACEMENT_3D` (or an `AXIS1_PLACEMENT`, as a frame around its axis).
    pub fn placement3(&self, id: u64) -> MapResult<Frame> {
        let inst = self.inst(id)?;
        let a = Attrs::first(&inst)?;
        if a.keyword == "AXIS2_PLACEMENT_2D" {
            // Its point has two coordinates: read as 2D, not as a 3D point missing one.
            let f = placement_2d(self, id, self.units.length_to_mm)?;
            return Ok(Frame {
                origin: f.origin.extend(0.0),
                x: f.x.extend(0.0),
                y: f.y.extend(0.0),
                z: Vec3::Z,
            });
        }
        let origin = self.point3(a.r#ref(1)?)?;
        let axis = match a.opt_ref(2) {
            Some(d) => self.direction(d)?,
            None => Vec3::Z,
        };
        let ref_dir = match a.keyword {
            "AXIS2_PLACEMENT_3D" => a.opt_ref(3).map(|d| self.direction(d)).transpose()?,
            "AXIS1_PLACEMENT" => None,
            "AXIS2_PLACEMENT_2D" => {
                let f = placement_2d(self, id, self.units.length_to_mm)?;
                return Ok(Frame {
                    origin: f.origin.extend(0.0),
                    x: f.x.extend(0.0),
                    y: f.y.extend(0.0),
                    z: Vec3::Z,
                });
            }
            other => return Err(a.err(format!("{other} is not an axis placement"))),
        };
        if let Some(r) = ref_dir
            && let Some(z) = axis.try_normalize()
            && (r - z * r.dot(z)).try_normalize().is_none()
        {
            // ISO 10303-42 requires them not to be parallel; `from_axis` then picks an
            // arbitrary perpendicular, so whatever the placement orients (a cylinder's seam,
            // a part's rotation) may not be what the author meant.
            self.note(
                id,
                "reference direction is parallel to the axis (or has zero length); an arbitrary perpendicular direction is used",
            );
        }
        Frame::from_axis(origin, axis, ref_dir).ok_or_else(|| a.err("axis has zero length"))
    }

    /// A placement or a `CARTESIAN_TRANSFORMATION_OPERATOR_3D` as an affine transform
    /// (local → containing coordinates, mm).
    pub fn transform(&self, id: u64) -> MapResult<Transform> {
        let inst = self.inst(id)?;
        if let Some(rec) = inst
            .records
            .iter()
            .find(|r| r.keyword.starts_with("CARTESIAN_TRANSFORMATION_OPERATOR"))
        {
            // Written with one or two leading names depending on the exporter: skip strings.
            let p: Vec<&Param<'_>> = rec
                .params
                .iter()
                .skip_while(|p| matches!(p, Param::String(_)))
                .collect();
            let dir = |i: usize| -> MapResult<Option<Vec3>> {
                p.get(i)
                    .and_then(|p| p.as_ref_id())
                    .map(|d| self.direction(d))
                    .transpose()
            };
            let (axis1, axis2) = (dir(0)?, dir(1)?);
            let origin = match p.get(2).and_then(|p| p.as_ref_id()) {
                Some(o) => self.point3(o)?,
                None => Vec3::ZERO,
            };
            let scale = p.get(3).and_then(|p| p.as_f64()).unwrap_or(1.0);
            let axis3 = dir(4)?;
            if !(scale.is_finite() && scale > 0.0) {
                return Err(MapError::new(id, "transformation scale is not positive"));
            }
            // ISO 10303-42 base_axis: normalise, fill in missing axes, orthogonalise.
            let z = axis3.and_then(|v| v.try_normalize()).unwrap_or(Vec3::Z);
            let frame = Frame::from_axis(Vec3::ZERO, z, axis1)
                .ok_or_else(|| MapError::new(id, "degenerate transformation axes"))?;
            let mut y = frame.y;
            if let Some(a2) = axis2.and_then(|v| v.try_normalize())
                && a2.dot(frame.y) < 0.0
            {
                // A mirrored operator.
                y = -y;
            }
            return Ok(Transform::from_cols(
                frame.x * scale,
                y * scale,
                frame.z * scale,
                origin,
            ));
        }
        Ok(self.placement3(id)?.to_transform())
    }

    /// A `VECTOR` in model space: direction times magnitude (mm).
    fn vector3(&self, id: u64) -> MapResult<Vec3> {
        vector::<S3>(self, id)
    }

    /// The 3D curve `id`, mapped once per units and stored in the model.
    pub fn curve_id(&mut self, id: u64) -> MapResult<CurveId> {
        if let Some(&c) = self.curves.get(&self.key(id)) {
            return Ok(c);
        }
        let curve = self.nested(id, |m| curve::<S3>(m, id))?;
        let cid = CurveId(self.model.curves.len() as u32);
        self.model.curves.push(curve);
        self.curves.insert(self.key(id), cid);
        Ok(cid)
    }

    /// The surface `id`, mapped once per units and stored in the model.
    pub fn surface_id(&mut self, id: u64) -> MapResult<SurfaceId> {
        if let Some(&s) = self.surfaces.get(&self.key(id)) {
            return Ok(s);
        }
        let surface = self.nested(id, |m| surface(m, id))?;
        let sid = SurfaceId(self.model.surfaces.len() as u32);
        self.model.surfaces.push(surface);
        self.surfaces.insert(self.key(id), sid);
        Ok(sid)
    }

    /// A curve in a surface's parameter space (raw file units).
    pub fn curve2(&mut self, id: u64) -> MapResult<Curve2> {
        self.nested(id, |m| curve::<S2>(m, id))
    }
}

fn vector<S: Space>(m: &Mapper<'_>, id: u64) -> MapResult<S::P> {
    let inst = m.inst(id)?;
    let a = Attrs::of(&inst, "VECTOR")?;
    let d = m.direction(a.r#ref(1)?)?;
    let mag = a.f64(2)?;
    let d = S::from_coords(&[d.x, d.y, d.z]).ok_or_else(|| a.err("bad direction"))?;
    let n = S::norm(d);
    if n == 0.0 {
        return Err(a.err("direction has zero length"));
    }
    Ok(d * (mag * S::length(m) / n))
}

/// Whether the curve's parameter is an angle (so trimming parameters use the angle unit).
fn angular<P>(c: &Curve<P>) -> bool {
    matches!(c, Curve::Circle { .. } | Curve::Ellipse { .. })
}

/// A curve of dimension `S`.
pub fn curve<S: Space>(m: &mut Mapper<'_>, id: u64) -> MapResult<Curve<S::P>> {
    let inst = m.inst(id)?;
    if inst.has("B_SPLINE_CURVE")
        || inst.has("B_SPLINE_CURVE_WITH_KNOTS")
        || inst.has("BEZIER_CURVE")
        || inst.has("UNIFORM_CURVE")
        || inst.has("QUASI_UNIFORM_CURVE")
    {
        return Ok(Curve::BSpline(bspline_curve::<S>(m, &inst)?));
    }
    // Curves on surfaces are also written as complex instances (BOUNDED_CURVE() CURVE() …
    // SURFACE_CURVE(curve_3d, …)) whose record has no leading name.
    if let Some(rec) = inst.records.iter().find(|r| {
        matches!(
            r.keyword,
            "SURFACE_CURVE" | "SEAM_CURVE" | "INTERSECTION_CURVE" | "BOUNDED_SURFACE_CURVE"
        )
    }) {
        let o = usize::from(!inst.complex);
        let c = rec
            .params
            .get(o)
            .and_then(|p| p.as_ref_id())
            .ok_or_else(|| MapError::new(id, format!("{}: no 3D curve", rec.keyword)))?;
        return m.nested(id, |m| curve::<S>(m, c));
    }
    let a = Attrs::first(&inst)?;
    let l = S::length(m);
    match a.keyword {
        "LINE" => Ok(Curve::Line {
            origin: point::<S>(m, a.r#ref(1)?)?,
            direction: vector::<S>(m, a.r#ref(2)?)?,
        }),
        "CIRCLE" => {
            let radius = a.f64(2)? * l;
            positive(&a, radius, "radius")?;
            Ok(Curve::Circle {
                frame: S::placement(m, a.r#ref(1)?)?,
                radius,
            })
        }
        "ELLIPSE" => {
            let (ra, rb) = (a.f64(2)? * l, a.f64(3)? * l);
            positive(&a, ra.min(rb), "semi-axis")?;
            Ok(Curve::Ellipse {
                frame: S::placement(m, a.r#ref(1)?)?,
                a: ra,
                b: rb,
            })
        }
        "PARABOLA" => Ok(Curve::Parabola {
            frame: S::placement(m, a.r#ref(1)?)?,
            focal: a.f64(2)? * l,
        }),
        "HYPERBOLA" => Ok(Curve::Hyperbola {
            frame: S::placement(m, a.r#ref(1)?)?,
            a: a.f64(2)? * l,
            b: a.f64(3)? * l,
        }),
        "POLYLINE" => {
            let ids = a.refs(1)?;
            if ids.len() < 2 {
                return Err(a.err("polyline needs at least two points"));
            }
            let pts = ids
                .iter()
                .map(|&p| point::<S>(m, p))
                .collect::<MapResult<Vec<_>>>()?;
            Ok(Curve::Polyline(pts))
        }
        "TRIMMED_CURVE" => trimmed_curve::<S>(m, &a),
        "COMPOSITE_CURVE"
        | "COMPOSITE_CURVE_ON_SURFACE"
        | "BOUNDARY_CURVE"
        | "OUTER_BOUNDARY_CURVE" => {
            let mut segments = Vec::new();
            for seg in a.refs(1)? {
                let s_inst = m.inst(seg)?;
                let s = Attrs::of(&s_inst, "COMPOSITE_CURVE_SEGMENT")?;
                let same_sense = s.bool_or(1, true);
                let parent = s.r#ref(2)?;
                let curve = m.nested(seg, |m| curve::<S>(m, parent))?;
                segments.push(CompositeSegment { curve, same_sense });
            }
            if segments.is_empty() {
                return Err(a.err("composite curve has no segments"));
            }
            Ok(Curve::Composite(segments))
        }
        "OFFSET_CURVE_3D" | "OFFSET_CURVE_2D" => {
            let basis = a.r#ref(1)?;
            let distance = a.f64(2)? * l;
            let ref_direction = match a.opt_ref(4) {
                Some(d) => m.direction(d)?,
                None => Vec3::Z,
            };
            let basis = m.nested(id, |m| curve::<S>(m, basis))?;
            Ok(Curve::Offset {
                basis: Box::new(basis),
                distance,
                ref_direction,
            })
        }
        "DEGENERATE_PCURVE" | "PCURVE" => Err(a.err("curve exists only on a surface")),
        other => Err(a.err(format!("unsupported curve type {other}"))),
    }
}

fn positive(a: &Attrs<'_, '_>, v: f64, what: &str) -> MapResult<()> {
    if v > 0.0 {
        Ok(())
    } else {
        Err(a.err(format!("{what} must be positive, got {v}")))
    }
}

/// A `TRIMMED_CURVE`: parameters from `PARAMETER_VALUE`s, or from points projected on the
/// basis when the file gives only points (or says points are the master representation).
fn trimmed_curve<S: Space>(m: &mut Mapper<'_>, a: &Attrs<'_, '_>) -> MapResult<Curve<S::P>> {
    let basis_id = a.r#ref(1)?;
    let basis = m.nested(a.id, |m| curve::<S>(m, basis_id))?;
    let sense = a.bool_or(4, true);
    let prefer_points = a.enumeration(5) == Some("CARTESIAN");
    let angle = if angular(&basis) {
        m.units.angle_to_rad
    } else {
        1.0
    };
    let trim = |i: usize| -> MapResult<f64> {
        let select = a.list(i)?;
        let param = select.iter().find_map(|p| match p {
            Param::Typed { keyword, value } if *keyword == "PARAMETER_VALUE" => value.as_f64(),
            Param::Real(r) => Some(*r),
            _ => None,
        });
        let pt = select.iter().find_map(Param::as_ref_id);
        match (param, pt) {
            (Some(t), None) => Ok(t * angle),
            (Some(t), Some(_)) if !prefer_points => Ok(t * angle),
            (_, Some(p)) => {
                let p = point::<S>(m, p)?;
                basis
                    .project(p, None, Accuracy::default())
                    .ok_or_else(|| a.err("trimming point does not project onto the basis curve"))
            }
            (None, None) => Err(a.err(format!("trim {} has neither parameter nor point", i - 1))),
        }
    };
    let t0 = trim(2)?;
    let t1 = trim(3)?;
    if !(t0.is_finite() && t1.is_finite()) {
        return Err(a.err("trimming parameters are not finite"));
    }
    Ok(Curve::Trimmed {
        basis: Box::new(basis),
        t0,
        t1,
        sense,
    })
}

/// The attributes of a B-spline's base record and the position of its first own attribute:
/// simple instances carry the name first and every inherited attribute, complex ones one record
/// per type with that type's attributes only.
fn base_attrs<'i, 'a>(inst: &'i Instance<'a>, keyword: &str) -> (Attrs<'i, 'a>, usize) {
    let (base, offset) = match inst.record(keyword) {
        Some(rec) if inst.complex => (rec, 0),
        _ => (&inst.records[0], 1),
    };
    (
        Attrs {
            id: inst.id,
            keyword: base.keyword,
            params: &base.params,
        },
        offset,
    )
}

/// Knot multiplicities: counts, with a bound on their sum so a corrupt file cannot make the
/// knot vector allocate without limit.
fn multiplicities(k: &Attrs<'_, '_>, i: usize) -> MapResult<Vec<usize>> {
    let m = k
        .list(i)?
        .iter()
        .map(|p| p.as_i64().and_then(|v| usize::try_from(v).ok()))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| k.err("knot multiplicities are not counts"))?;
    if m.iter().fold(0usize, |a, &b| a.saturating_add(b)) > MAX_BSPLINE_POINTS * 2 {
        return Err(k.err("knot multiplicities are beyond reason"));
    }
    Ok(m)
}

/// Degree, control points, knots and weights of a B-spline curve in either instance form.
fn bspline_curve<S: Space>(m: &Mapper<'_>, inst: &Instance<'_>) -> MapResult<BSplineCurve<S::P>> {
    let (a, offset) = base_attrs(inst, "B_SPLINE_CURVE");
    let degree = a.usize(offset)?;
    let ids = a.refs(offset + 1)?;
    if ids.len() > MAX_BSPLINE_POINTS {
        return Err(a.err(format!("{} control points is beyond reason", ids.len())));
    }
    let points = ids
        .iter()
        .map(|&p| point::<S>(m, p))
        .collect::<MapResult<Vec<_>>>()?;
    let n = points.len();
    let knots = if let Some(rec) = inst.record("B_SPLINE_CURVE_WITH_KNOTS") {
        let k = Attrs {
            id: inst.id,
            keyword: rec.keyword,
            params: &rec.params,
        };
        let o = if inst.complex { 0 } else { offset + 5 };
        let mults = multiplicities(&k, o)?;
        let values = k.f64s(o + 1)?;
        expand_knots(&values, &mults).map_err(|e| k.err(e.to_string()))?
    } else if inst.has("UNIFORM_CURVE") {
        (0..n + degree + 1)
            .map(|i| i as f64 - degree as f64)
            .collect()
    } else if inst.has("QUASI_UNIFORM_CURVE") {
        quasi_uniform_knots(n, degree)
    } else {
        bezier_knots(n, degree)
    };
    let weights = match inst.record("RATIONAL_B_SPLINE_CURVE") {
        Some(rec) => {
            let w = Attrs {
                id: inst.id,
                keyword: rec.keyword,
                params: &rec.params,
            };
            Some(w.f64s(0)?)
        }
        None => None,
    };
    let mut c = BSplineCurve::try_new(degree, knots, points, weights)
        .map_err(|e| MapError::new(inst.id, format!("B-spline curve: {e}")))?;
    c.closed = c.ends_meet();
    Ok(c)
}

/// Clamped knots with uniform interior spacing (ISO 10303-42 quasi-uniform).
fn quasi_uniform_knots(n: usize, p: usize) -> Vec<f64> {
    let spans = n.saturating_sub(p).max(1);
    let mut k = vec![0.0; p + 1];
    k.extend((1..spans).map(|i| i as f64));
    k.extend(std::iter::repeat_n(spans as f64, p + 1));
    k
}

/// Knots of a piecewise Bézier curve of `n` points and degree `p` (one span per `p` points).
fn bezier_knots(n: usize, p: usize) -> Vec<f64> {
    if p == 0 {
        return Vec::new();
    }
    let spans = (n.saturating_sub(1) / p).max(1);
    let mut k = vec![0.0; p + 1];
    for s in 1..spans {
        k.extend(std::iter::repeat_n(s as f64, p));
    }
    k.extend(std::iter::repeat_n(spans as f64, p + 1));
    k
}

/// A surface in model space (mm, radians).
pub fn surface(m: &mut Mapper<'_>, id: u64) -> MapResult<Surface> {
    let inst = m.inst(id)?;
    if inst.has("B_SPLINE_SURFACE")
        || inst.has("B_SPLINE_SURFACE_WITH_KNOTS")
        || inst.has("BEZIER_SURFACE")
        || inst.has("UNIFORM_SURFACE")
        || inst.has("QUASI_UNIFORM_SURFACE")
    {
        return Ok(Surface::BSpline(Box::new(bspline_surface(m, &inst)?)));
    }
    let a = Attrs::first(&inst)?;
    let l = m.units.length_to_mm;
    match a.keyword {
        "PLANE" => Ok(Surface::Plane {
            frame: m.placement3(a.r#ref(1)?)?,
        }),
        "CYLINDRICAL_SURFACE" => {
            let radius = a.f64(2)? * l;
            positive(&a, radius, "radius")?;
            Ok(Surface::Cylinder {
                frame: m.placement3(a.r#ref(1)?)?,
                radius,
            })
        }
        "CONICAL_SURFACE" => {
            let radius = a.f64(2)? * l;
            let semi_angle = a.f64(3)? * m.units.angle_to_rad;
            if !(radius >= 0.0 && semi_angle.abs() > 0.0 && semi_angle.abs() < PI / 2.0) {
                return Err(a.err(format!(
                    "cone radius {radius} / semi-angle {semi_angle} rad out of range (angle unit {})",
                    m.units.angle_name
                )));
            }
            Ok(Surface::Cone {
                frame: m.placement3(a.r#ref(1)?)?,
                radius,
                semi_angle,
            })
        }
        "SPHERICAL_SURFACE" => {
            let radius = a.f64(2)? * l;
            positive(&a, radius, "radius")?;
            Ok(Surface::Sphere {
                frame: m.placement3(a.r#ref(1)?)?,
                radius,
            })
        }
        "TOROIDAL_SURFACE" | "DEGENERATE_TOROIDAL_SURFACE" => {
            let (major, minor) = (a.f64(2)? * l, a.f64(3)? * l);
            positive(&a, minor, "minor radius")?;
            if major < 0.0 {
                return Err(a.err("major radius is negative"));
            }
            Ok(Surface::Torus {
                frame: m.placement3(a.r#ref(1)?)?,
                major_radius: major,
                minor_radius: minor,
            })
        }
        "SURFACE_OF_REVOLUTION" => {
            let profile = m.curve_or_nested(a.r#ref(1)?)?;
            let axis = m.placement3(a.r#ref(2)?)?;
            Ok(Surface::Revolution {
                profile: Box::new(profile),
                axis_origin: axis.origin,
                axis_direction: axis.z,
            })
        }
        "SURFACE_OF_LINEAR_EXTRUSION" => {
            let profile = m.curve_or_nested(a.r#ref(1)?)?;
            let direction = m.vector3(a.r#ref(2)?)?;
            Ok(Surface::Extrusion {
                profile: Box::new(profile),
                direction,
            })
        }
        "OFFSET_SURFACE" => {
            let basis = a.r#ref(1)?;
            let distance = a.f64(2)? * l;
            let basis = m.nested(id, |m| surface(m, basis))?;
            Ok(Surface::Offset {
                basis: Box::new(basis),
                distance,
            })
        }
        "RECTANGULAR_TRIMMED_SURFACE" => {
            let basis_id = a.r#ref(1)?;
            let basis = m.nested(id, |m| surface(m, basis_id))?;
            let (su, sv) = parameter_scale(&basis, &m.units);
            Ok(Surface::Trimmed {
                basis: Box::new(basis),
                u0: a.f64(2)? * su,
                u1: a.f64(3)? * su,
                v0: a.f64(4)? * sv,
                v1: a.f64(5)? * sv,
            })
        }
        "CURVE_BOUNDED_SURFACE" => {
            // The face's own bounds trim it; the boundaries repeat them.
            let basis = a.r#ref(1)?;
            m.nested(id, |m| surface(m, basis))
        }
        other => Err(a.err(format!("unsupported surface type {other}"))),
    }
}

impl Mapper<'_> {
    fn curve_or_nested(&mut self, id: u64) -> MapResult<Curve3> {
        self.nested(id, |m| curve::<S3>(m, id))
    }
}

fn bspline_surface(m: &Mapper<'_>, inst: &Instance<'_>) -> MapResult<BSplineSurface> {
    let (a, offset) = base_attrs(inst, "B_SPLINE_SURFACE");
    let (pu, pv) = (a.usize(offset)?, a.usize(offset + 1)?);
    let rows = a.list(offset + 2)?;
    if rows.len() > MAX_BSPLINE_POINTS {
        return Err(a.err("control net is beyond reason"));
    }
    let mut net = Vec::with_capacity(rows.len());
    let mut total = 0usize;
    for row in rows {
        let ids = row
            .as_list()
            .ok_or_else(|| a.err("control net row is not a list"))?;
        total += ids.len();
        if total > MAX_BSPLINE_POINTS * 4 {
            return Err(a.err("control net is beyond reason"));
        }
        net.push(
            ids.iter()
                .map(|p| {
                    p.as_ref_id()
                        .ok_or_else(|| a.err("control point is not a reference"))
                        .and_then(|p| m.point3(p))
                })
                .collect::<MapResult<Vec<_>>>()?,
        );
    }
    let (u_closed, v_closed) = (a.bool_or(offset + 4, false), a.bool_or(offset + 5, false));
    let nu = net.len();
    let nv = net.first().map_or(0, Vec::len);
    let (u_knots, v_knots) = if let Some(rec) = inst.record("B_SPLINE_SURFACE_WITH_KNOTS") {
        let k = Attrs {
            id: inst.id,
            keyword: rec.keyword,
            params: &rec.params,
        };
        let o = if inst.complex { 0 } else { offset + 7 };
        let (mu, mv) = (multiplicities(&k, o)?, multiplicities(&k, o + 1)?);
        (
            expand_knots(&k.f64s(o + 2)?, &mu).map_err(|e| k.err(e.to_string()))?,
            expand_knots(&k.f64s(o + 3)?, &mv).map_err(|e| k.err(e.to_string()))?,
        )
    } else if inst.has("UNIFORM_SURFACE") {
        let uni = |n: usize, p: usize| (0..n + p + 1).map(|i| i as f64 - p as f64).collect();
        (uni(nu, pu), uni(nv, pv))
    } else if inst.has("QUASI_UNIFORM_SURFACE") {
        (quasi_uniform_knots(nu, pu), quasi_uniform_knots(nv, pv))
    } else {
        (bezier_knots(nu, pu), bezier_knots(nv, pv))
    };
    let weights = match inst.record("RATIONAL_B_SPLINE_SURFACE") {
        Some(rec) => {
            let w = Attrs {
                id: inst.id,
                keyword: rec.keyword,
                params: &rec.params,
            };
            let rows = w.list(0)?;
            Some(
                rows.iter()
                    .map(|r| {
                        let r = r
                            .as_list()
                            .ok_or_else(|| w.err("weights row is not a list"))?;
                        super::access::list_f64(&w, r, 0)
                    })
                    .collect::<MapResult<Vec<_>>>()?,
            )
        }
        None => None,
    };
    let mut s = BSplineSurface::try_new(pu, pv, u_knots, v_knots, net, weights)
        .map_err(|e| MapError::new(inst.id, format!("B-spline surface: {e}")))?;
    s.u_closed = u_closed;
    s.v_closed = v_closed;
    Ok(s)
}

/// How the file's raw (u, v) parameters of `surface` convert to ours: lengths to mm, angles to
/// radians, B-spline and curve parameters unchanged.
pub fn parameter_scale(surface: &Surface, units: &cadre_brep::Units) -> (f64, f64) {
    let (l, a) = (units.length_to_mm, units.angle_to_rad);
    match surface {
        Surface::Plane { .. } => (l, l),
        Surface::Cylinder { .. } | Surface::Cone { .. } => (a, l),
        Surface::Sphere { .. } | Surface::Torus { .. } => (a, a),
        Surface::Revolution { .. } => (a, 1.0),
        Surface::BSpline(_) | Surface::Extrusion { .. } => (1.0, 1.0),
        Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => {
            parameter_scale(basis, units)
        }
    }
}

/// Scales a pcurve from raw file parameters to the surface's parameters. Exact for every curve
/// when both scales agree; with different scales (degrees × mm on a cylinder) conics cannot be
/// scaled exactly and are refused.
pub fn scale_pcurve(c: Curve2, su: f64, sv: f64) -> Option<Curve2> {
    if su == 1.0 && sv == 1.0 {
        return Some(c);
    }
    let s = |p: Vec2| Vec2::new(p.x * su, p.y * sv);
    let uniform = (su - sv).abs() <= 1e-15 * su.abs().max(sv.abs());
    Some(match c {
        Curve::Line { origin, direction } => Curve::Line {
            origin: s(origin),
            direction: s(direction),
        },
        Curve::Polyline(p) => Curve::Polyline(p.into_iter().map(s).collect()),
        Curve::BSpline(mut b) => {
            b.control_points.iter_mut().for_each(|p| *p = s(*p));
            Curve::BSpline(b)
        }
        Curve::Circle { frame, radius } if uniform => Curve::Circle {
            frame: CurveFrame {
                origin: s(frame.origin),
                ..frame
            },
            radius: radius * su,
        },
        Curve::Ellipse { frame, a, b } if uniform => Curve::Ellipse {
            frame: CurveFrame {
                origin: s(frame.origin),
                ..frame
            },
            a: a * su,
            b: b * su,
        },
        Curve::Trimmed {
            basis,
            t0,
            t1,
            sense,
        } => Curve::Trimmed {
            basis: Box::new(scale_pcurve(*basis, su, sv)?),
            t0,
            t1,
            sense,
        },
        Curve::Composite(segs) => Curve::Composite(
            segs.into_iter()
                .map(|seg| {
                    Some(CompositeSegment {
                        curve: scale_pcurve(seg.curve, su, sv)?,
                        same_sense: seg.same_sense,
                    })
                })
                .collect::<Option<Vec<_>>>()?,
        ),
        _ => return None,
    })
}
