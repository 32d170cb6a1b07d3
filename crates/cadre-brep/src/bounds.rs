//! Bounding boxes of faces, parts and whole models, from the exact geometry.
//!
//! A face's box is the box of its edges plus, for a curved face, the box of its support
//! surface over the face's (u, v) bounds (found by projecting edge samples onto the surface).
//! This is what OCCT's `BRepBndLib::Add` measures too, so the two agree closely; it can only
//! overestimate a face whose (u, v) rectangle is larger than the face itself.

use std::f64::consts::FRAC_PI_2;

mod model;

use crate::topology::{Edge, Face, LoopKind};
use crate::{EdgeId, Model};
use cadre_geom::{Accuracy, BoundingBox, Curve3, Surface, Transform, Vec3};

/// Samples taken along each edge to find a face's (u, v) bounds and to bound rotated instances.
const EDGE_SAMPLES: usize = 24;
/// Grid samples per direction on a curved face, kept for bounding rotated instances.
const FACE_GRID: usize = 9;
/// Grid cells per direction when bounding the inside of a trimmed face; the box can miss an
/// interior bulge by at most the surface's deviation within one cell.
const TRIM_GRID: usize = 48;
/// Grid cells per direction over a closed surface when the face is found by the side of its
/// boundary (each sample is tested against every boundary sample).
const SIDE_GRID: usize = 40;

/// The surface type name a face reports: a rectangular trimmed surface reports its basis, as
/// CAD kernels do.
pub fn reported_type(surface: &Surface) -> &'static str {
    match surface {
        Surface::Trimmed { basis, .. } => reported_type(basis),
        other => other.type_name(),
    }
}

/// The parameter interval of an edge on its curve, increasing, or `None` for a degenerate edge
/// or one whose vertices cannot be placed on the curve.
pub fn edge_range(model: &Model, edge: &Edge, acc: Accuracy) -> Option<(f64, f64)> {
    let curve = &model.curves[edge.curve?.index()];
    let p_start = model.vertices[edge.start.index()].point;
    let p_end = model.vertices[edge.end.index()].point;
    let (p0, p1) = if edge.same_sense {
        (p_start, p_end)
    } else {
        (p_end, p_start)
    };
    // No hints: periodic results land in the first period and the loop below orders them.
    let t0 = curve.project(p0, None, acc)?;
    let mut t1 = curve.project(p1, None, acc)?;
    if let Some(period) = curve.period() {
        // A closed edge on a periodic curve (start vertex = end vertex) covers the period.
        let closed = edge.start == edge.end || (p_start - p_end).length() <= acc.distance * 10.0;
        while t1 <= t0 + 1e-12 {
            t1 += period;
        }
        if closed || t1 - t0 > period {
            t1 = t0 + period;
        }
        return Some((t0, t1));
    }
    let closed_domain = curve.domain().filter(|&(d0, d1)| {
        d0.is_finite()
            && d1.is_finite()
            && (curve.eval(d0) - curve.eval(d1)).length() <= acc.distance.max(1e-9) * 1e3
    });
    if let Some((d0, d1)) = closed_domain {
        // A closed edge on a closed, non-periodic curve (a circle written as a B-spline): the
        // edge is the whole curve.
        if (t1 - t0).abs() <= 1e-12 * (1.0 + t0.abs())
            && (curve.eval(0.5 * (d0 + d1)) - p0).length() > acc.distance * 1e3
        {
            return Some((d0, d1));
        }
        // A vertex at the closing point projects to either end; the edge runs forward from
        // its start (trj3_s1-ec-214.stp: two edges split one closed B-spline, the second
        // ending at the closing point came out as the first's range).
        let tiny = 1e-9 * (d1 - d0).abs().max(1.0);
        if t1 < t0 {
            if (t1 - d0).abs() <= tiny {
                t1 = d1;
            } else if (t0 - d1).abs() <= tiny {
                return Some((d0, t1));
            }
        }
    }
    if t1 < t0 {
        // A bounded curve run against its parameter: keep the interval increasing anyway.
        return Some((t1, t0));
    }
    Some((t0, t1))
}

fn curve_samples(curve: &Curve3, range: (f64, f64), n: usize) -> impl Iterator<Item = Vec3> + '_ {
    (0..=n).map(move |i| curve.eval(range.0 + (range.1 - range.0) * i as f64 / n as f64))
}

/// Box and sample points of one edge.
fn edge_bounds(model: &Model, id: EdgeId, acc: Accuracy, samples: &mut Vec<Vec3>) -> BoundingBox {
    let edge = &model.edges[id.index()];
    let mut b = BoundingBox::from_points([
        model.vertices[edge.start.index()].point,
        model.vertices[edge.end.index()].point,
    ]);
    if let (Some(curve), Some(range)) = (edge.curve, model.edge_range(id, acc)) {
        let curve = &model.curves[curve.index()];
        b = b.union(&curve.bbox_between(range.0, range.1));
        samples.extend(curve_samples(curve, range, EDGE_SAMPLES));
    }
    samples.push(model.vertices[edge.start.index()].point);
    b
}

/// The (u, v) rectangle a face occupies, from its edges projected on the surface, as
/// `[u0, u1, v0, v1]`; `None` when no edge point projects.
pub fn face_uv_box(
    model: &Model,
    face: &Face,
    surface: &Surface,
    acc: Accuracy,
) -> Option<[f64; 4]> {
    face_uv_region(model, face, surface, acc).map(|r| r.rect)
}

/// Where a face lies in its surface's parameter space.
#[derive(Clone, Debug)]
pub struct UvRegion {
    /// `[u0, u1, v0, v1]`: the rectangle the face occupies.
    pub rect: [f64; 4],
    /// The loops as (u, v) polygons, continuous across seams; `None` when some loop does not
    /// close in (u, v) (it goes around the surface) or the face wraps, so the polygons do not
    /// delimit the face.
    pub polygons: Option<Vec<Vec<(f64, f64)>>>,
    /// Boundary samples with the unit direction, tangent to the surface, that points into the
    /// face (left of the loop about the face normal).
    pub sides: Vec<(Vec3, Vec3)>,
    /// Each loop's points in model space, with whether it runs counter-clockwise about the
    /// surface normal (loop orientation agrees with the face's sense).
    pub loops: Vec<(Vec<Vec3>, bool)>,
}

impl UvRegion {
    /// Whether a point of the sphere (`centre`, any radius) lies inside the face: the loops,
    /// projected stereographically from the point's antipode onto the plane normal to it (an
    /// orientation-preserving map of the sphere seen from outside), wind once around it.
    /// Seams cancel out (used twice in opposite directions).
    pub fn sphere_contains(&self, centre: Vec3, p: Vec3, outward: bool) -> bool {
        let Some(n) = (p - centre).try_normalize() else {
            return false;
        };
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let mut turns = 0.0;
        for (points, forward) in &self.loops {
            let mut total = 0.0;
            let mut prev: Option<f64> = None;
            let mut first: Option<f64> = None;
            for &q in points {
                let Some(q) = (q - centre).try_normalize() else {
                    continue;
                };
                let d = 1.0 + q.dot(n);
                if d < 1e-9 {
                    continue; // the antipode itself: no image
                }
                let s = (q - n * q.dot(n)) / d;
                let a = s.dot(e2).atan2(s.dot(e1));
                if let Some(b) = prev {
                    total += wrap_angle(a - b);
                } else {
                    first = Some(a);
                }
                prev = Some(a);
            }
            if let (Some(a), Some(b)) = (first, prev) {
                total += wrap_angle(a - b);
            }
            let sense = if *forward == outward { 1.0 } else { -1.0 };
            turns += sense * total / std::f64::consts::TAU;
        }
        turns > 0.5
    }

    /// Whether a surface point lies on the face's side of the nearest boundary sample: a
    /// test that holds on closed surfaces, across seams and at poles, where (u, v) polygons
    /// do not delimit the face.
    pub fn on_face_side(&self, p: Vec3) -> bool {
        self.sides
            .iter()
            .min_by(|a, b| {
                (a.0 - p)
                    .length_squared()
                    .total_cmp(&(b.0 - p).length_squared())
            })
            .is_none_or(|(b, left)| (p - *b).dot(*left) >= 0.0)
    }

    /// Whether (u, v) is inside the face by the even-odd rule over its loops; always true when
    /// the loops do not delimit the face.
    pub fn contains(&self, u: f64, v: f64) -> bool {
        let Some(polygons) = &self.polygons else {
            return true;
        };
        let mut inside = false;
        for poly in polygons {
            let n = poly.len();
            for i in 0..n {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                if (a.1 > v) != (b.1 > v) && u < a.0 + (v - a.1) / (b.1 - a.1) * (b.0 - a.0) {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// The (u, v) region of a face: its rectangle and, when its loops close in (u, v), their
/// polygons.
pub fn face_uv_region(
    model: &Model,
    face: &Face,
    surface: &Surface,
    acc: Accuracy,
) -> Option<UvRegion> {
    // No loop, or only vertex loops (a whole sphere or torus written with one vertex), or
    // loops left empty by edges that failed to load: the face is the whole surface, as the
    // trimmer reads it too (a fuzzed torus face whose edges all named missing vertices was
    // meshed whole, 384k triangles, while its box was empty and the deflection fell back to
    // 0.001 mm).
    if face.loops.iter().all(|l| match &l.kind {
        LoopKind::Vertex(_) => true,
        LoopKind::Edges(edges) => edges.is_empty(),
        LoopKind::Poly(points) => points.is_empty(),
    }) {
        let ((u0, u1), (v0, v1)) = surface.domain();
        return Some(UvRegion {
            rect: [u0, u1, v0, v1],
            polygons: None,
            sides: Vec::new(),
            loops: Vec::new(),
        });
    }
    let mut polygons: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut sides: Vec<(Vec3, Vec3)> = Vec::new();
    let mut loops3d: Vec<(Vec<Vec3>, bool)> = Vec::new();
    let mut all_closed = true;
    let mut uv = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut hint: Option<(f64, f64)> = None;
    let mut add = |p: Vec3, hint: &mut Option<(f64, f64)>| {
        if let Some((mut u, mut v)) = surface.project(p, *hint, acc) {
            // Keep parameters continuous across a seam, so a loop that goes around the
            // surface shows up as a range of a whole period.
            if let (Some((hu, hv)), Some(pu)) = (*hint, surface.u_period()) {
                u += ((hu - u) / pu).round() * pu;
                let _ = hv;
            }
            if let (Some((_, hv)), Some(pv)) = (*hint, surface.v_period()) {
                v += ((hv - v) / pv).round() * pv;
            }
            uv[0] = uv[0].min(u);
            uv[1] = uv[1].max(u);
            uv[2] = uv[2].min(v);
            uv[3] = uv[3].max(v);
            *hint = Some((u, v));
        }
    };
    let mut uses: std::collections::HashMap<crate::EdgeId, u32> = std::collections::HashMap::new();
    for lp in &face.loops {
        if let LoopKind::Edges(edges) = &lp.kind {
            for oe in edges {
                *uses.entry(oe.edge).or_default() += 1;
            }
        }
    }
    let mut seen = std::collections::HashSet::new();
    let mut seams = Vec::new();
    let mut complement = false;
    // For each loop that goes once around u: whether the face lies on its +v side.
    let mut wrapping: Vec<bool> = Vec::new();
    for lp in &face.loops {
        let first_hint = hint;
        let mut loop_uv: Vec<(f64, f64)> = Vec::new();
        // Points with their (u, v) and whether they lie on a seam (which bounds nothing).
        let mut loop_pts: Vec<(Vec3, (f64, f64), bool)> = Vec::new();
        let mut add = |p: Vec3, hint: &mut Option<(f64, f64)>, on_seam: bool| {
            let before = *hint;
            add(p, hint);
            if let Some(h) = *hint
                && *hint != first_hint
            {
                loop_uv.push(h);
            }
            if let Some(h) = *hint
                && (*hint != before || before.is_none())
            {
                loop_pts.push((p, h, on_seam));
            }
        };
        match &lp.kind {
            LoopKind::Edges(edges) => {
                for oe in edges {
                    if !seen.insert(oe.edge) {
                        seams.push(oe.edge);
                    }
                    let edge = &model.edges[oe.edge.index()];
                    let mut pts = Vec::new();
                    if let (Some(c), Some(r)) = (edge.curve, model.edge_range(oe.edge, acc)) {
                        pts.extend(curve_samples(&model.curves[c.index()], r, EDGE_SAMPLES));
                        // Samples run along the curve; the loop runs along the edge as used.
                        if oe.forward != edge.same_sense {
                            pts.reverse();
                        }
                    } else {
                        pts.push(model.vertices[edge.start.index()].point);
                    }
                    let on_seam = uses.get(&oe.edge).is_some_and(|&n| n > 1);
                    for p in pts {
                        add(p, &mut hint, on_seam);
                    }
                }
            }
            LoopKind::Vertex(v) => add(model.vertices[v.index()].point, &mut hint, false),
            LoopKind::Poly(points) => {
                for &p in points {
                    add(p, &mut hint, false);
                }
            }
        }
        let forward = lp.orientation == face.same_sense;
        loops3d.push((loop_pts.iter().map(|p| p.0).collect(), forward));
        // Into-the-face directions along the loop: face normal × tangent.
        let n = loop_pts.len();
        for i in 0..n {
            let t = loop_pts[(i + 1) % n].0 - loop_pts[(i + n - 1) % n].0;
            let (pu, pv) = loop_pts[i].1;
            if loop_pts[i].2 {
                continue;
            }
            if let Some(normal) = surface.normal(pu, pv) {
                let left = normal.cross(t) * if forward { 1.0 } else { -1.0 };
                if let Some(left) = left.try_normalize() {
                    sides.push((loop_pts[i].0, left));
                }
            }
        }
        if (lp.outer || face.loops.len() == 1) && runs_clockwise(&loop_uv, surface, forward) {
            complement = true;
        }
        if let Some(up) = wraps_in_u(&loop_uv, surface) {
            wrapping.push(up == forward);
        }
        if closes(&loop_uv) {
            polygons.push(loop_uv);
        } else if !matches!(lp.kind, LoopKind::Vertex(_)) {
            all_closed = false;
        }
    }
    if !(uv[0] <= uv[1] && uv[2] <= uv[3]) {
        return None;
    }
    // On a closed surface a clockwise outer loop bounds the rest of the surface: the face
    // covers every period of it.
    if complement {
        if let Some(pu) = surface.u_period() {
            uv[1] = uv[0] + pu;
        }
        if let Some(pv) = surface.v_period() {
            uv[3] = uv[2] + pv;
        }
    }
    // A single loop around u (a spherical cap's circle, a cone's base) bounds the face
    // together with a pole: the face reaches the pole on the side it lies on.
    if let [plus_v] = wrapping[..]
        && let Some((v_low, v_high)) = pole_parameters(surface)
    {
        if plus_v {
            uv[3] = uv[3].max(v_high);
        } else {
            uv[2] = uv[2].min(v_low);
        }
    }
    // A loop cannot cover more than one period.
    if let Some(pu) = surface.u_period() {
        uv[1] = uv[1].min(uv[0] + pu);
    }
    if let Some(pv) = surface.v_period() {
        uv[3] = uv[3].min(uv[2] + pv);
    }
    let seams_empty = seams.is_empty();
    // A seam edge used twice means the face wraps all the way around, across the direction
    // the seam does not run in (an iso-u seam closes the face in u).
    for seam in seams {
        let edge = &model.edges[seam.index()];
        let (Some(c), Some(r)) = (edge.curve, model.edge_range(seam, acc)) else {
            continue;
        };
        let pts: Vec<(f64, f64)> = curve_samples(&model.curves[c.index()], r, 4)
            .filter_map(|p| surface.project(p, None, acc))
            .collect();
        let span = |f: fn(&(f64, f64)) -> f64| {
            let (lo, hi) = pts
                .iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x), b.max(x))
                });
            hi - lo
        };
        let (du, dv) = (span(|p| p.0), span(|p| p.1));
        if du <= dv {
            if let Some(pu) = surface.u_period() {
                uv[1] = uv[1].max(uv[0] + pu);
            }
        } else if let Some(pv) = surface.v_period() {
            uv[3] = uv[3].max(uv[2] + pv);
        }
    }
    // Loops that enclose nothing in (u, v) (every point projects to one spot or one line: a
    // degenerate edge alone) are dropped by the trimmer, which then reads the face as its
    // whole surface when that is bounded; the box follows it (a fuzzed B-spline face had a
    // one-point box while it meshed whole, so the deflection fell to its 1e-7 mm floor).
    let ((du0, du1), (dv0, dv1)) = surface.domain();
    let flat = |lo: f64, hi: f64, d0: f64, d1: f64| hi - lo <= 1e-9 * (d1 - d0).abs().max(1.0);
    if (flat(uv[0], uv[1], du0, du1) || flat(uv[2], uv[3], dv0, dv1))
        && [du0, du1, dv0, dv1].iter().all(|x| x.is_finite())
    {
        return Some(UvRegion {
            rect: [du0, du1, dv0, dv1],
            polygons: None,
            sides: Vec::new(),
            loops: Vec::new(),
        });
    }
    let wraps = complement || !seams_empty || !wrapping.is_empty();
    Some(UvRegion {
        rect: uv,
        polygons: (all_closed && !wraps && !polygons.is_empty()).then_some(polygons),
        sides,
        loops: loops3d,
    })
}

/// Whether a loop's (u, v) samples come back to where they started.
fn closes(uv: &[(f64, f64)]) -> bool {
    if uv.len() < 3 {
        return false;
    }
    let (first, last) = (uv[0], uv[uv.len() - 1]);
    let span = uv.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
        (a.max((p.0 - first.0).abs()), b.max((p.1 - first.1).abs()))
    });
    (last.0 - first.0).abs() <= 1e-3 * span.0.max(1e-9) + 1e-6
        && (last.1 - first.1).abs() <= 1e-3 * span.1.max(1e-9) + 1e-6
}

/// For a loop whose (u, v) samples (continuous across the seam) go once around a u-periodic
/// surface: `Some(true)` when it runs towards +u, `Some(false)` towards −u.
fn wraps_in_u(uv: &[(f64, f64)], surface: &Surface) -> Option<bool> {
    let period = surface.u_period()?;
    let (first, last) = (uv.first()?, uv.last()?);
    let du = last.0 - first.0;
    ((du.abs() - period).abs() <= 0.05 * period).then_some(du > 0.0)
}

/// An angle difference brought into (−π, π].
fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = a.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

/// Whether `outer` contains `inner` (to a small tolerance): then a face's edges already bound
/// the surface over its whole (u, v) rectangle, and nothing inside can stick out.
fn contains_box(outer: &BoundingBox, inner: &BoundingBox, acc: Accuracy) -> bool {
    if inner.is_empty() {
        return true;
    }
    let tol = acc.distance.max(1e-9 * outer.diagonal());
    outer.min.x <= inner.min.x + tol
        && outer.min.y <= inner.min.y + tol
        && outer.min.z <= inner.min.z + tol
        && outer.max.x >= inner.max.x - tol
        && outer.max.y >= inner.max.y - tol
        && outer.max.z >= inner.max.z - tol
}

/// The surface under a rectangular trim.
fn basis_of(surface: &Surface) -> &Surface {
    match surface {
        Surface::Trimmed { basis, .. } => basis_of(basis),
        other => other,
    }
}

/// The v parameters of the poles where a surface closes on its axis, low and high, when it
/// has them (sphere: ±π/2; cone: its apex on one side).
fn pole_parameters(surface: &Surface) -> Option<(f64, f64)> {
    match surface {
        Surface::Sphere { .. } => Some((-FRAC_PI_2, FRAC_PI_2)),
        Surface::Cone {
            radius, semi_angle, ..
        } => {
            let apex = -radius / semi_angle.tan();
            Some((apex, apex))
        }
        Surface::Trimmed { basis, .. } => pole_parameters(basis),
        _ => None,
    }
}

/// Whether a loop that closes in (u, v) runs clockwise once oriented as the face uses it
/// (`forward`: loop orientation agrees with the face's sense). Loops that do not close in
/// parameter space (they go around a periodic direction) are not clockwise.
fn runs_clockwise(uv: &[(f64, f64)], surface: &Surface, forward: bool) -> bool {
    if uv.len() < 3 || (surface.u_period().is_none() && surface.v_period().is_none()) {
        return false;
    }
    if !closes(uv) {
        return false;
    }
    let area: f64 = uv
        .iter()
        .zip(uv.iter().cycle().skip(1))
        .map(|(a, b)| a.0 * b.1 - b.0 * a.1)
        .sum();
    if forward { area < 0.0 } else { area > 0.0 }
}

/// Bounds of one face: its box and sample points on it.
pub fn face_bounds(model: &Model, face: &Face, acc: Accuracy) -> (BoundingBox, Vec<Vec3>) {
    let mut samples = Vec::new();
    let mut b = BoundingBox::EMPTY;
    for lp in &face.loops {
        match &lp.kind {
            LoopKind::Edges(edges) => {
                for oe in edges {
                    b = b.union(&edge_bounds(model, oe.edge, acc, &mut samples));
                }
            }
            LoopKind::Vertex(v) => {
                b.add_point(model.vertices[v.index()].point);
                samples.push(model.vertices[v.index()].point);
            }
            LoopKind::Poly(points) => {
                for &p in points {
                    b.add_point(p);
                    samples.push(p);
                }
            }
        }
    }
    let surface = &model.surfaces[face.surface.index()];
    if matches!(surface, Surface::Plane { .. }) && !face.loops.is_empty() {
        // A plane region's extremes lie on its boundary.
        return (b, samples);
    }
    let region = face_uv_region(model, face, surface, acc);
    if let Some(region) = &region
        && region.rect.iter().all(|x| x.is_finite())
    {
        let [u0, u1, v0, v1] = region.rect;
        // The side-of-boundary test is reliable only near the boundary; on spheres and tori
        // every point of the surface is near enough for it to decide (caps, lenses,
        // complements), on open cylinders and cones it is not.
        let closed = matches!(
            basis_of(surface),
            Surface::Sphere { .. } | Surface::Torus { .. }
        );
        let sphere = matches!(basis_of(surface), Surface::Sphere { .. });
        if (sphere && !region.loops.is_empty())
            || (region.polygons.is_none() && closed && !region.sides.is_empty())
        {
            // Loops around a closed surface: sample the whole of it and keep what lies on
            // the face's side of its boundary.
            let (su0, su1) = match surface.u_period() {
                Some(p) => (u0, u0 + p),
                None => (u0, u1),
            };
            let (sv0, sv1) = match (surface.v_period(), pole_parameters(surface)) {
                (Some(p), _) => (v0, v0 + p),
                (None, Some((lo, hi))) => (v0.min(lo), v1.max(hi)),
                (None, None) => (v0, v1),
            };
            for i in 0..=SIDE_GRID {
                for j in 0..=SIDE_GRID {
                    let u = su0 + (su1 - su0) * i as f64 / SIDE_GRID as f64;
                    let v = sv0 + (sv1 - sv0) * j as f64 / SIDE_GRID as f64;
                    let p = surface.eval(u, v);
                    let inside = match basis_of(surface) {
                        Surface::Sphere { frame, .. } => {
                            region.sphere_contains(frame.origin, p, true)
                        }
                        _ => region.on_face_side(p),
                    };
                    if inside {
                        b.add_point(p);
                        if i % 4 == 0 && j % 4 == 0 {
                            samples.push(p);
                        }
                    }
                }
            }
        } else if region.polygons.is_some()
            && !contains_box(&b, &surface.bbox_over(u0, u1, v0, v1), acc)
        {
            // The loops delimit the face: bound the surface points inside them (the boundary
            // is already in), not the whole rectangle, whose corners may lie off the face.
            for i in 0..=TRIM_GRID {
                for j in 0..=TRIM_GRID {
                    let u = u0 + (u1 - u0) * i as f64 / TRIM_GRID as f64;
                    let v = v0 + (v1 - v0) * j as f64 / TRIM_GRID as f64;
                    if region.contains(u, v) {
                        let p = surface.eval(u, v);
                        b.add_point(p);
                        // A coarse subset is kept for rotated instances (memory).
                        if i % 6 == 0 && j % 6 == 0 {
                            samples.push(p);
                        }
                    }
                }
            }
        } else {
            b = b.union(&surface.bbox_over(u0, u1, v0, v1));
            for i in 0..FACE_GRID {
                for j in 0..FACE_GRID {
                    let s = i as f64 / (FACE_GRID - 1) as f64;
                    let t = j as f64 / (FACE_GRID - 1) as f64;
                    samples.push(surface.eval(u0 + (u1 - u0) * s, v0 + (v1 - v0) * t));
                }
            }
        }
    }
    samples.retain(|p| p.is_finite());
    (b, samples)
}

/// Whether `t` maps axis-aligned boxes to axis-aligned boxes exactly (its linear part is a
/// signed permutation times a scale).
pub(crate) fn is_axis_aligned(t: &Transform) -> bool {
    let m = t.matrix3;
    [m.x_axis, m.y_axis, m.z_axis].iter().all(|c| {
        let a = c.abs();
        let big = a.max_element();
        (a.x + a.y + a.z - big) <= 1e-12 * big.max(1.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_geom::{Frame, Transform};

    #[test]
    fn axis_permutations_are_axis_aligned_rotations_are_not() {
        let swap = Transform::from_cols(Vec3::Y, -Vec3::X, Vec3::Z * 2.0, Vec3::ONE);
        assert!(is_axis_aligned(&swap));
        let tilted = Transform::from_rotation_z(0.3);
        assert!(!is_axis_aligned(&tilted));
    }

    /// Two edges split a closed B-spline (a square loop, first control point repeated last):
    /// the one ending at the closing point runs to the curve's end, not back to its start.
    #[test]
    fn edge_ending_at_the_closing_point_of_a_closed_curve() {
        let square = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
        ];
        let curve = cadre_geom::BSplineCurve::try_new(
            1,
            vec![0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0],
            square.to_vec(),
            None,
        )
        .unwrap();
        let mut model = Model::default();
        model.curves.push(cadre_geom::Curve::BSpline(curve));
        model.vertices.push(crate::Vertex {
            point: square[0],
            step_id: 0,
        });
        model.vertices.push(crate::Vertex {
            point: square[2],
            step_id: 0,
        });
        let edge = |start: u32, end: u32| crate::Edge {
            curve: Some(crate::CurveId(0)),
            start: crate::VertexId(start),
            end: crate::VertexId(end),
            same_sense: true,
            pcurves: Vec::new(),
            step_id: 0,
        };
        let acc = Accuracy::default();
        assert_eq!(edge_range(&model, &edge(0, 1), acc), Some((0.0, 2.0)));
        assert_eq!(edge_range(&model, &edge(1, 0), acc), Some((2.0, 4.0)));
    }

    #[test]
    fn loop_orientation_and_wrapping_are_read_from_uv_samples() {
        let sphere = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 1.0,
        };
        // A small counter-clockwise square, then the same square clockwise.
        let ccw = [(0.0, 0.0), (0.1, 0.0), (0.1, 0.1), (0.0, 0.1), (0.0, 0.0)];
        let cw: Vec<(f64, f64)> = ccw.iter().rev().copied().collect();
        assert!(!runs_clockwise(&ccw, &sphere, true));
        assert!(runs_clockwise(&cw, &sphere, true));
        assert!(!runs_clockwise(&cw, &sphere, false));
        // A circle of latitude walked towards +u wraps once around u.
        let around: Vec<(f64, f64)> = (0..=16)
            .map(|i| (std::f64::consts::TAU * f64::from(i) / 16.0, 0.5))
            .collect();
        assert_eq!(wraps_in_u(&around, &sphere), Some(true));
        assert_eq!(wraps_in_u(&ccw, &sphere), None);
    }

    #[test]
    fn sphere_winding_decides_which_side_of_a_loop_is_the_face() {
        // A circle of latitude 45° walked towards +u: counter-clockwise seen from above, so
        // the face it bounds (on its left, normal outward) is the northern cap.
        let circle: Vec<Vec3> = (0..64)
            .map(|i| {
                let u = std::f64::consts::TAU * f64::from(i) / 64.0;
                let r = std::f64::consts::FRAC_1_SQRT_2;
                Vec3::new(r * u.cos(), r * u.sin(), r)
            })
            .collect();
        let cap = UvRegion {
            rect: [0.0; 4],
            polygons: None,
            sides: Vec::new(),
            loops: vec![(circle.clone(), true)],
        };
        assert!(cap.sphere_contains(Vec3::ZERO, Vec3::Z, true));
        assert!(!cap.sphere_contains(Vec3::ZERO, -Vec3::Z, true));
        assert!(!cap.sphere_contains(Vec3::ZERO, Vec3::X, true));
        // The same circle used reversed bounds the rest of the sphere.
        let rest = UvRegion {
            loops: vec![(circle, false)],
            ..cap
        };
        assert!(!rest.sphere_contains(Vec3::ZERO, Vec3::Z, true));
        assert!(rest.sphere_contains(Vec3::ZERO, -Vec3::Z, true));
    }

    #[test]
    fn even_odd_containment_with_a_hole() {
        let square = |a: f64, b: f64| vec![(a, a), (b, a), (b, b), (a, b)];
        let region = UvRegion {
            rect: [0.0, 4.0, 0.0, 4.0],
            polygons: Some(vec![square(0.0, 4.0), square(1.0, 2.0)]),
            sides: Vec::new(),
            loops: Vec::new(),
        };
        assert!(region.contains(0.5, 0.5));
        assert!(!region.contains(1.5, 1.5), "inside the hole");
        assert!(!region.contains(5.0, 1.0));
    }
}
