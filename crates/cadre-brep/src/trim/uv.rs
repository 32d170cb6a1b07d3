//! (u, v) of loop points: from the file's pcurves when they agree with the 3D points, else
//! by projection; unwrapped across seams; singular points (poles, apex) completed from their
//! neighbours.

use std::collections::HashMap;

use cadre_geom::{Accuracy, Curve2, Surface, Vec2, Vec3};

use super::exact;
use super::{
    EdgeSamples, ExactTrim, SegmentSource, TrimError, TrimKey, TrimPoint, TrimSegment,
    TrimTolerance,
};
use crate::{EdgeId, Face, LoopKind, Model, OrientedEdge, SurfaceId};

/// Periods used for unwrapping: the surface's own, or for a B-spline closed in a direction
/// (first and last rows of control points meet), the length of its domain there.
pub fn periods(surface: &Surface) -> [Option<f64>; 2] {
    let mut p = [surface.u_period(), surface.v_period()];
    if let Surface::BSpline(b) = surface
        && b.is_well_formed()
    {
        let ((u0, u1), (v0, v1)) = b.domain();
        let size = (surface.eval(u0, v0) - surface.eval(u1, v1)).length()
            + (surface.eval(u0, v1) - surface.eval(u1, v0)).length()
            + (surface.eval(0.5 * (u0 + u1), v0) - surface.eval(0.5 * (u0 + u1), v1)).length()
            + 1e-9;
        let tol = 1e-7 * size.max(1.0);
        let samples = |f: &dyn Fn(f64) -> bool| (0..=8).all(|i| f(i as f64 / 8.0));
        if samples(&|s| {
            let v = v0 + (v1 - v0) * s;
            (surface.eval(u0, v) - surface.eval(u1, v)).length() <= tol
        }) {
            p[0] = Some(u1 - u0);
        }
        if samples(&|s| {
            let u = u0 + (u1 - u0) * s;
            (surface.eval(u, v0) - surface.eval(u, v1)).length() <= tol
        }) {
            p[1] = Some(v1 - v0);
        }
    }
    p
}

/// A point under construction: which of its parameters are free (the point is a pole in
/// that direction), and the segment it belongs to.
#[derive(Clone, Copy, Debug)]
struct Raw {
    point: TrimPoint,
    free: [bool; 2],
    segment: usize,
}

/// A chain of segments: a whole loop, or the part of a loop between two uses of a seam.
#[derive(Clone, Debug, Default)]
pub(super) struct Chain {
    pub segments: Vec<TrimSegment>,
    /// Whether the chain's closing point was dropped (a loop closing at a pole): it is closed
    /// and does not wrap, whatever its end points say.
    pub closes_at_pole: bool,
}

impl Chain {
    /// Runs the chain backwards.
    pub fn reverse(&mut self) {
        self.segments.reverse();
        for s in &mut self.segments {
            s.points.reverse();
            if let SegmentSource::Edge { forward, .. } = &mut s.source {
                *forward = !*forward;
            }
            if let Some(e) = &mut s.exact {
                std::mem::swap(&mut e.t0, &mut e.t1);
            }
        }
    }

    /// All points in order, consecutive repeats (same key and (u, v)) removed.
    pub fn points(&self) -> Vec<TrimPoint> {
        super::merge_repeats(self.segments.iter().flat_map(|s| s.points.iter().copied()))
    }
}

/// A face bound that is a single vertex: its point and weld key.
pub(super) type VertexLoop = (Vec3, u64);

/// Tolerances derived once per face.
struct Ctx<'a> {
    model: &'a Model,
    surface_id: SurfaceId,
    surface: &'a Surface,
    periods: [Option<f64>; 2],
    acc: Accuracy,
    /// Distance under which a pcurve point and the 3D point agree.
    agree: f64,
    /// Distance under which a parameter step does not move the point: a pole.
    pole: f64,
    /// Parameter steps probing for poles.
    probe: [f64; 2],
    keep_exact: bool,
    /// The surface's parameter domain, `[(u0, u1), (v0, v1)]`.
    domain: [(f64, f64); 2],
}

/// Joins the pieces a loop falls into when its seams are taken out wherever one ends where
/// another starts, so that a hole whose boundary touches the seam at two points becomes one
/// closed chain again (trj4_pm2-ec-214.stp face #21376: a cut-out across a cylinder's seam,
/// left as two open chains "closed with a straight segment" each). Each piece comes back
/// with whether it was joined into a closed chain.
fn stitch(pieces: impl Iterator<Item = Vec<TrimSegment>>) -> Vec<(Vec<TrimSegment>, bool)> {
    let key = |p: &[TrimSegment], last: bool| {
        let seg = if last { p.last() } else { p.first() };
        seg.and_then(|s| {
            if last {
                s.points.last()
            } else {
                s.points.first()
            }
        })
        .map(|pt| pt.key)
    };
    let mut out: Vec<(Vec<TrimSegment>, bool)> = pieces.map(|p| (p, false)).collect();
    // Each join removes a piece, so this ends.
    'join: loop {
        for i in 0..out.len() {
            let (start, end) = (key(&out[i].0, false), key(&out[i].0, true));
            if start.is_none() || start == end {
                continue;
            }
            let Some(j) = (0..out.len())
                .find(|&j| j != i && key(&out[j].0, false) == end && key(&out[j].0, true) != end)
            else {
                continue;
            };
            let (next, _) = out.remove(j);
            let i = if j < i { i - 1 } else { i };
            out[i].0.extend(next);
            out[i].1 = key(&out[i].0, false) == key(&out[i].0, true);
            continue 'join;
        }
        break;
    }
    out
}

/// The face's loops as chains, seams removed, in (u, v), face on the left. Vertex loops are
/// returned separately as (point, key).
pub(super) fn face_chains(
    model: &Model,
    face: &Face,
    surface: &Surface,
    edges: &impl EdgeSamples,
    tol: &TrimTolerance,
) -> Result<(Vec<Chain>, Vec<VertexLoop>), TrimError> {
    let reversed = !face.same_sense;
    let ((u0, u1), (v0, v1)) = surface.domain();
    let span = |a: f64, b: f64| {
        if (b - a).is_finite() {
            0.25 * (b - a)
        } else {
            1.0
        }
    };
    let cx = Ctx {
        model,
        surface_id: face.surface,
        surface,
        periods: periods(surface),
        acc: tol.accuracy,
        // Tight: a pcurve parameterised differently from its 3D curve (trj9_io1-sy-214.stp:
        // a line pcurve on a cone B-spline) is wrong by about the edge length, not the
        // deflection, but a loose test let it through at coarse deflections.
        agree: (0.05 * tol.deflection).max(1e3 * tol.accuracy.distance),
        pole: (1e-3 * tol.deflection).max(10.0 * tol.accuracy.distance),
        probe: [span(u0, u1), span(v0, v1)],
        keep_exact: tol.keep_exact,
        domain: [(u0, u1), (v0, v1)],
    };
    // An edge used twice by the face in opposite directions is a seam (or a slit): it bounds
    // nothing, and the closing step adds its own seam lines where the face needs them.
    let mut uses: HashMap<EdgeId, [u32; 2]> = HashMap::new();
    for lp in &face.loops {
        if let LoopKind::Edges(oes) = &lp.kind {
            for oe in oes {
                uses.entry(oe.edge).or_default()[usize::from(oe.forward)] += 1;
            }
        }
    }
    let is_seam = |e: EdgeId| uses.get(&e).is_some_and(|n| n[0] > 0 && n[1] > 0);
    let mut chains = Vec::new();
    let mut vertex_loops = Vec::new();
    let mut hint: Option<Vec2> = None;
    for lp in &face.loops {
        let flip = lp.orientation == reversed;
        match &lp.kind {
            LoopKind::Edges(oes) => {
                let mut pieces: Vec<Vec<TrimSegment>> = vec![Vec::new()];
                let mut cut = false;
                for oe in oes {
                    if is_seam(oe.edge) {
                        cut = true;
                        pieces.push(Vec::new());
                        continue;
                    }
                    let seg = edge_segment(&cx, *oe, edges, &mut hint)?;
                    pieces.last_mut().expect("pieces is never empty").push(seg);
                }
                if cut && pieces.len() > 1 {
                    // The loop is cyclic: its last piece continues into its first.
                    let first = pieces.remove(0);
                    pieces
                        .last_mut()
                        .expect("len > 1 before remove")
                        .extend(first);
                }
                for (piece, joined) in stitch(pieces.into_iter().filter(|p| !p.is_empty())) {
                    let mut chain = finish(&cx, piece, !cut || joined, flip)?;
                    if flip {
                        chain.reverse();
                    }
                    chains.push(chain);
                }
            }
            LoopKind::Poly(points) => {
                let mut seg = TrimSegment {
                    source: SegmentSource::Polygon,
                    exact: None,
                    points: Vec::with_capacity(points.len() + 1),
                };
                for p in points.iter().chain(points.first()) {
                    let Some((u, v)) = surface.project(*p, hint.map(|h| (h.x, h.y)), cx.acc) else {
                        continue;
                    };
                    hint = Some(Vec2::new(u, v));
                    seg.points.push(TrimPoint {
                        uv: Vec2::new(u, v),
                        xyz: *p,
                        key: TrimKey::position(*p),
                    });
                }
                if seg.points.len() < 3 {
                    return Err(TrimError::Projection);
                }
                let mut chain = finish(&cx, vec![seg], true, flip)?;
                if flip {
                    chain.reverse();
                }
                chains.push(chain);
            }
            LoopKind::Vertex(v) => {
                vertex_loops.push((model.vertices[v.index()].point, TrimKey::vertex(*v)));
            }
        }
    }
    Ok((chains, vertex_loops))
}

/// One edge's points in (u, v), in loop order, before unwrapping.
fn edge_segment(
    cx: &Ctx,
    oe: OrientedEdge,
    edges: &impl EdgeSamples,
    hint: &mut Option<Vec2>,
) -> Result<TrimSegment, TrimError> {
    let edge = &cx.model.edges[oe.edge.index()];
    let samples = edges.samples(oe.edge);
    if samples.is_empty() {
        return Err(TrimError::EdgeNotSampled(edge.step_id));
    }
    let n = samples.len();
    let at = |i: usize| {
        if oe.forward {
            samples[i]
        } else {
            samples[n - 1 - i]
        }
    };
    // The file's pcurve, if it lies where the 3D points are (pcurves are parameterised like
    // the 3D curve, but files are not always right about it).
    let pcurve: Option<&Curve2> = edge.curve.and_then(|_| {
        edge.pcurves
            .iter()
            .filter(|(s, _)| *s == cx.surface_id)
            .map(|(_, p)| &cx.model.pcurves[p.index()])
            .find(|pc| {
                [0, n / 2, n - 1].iter().all(|&i| {
                    let s = samples[i];
                    let uv = pc.eval(s.t);
                    uv.is_finite() && (cx.surface.eval(uv.x, uv.y) - s.xyz).length() <= cx.agree
                })
            })
    });
    let mut points = Vec::with_capacity(n);
    // The curve parameter of each point (inner samples that do not project are left out).
    let mut ts = Vec::with_capacity(n);
    for i in 0..n {
        let s = at(i);
        let uv = match pcurve {
            Some(pc) => Some(pc.eval(s.t)),
            None => cx
                .surface
                .project(s.xyz, hint.map(|h| (h.x, h.y)), cx.acc)
                .map(|(u, v)| Vec2::new(u, v)),
        };
        let residual = |uv: Vec2| (cx.surface.eval(uv.x, uv.y) - s.xyz).length();
        // A projection seeded from a far hint can converge to a wrong local minimum (or leave
        // the domain of a B-spline); the point must lie where it says, so retry unseeded and
        // keep the better one.
        let uv = match uv {
            Some(uv) if residual(uv) <= cx.agree => Some(uv),
            first => {
                let fresh = cx
                    .surface
                    .project(s.xyz, None, cx.acc)
                    .map(|(u, v)| Vec2::new(u, v));
                match (first, fresh) {
                    (Some(a), Some(b)) => Some(if residual(b) < residual(a) { b } else { a }),
                    (a, b) => a.or(b),
                }
            }
        };
        let uv = match uv {
            Some(uv) => snap_to_domain(cx, uv),
            // An inner sample that does not project is left out; the ends may not be.
            None if i > 0 && i + 1 < n => continue,
            None => return Err(TrimError::Projection),
        };
        *hint = Some(uv);
        ts.push(s.t);
        points.push(TrimPoint {
            uv,
            xyz: s.xyz,
            key: s.key,
        });
    }
    let exact = if !cx.keep_exact {
        None
    } else if let Some(pc) = pcurve {
        Some(ExactTrim {
            curve: pc.clone(),
            t0: at(0).t,
            t1: at(n - 1).t,
            offset: Vec2::ZERO,
        })
    } else {
        edge.curve
            .and_then(|c| {
                let curve = &cx.model.curves[c.index()];
                exact::image(cx.surface, curve).or_else(|| {
                    // Fit through inner points (an end at a pole has no u yet).
                    let m = points.len();
                    let (a, b) = if m >= 4 {
                        (m / 3, 2 * m / 3)
                    } else {
                        (0, m.checked_sub(1)?)
                    };
                    let end = unwrapped_end(cx, &points[a..=b])?;
                    let tol = (10.0 * cx.acc.distance).max(1e-3 * cx.agree);
                    exact::linear_image(
                        cx.surface,
                        curve,
                        (ts[a], points[a].uv),
                        (ts[b], end),
                        (at(0).t, at(n - 1).t),
                        tol,
                    )
                })
            })
            .map(|curve| ExactTrim {
                curve,
                t0: at(0).t,
                t1: at(n - 1).t,
                offset: Vec2::ZERO,
            })
    };
    Ok(TrimSegment {
        source: SegmentSource::Edge {
            edge: oe.edge,
            forward: oe.forward,
        },
        exact,
        points,
    })
}

/// The last point's (u, v) continued from the first across the periods (each point nearest
/// the one before), so the end of an edge going around a cylinder is a period on, not back at
/// the seam. `None` for fewer than two points.
fn unwrapped_end(cx: &Ctx, points: &[TrimPoint]) -> Option<Vec2> {
    let mut prev = points.first()?.uv;
    for p in &points[1..] {
        let mut uv = p.uv;
        for k in 0..2 {
            if let Some(period) = cx.periods[k] {
                uv[k] += ((prev[k] - uv[k]) / period).round() * period;
            }
        }
        prev = uv;
    }
    (points.len() > 1).then_some(prev)
}

/// Puts points that lie on a side of a bounded domain exactly on it. Vertices sit a little
/// off their surface (file tolerance), so an edge along a B-spline patch boundary projects to a
/// zigzag a hair inside and outside the side (trj9_io1-sy-214.stp face #439: u = 0 and
/// 1.7e-5 alternately); the triangulation then spans long chords between those points that
/// refinement can never shorten, and it ran away.
fn snap_to_domain(cx: &Ctx, uv: Vec2) -> Vec2 {
    let mut out = uv;
    for k in 0..2 {
        let (d0, d1) = cx.domain[k];
        if cx.periods[k].is_some() || !(d0.is_finite() && d1.is_finite()) || d1 <= d0 {
            continue;
        }
        let tol = SNAP * (d1 - d0);
        if (out[k] - d0).abs() <= tol {
            out[k] = d0;
        } else if (out[k] - d1).abs() <= tol {
            out[k] = d1;
        }
    }
    out
}

/// Relative distance to a side of the domain under which a point is put on it.
const SNAP: f64 = 1e-4;

/// Which parameters of a surface point are free: moving them does not move the point.
fn free_params(cx: &Ctx, uv: Vec2, xyz: Vec3) -> [bool; 2] {
    if matches!(
        cx.surface,
        Surface::Plane { .. } | Surface::Cylinder { .. } | Surface::Extrusion { .. }
    ) {
        return [false, false];
    }
    let moved = |du: f64, dv: f64| (cx.surface.eval(uv.x + du, uv.y + dv) - xyz).length();
    [
        moved(cx.probe[0], 0.0) <= cx.pole && moved(-cx.probe[0], 0.0) <= cx.pole,
        moved(0.0, cx.probe[1]) <= cx.pole && moved(0.0, -cx.probe[1]) <= cx.pole,
    ]
}

/// The multiple of `period` to add to `x`, the first value of periodic parameter `k` after a
/// pole, which follows `prev` before the pole. Across a pole the loop may jump by anything
/// (a lune of a sphere goes up one meridian and down another), so the nearest copy is no
/// guide (half a period is a tie: pr1db.stp face #578 became a hole beyond the domain).
/// Instead the jump takes the direction in which a loop with the face on its left runs along
/// the pole line: leftwards (decreasing u) along a pole above the loop, rightwards below it;
/// for a pole free in v, downwards on the loop's left side (`high` false), upwards on its
/// right. `flip`: the chain is reversed afterwards, so the direction is too.
fn pole_crossing_shift(k: usize, prev: f64, x: f64, period: f64, high: bool, flip: bool) -> f64 {
    // Whether the parameter must increase across the pole, in the chain's final direction.
    let increasing = if k == 0 { !high } else { high };
    let d = x - prev;
    let mut n = -(d / period).floor();
    // Now prev <= x + n·period < prev + period.
    if increasing == flip {
        // Decreasing: prev - period < x + n·period <= prev.
        if d + n * period > 0.0 {
            n -= 1.0;
        }
    }
    n * period
}

/// Unwraps a chain's points across seams and completes its singular points. `cyclic`: the
/// chain is a whole loop (its end runs into its start); `flip`: the chain will be reversed
/// afterwards (see [`pole_crossing_shift`]).
fn finish(
    cx: &Ctx,
    segments: Vec<TrimSegment>,
    cyclic: bool,
    flip: bool,
) -> Result<Chain, TrimError> {
    let mut raw: Vec<Raw> = Vec::new();
    let mut sources = Vec::with_capacity(segments.len());
    for (si, s) in segments.into_iter().enumerate() {
        for p in &s.points {
            raw.push(Raw {
                point: *p,
                free: free_params(cx, p.uv, p.xyz),
                segment: si,
            });
        }
        sources.push((s.source, s.exact));
    }
    let mut closes_at_pole = false;
    // A whole loop that starts and ends at a pole: its last point closes onto its first; keep
    // one, so the pole line is made once (lune of a sphere from pole to pole: trj3_s1-db-214).
    if cyclic
        && raw.len() > 2
        && raw[0].point.key == raw[raw.len() - 1].point.key
        && (raw[0].free[0] || raw[0].free[1])
    {
        raw.pop();
        closes_at_pole = true;
    }
    let fixed = |r: &Raw| !r.free[0] && !r.free[1];
    if !raw.iter().any(fixed) {
        return Err(TrimError::Projection);
    }
    // Unwrap: each periodic parameter continues from the previous point that fixes it, by
    // the nearest copy; across a pole (a run of points free in that parameter) by the copy
    // that keeps the face on the left.
    let mean_fixed: [f64; 2] = std::array::from_fn(|k| {
        let (sum, n) = raw
            .iter()
            .filter(|r| !r.free[k])
            .fold((0.0, 0usize), |(s, n), r| (s + r.point.uv[k], n + 1));
        if n > 0 { sum / n as f64 } else { 0.0 }
    });
    let mut prev: [Option<f64>; 2] = [None, None];
    let mut crossed: [Option<f64>; 2] = [None, None];
    for r in raw.iter_mut() {
        for (k, last) in prev.iter_mut().enumerate() {
            if r.free[k] {
                // The pole's other parameter, to tell which side of the loop it is on.
                crossed[k] = Some(r.point.uv[1 - k]);
                continue;
            }
            let x = &mut r.point.uv[k];
            if let (Some(p), Some(period)) = (*last, cx.periods[k]) {
                *x += match crossed[k] {
                    Some(pole) => {
                        pole_crossing_shift(k, p, *x, period, pole > mean_fixed[1 - k], flip)
                    }
                    None => ((p - *x) / period).round() * period,
                };
            }
            crossed[k] = None;
            *last = Some(*x);
        }
    }
    // Singular points: each run of points free in a parameter goes, in that parameter, from
    // the value of the fixed point before the run to the value of the one after it (the pole
    // line). A lone singular point is doubled so the pole line has both ends.
    for k in 0..2 {
        let mut i = 0;
        let mut out: Vec<Raw> = Vec::with_capacity(raw.len() + 4);
        // A pole copy that ends the chain (see below), put back after the last point.
        let mut tail: Option<Raw> = None;
        while i < raw.len() {
            if !raw[i].free[k] {
                out.push(raw[i]);
                i += 1;
                continue;
            }
            let start = i;
            while i < raw.len() && raw[i].free[k] {
                i += 1;
            }
            let before = (0..start).rev().find(|&j| !raw[j].free[k]).or_else(|| {
                cyclic
                    .then(|| (i..raw.len()).rev().find(|&j| !raw[j].free[k]))
                    .flatten()
            });
            let after = (i..raw.len()).find(|&j| !raw[j].free[k]).or_else(|| {
                cyclic
                    .then(|| (0..start).find(|&j| !raw[j].free[k]))
                    .flatten()
            });
            let a = before.map(|j| raw[j].point.uv[k]);
            let b = after.map(|j| raw[j].point.uv[k]);
            let (a, b) = match (a, b) {
                (Some(a), Some(b)) => (a, b),
                (Some(a), None) => (a, a),
                (None, Some(b)) => (b, b),
                (None, None) => (0.0, 0.0),
            };
            let mut run: Vec<Raw> = raw[start..i].to_vec();
            if run.len() == 1 && a != b {
                run.push(run[0]);
                // The lone point is where one edge ends and the next starts (an edge's last
                // sample and the next one's first were merged): the first copy ends the
                // previous segment, so each edge's points reach the pole.
                if let Some(j) = before.filter(|&j| j + 1 == start)
                    && raw[j].segment != run[0].segment
                {
                    run[0].segment = raw[j].segment;
                }
            }
            // A loop that starts at the pole (its closing copy was dropped): the first copy
            // closes the last segment, at the end of the chain.
            let to_tail = before
                .filter(|&j| cyclic && start == 0 && j >= i && run.len() == 2 && a != b)
                .map(|j| raw[j].segment);
            let m = run.len();
            for (j, r) in run.iter_mut().enumerate() {
                let s = if m > 1 {
                    j as f64 / (m - 1) as f64
                } else {
                    0.0
                };
                r.point.uv[k] = a + (b - a) * s;
                r.free[k] = false;
            }
            if let Some(segment) = to_tail {
                let mut last = run.remove(0);
                last.segment = segment;
                tail = Some(last);
            }
            out.extend(run);
        }
        out.extend(tail);
        raw = out;
    }
    // Back into segments.
    let mut segments: Vec<TrimSegment> = sources
        .into_iter()
        .map(|(source, exact)| TrimSegment {
            source,
            exact,
            points: Vec::new(),
        })
        .collect();
    for r in raw {
        segments[r.segment].points.push(r.point);
    }
    segments.retain(|s| !s.points.is_empty());
    // The exact curve's period shift is the one the segment's points got: compared at the
    // middle (an end may be a pole, whose u is only the pole line's convention; between the
    // middle sample and the curve's middle parameter there is much less than half a period).
    for s in &mut segments {
        if let Some(e) = &mut s.exact {
            let p = e.curve.eval(0.5 * (e.t0 + e.t1));
            let q = s.points[s.points.len() / 2].uv;
            if p.is_finite() {
                let mut off = q - p;
                for k in 0..2 {
                    off[k] = match cx.periods[k] {
                        Some(period) => (off[k] / period).round() * period,
                        None => 0.0,
                    };
                }
                e.offset = off;
            }
        }
    }
    Ok(Chain {
        segments,
        closes_at_pole,
    })
}
