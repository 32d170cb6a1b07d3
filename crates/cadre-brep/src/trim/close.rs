//! Closing: turns chains into closed (u, v) loops. Chains that go around a periodic surface
//! are joined pairwise by seam lines, or closed along a pole or a side of the domain; a face
//! made only of holes on a closed surface (a sphere with a hole) gets the whole domain as its
//! outer loop; holes are moved by whole periods into the region they belong to.

use std::collections::HashMap;

use cadre_geom::{Curve2, Surface, Vec2, Vec3};

use super::uv::{Chain, periods};
use super::{
    ExactTrim, SegmentSource, TrimError, TrimKey, TrimLoop, TrimPoint, TrimSegment, TrimTolerance,
    polygon_area,
};
use crate::FaceId;

/// Deepest subdivision of a seam or pole line (2^10 pieces).
const MAX_LINE_DEPTH: u32 = 10;

/// Makes the points a face adds itself, with keys that weld the two sides of a seam and all
/// the points of a pole.
struct Maker<'a> {
    surface: &'a Surface,
    periods: [Option<f64>; 2],
    start: [f64; 2],
    face: FaceId,
    keys: HashMap<(i64, i64), u64>,
    /// Known points (vertex loops, chain points) whose keys a made point at the same place
    /// must reuse.
    known: Vec<(Vec3, u64)>,
    same: f64,
    tol: TrimTolerance,
}

impl Maker<'_> {
    /// Canonical parameter: wrapped into the first period.
    fn canonical(&self, k: usize, x: f64) -> f64 {
        match self.periods[k] {
            Some(p) => {
                let mut f = (x - self.start[k]) / p;
                f -= f.floor();
                if f > 1.0 - 1e-9 {
                    f = 0.0;
                }
                f * p
            }
            None => x,
        }
    }

    /// The surface point at (u, v), wrapped into the domain for evaluation.
    fn eval(&self, uv: Vec2) -> Vec3 {
        let w = |k: usize| match self.periods[k] {
            Some(_) => self.start[k] + self.canonical(k, uv[k]),
            None => uv[k],
        };
        self.surface.eval(w(0), w(1))
    }

    fn point(&mut self, uv: Vec2, pole: bool) -> TrimPoint {
        let xyz = self.eval(uv);
        if let Some(&(_, key)) = self
            .known
            .iter()
            .find(|(p, _)| (*p - xyz).length() <= self.same)
        {
            return TrimPoint { uv, xyz, key };
        }
        let q = |x: f64| (x * (1u64 << 30) as f64).round() as i64;
        let id = if pole {
            (
                i64::MIN,
                q(xyz.x) ^ q(xyz.y).rotate_left(21) ^ q(xyz.z).rotate_left(42),
            )
        } else {
            (q(self.canonical(0, uv.x)), q(self.canonical(1, uv.y)))
        };
        let next = self.keys.len();
        let face = self.face;
        let key = *self
            .keys
            .entry(id)
            .or_insert_with(|| TrimKey::face(face, next));
        if pole {
            self.known.push((xyz, key));
        }
        TrimPoint { uv, xyz, key }
    }

    /// Points strictly between `a` and `b` on the (u, v) segment, dense enough for the
    /// tolerances (these segments are trim constraints: the triangulator will not split them).
    fn line(&mut self, a: Vec2, b: Vec2, pole: bool) -> Vec<TrimPoint> {
        let mut params = Vec::new();
        if !pole {
            self.split(a, b, 0.0, 1.0, 0, &mut params);
        }
        params
            .into_iter()
            .map(|s| self.point(a + (b - a) * s, pole))
            .collect()
    }

    fn split(&self, a: Vec2, b: Vec2, s0: f64, s1: f64, depth: u32, out: &mut Vec<f64>) {
        if depth >= MAX_LINE_DEPTH {
            return;
        }
        let (pa, pb) = (a + (b - a) * s0, a + (b - a) * s1);
        let sm = 0.5 * (s0 + s1);
        let pm = a + (b - a) * sm;
        let (xa, xb, xm) = (self.eval(pa), self.eval(pb), self.eval(pm));
        let deviation = (xm - 0.5 * (xa + xb)).length();
        let turn = |p: Vec2| self.surface.normal(p.x, p.y);
        let bent = match (turn(pa), turn(pb)) {
            (Some(na), Some(nb)) => na.dot(nb).clamp(-1.0, 1.0).acos() > self.tol.angle,
            _ => false,
        };
        // Long lines in a periodic direction get a few points even when straight in 3D, so
        // the triangulation has something to attach to.
        let long = (0..2).any(|k| self.periods[k].is_some_and(|p| (pb[k] - pa[k]).abs() > p / 8.0));
        if deviation > self.tol.deflection || bent || long {
            self.split(a, b, s0, sm, depth + 1, out);
            out.push(sm);
            self.split(a, b, sm, s1, depth + 1, out);
        }
    }
}

fn segment(source: SegmentSource, points: Vec<TrimPoint>) -> TrimSegment {
    TrimSegment {
        source,
        exact: None,
        points,
    }
}

/// How a chain runs in (u, v).
enum Kind {
    /// Closed without going around the surface.
    Contractible,
    /// Goes once around in direction `axis`, `sign` ±1.
    Wrap { axis: usize, sign: f64 },
}

fn shift_chain(chain: &mut Chain, by: Vec2) {
    shift_segments(&mut chain.segments, by);
}

fn unit(axis: usize) -> Vec2 {
    if axis == 0 { Vec2::X } else { Vec2::Y }
}

/// Whether (u, v) is inside a closed polygon (even-odd).
fn inside(poly: &[TrimPoint], q: Vec2) -> bool {
    let n = poly.len();
    let mut c = false;
    for i in 0..n {
        let (a, b) = (poly[i].uv, poly[(i + 1) % n].uv);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            c = !c;
        }
    }
    c
}

/// Closes the chains of one face into loops.
pub(super) fn close_loops(
    surface: &Surface,
    face: FaceId,
    chains: Vec<Chain>,
    vertex_loops: &[(Vec3, u64)],
    tol: &TrimTolerance,
    notes: &mut Vec<String>,
) -> Result<Vec<TrimLoop>, TrimError> {
    let periods = periods(surface);
    let ((u0, u1), (v0, v1)) = surface.domain();
    let same = (1e-3 * tol.deflection).max(100.0 * tol.accuracy.distance);
    let mut maker = Maker {
        surface,
        periods,
        start: [
            if u0.is_finite() { u0 } else { 0.0 },
            if v0.is_finite() { v0 } else { 0.0 },
        ],
        face,
        keys: HashMap::new(),
        known: vertex_loops.to_vec(),
        same,
        tol: *tol,
    };
    let mut contractible: Vec<Chain> = Vec::new();
    let mut wrapping: Vec<(Chain, usize, f64)> = Vec::new();
    for chain in chains {
        let pts = chain.points();
        if pts.len() < 2 {
            continue;
        }
        if chain.closes_at_pole {
            contractible.push(chain);
            continue;
        }
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        let closed = first.key == last.key || (first.xyz - last.xyz).length() <= same;
        if !closed {
            notes.push("a loop does not close; closed with a straight segment".into());
            contractible.push(chain);
            continue;
        }
        let d = last.uv - first.uv;
        let turns = [0, 1].map(|k| periods[k].map_or(0.0, |p| (d[k] / p).round()));
        let kind = match turns {
            [0.0, 0.0] => Kind::Contractible,
            [t, 0.0] if t.abs() == 1.0 => Kind::Wrap { axis: 0, sign: t },
            [0.0, t] if t.abs() == 1.0 => Kind::Wrap { axis: 1, sign: t },
            _ => {
                return Err(TrimError::Wrapping(format!(
                    "a loop goes around the surface {turns:?} times"
                )));
            }
        };
        match kind {
            Kind::Contractible => contractible.push(chain),
            Kind::Wrap { axis, sign } => wrapping.push((chain, axis, sign)),
        }
    }
    let mut loops: Vec<TrimLoop> = Vec::new();
    if wrapping.is_empty() {
        let area: f64 = contractible.iter().map(|c| polygon_area(&c.points())).sum();
        // A cone closes at its apex on one side only: the other side runs to infinity (asked
        // without a range, `closing` offers the apex on both sides).
        let cone = matches!(surface, Surface::Cone { .. });
        let closed_all_around = (0..2).all(|k| {
            periods[k].is_some()
                || (!cone
                    && closing(surface, 1 - k, 1.0, None).is_some_and(|c| c.1)
                    && closing(surface, 1 - k, -1.0, None).is_some_and(|c| c.1))
        });
        if area < 0.0 && !closed_all_around {
            // Loops running clockwise would leave the face the unbounded rest of its surface
            // (trj6_b1-ec-214.stp: 9 cone patches); `face_trim` reads such a face again with
            // its sense turned over.
            return Err(TrimError::Clockwise);
        }
        if contractible.is_empty() || (area < 0.0 && closed_all_around) {
            // The whole surface, minus the holes; its seams run through the widest gap
            // between the holes, so no hole straddles them (bug28414: a hole across both
            // seams of a torus was cut by the box).
            let start = |k: usize| match periods[k] {
                Some(p) => seam_between_holes(&contractible, k, p, maker.start[k]),
                None => maker.start[k],
            };
            let (us, vs) = (start(0), start(1));
            let ur = periods[0].map_or((u0, u1), |p| (us, us + p));
            let vr = periods[1].map_or((v0, v1), |p| (vs, vs + p));
            if !(ur.0.is_finite() && ur.1.is_finite() && vr.0.is_finite() && vr.1.is_finite()) {
                return Err(TrimError::Unbounded);
            }
            let outer = domain_box(&mut maker, ur, vr);
            place_holes(&mut contractible, &outer, &periods, notes);
            loops.push(outer);
        } else if periods.iter().any(Option::is_some) && contractible.len() > 1 {
            // Holes go inside the outer loop, whatever period their points landed in.
            let outer_index = (0..contractible.len())
                .max_by(|&a, &b| {
                    polygon_area(&contractible[a].points())
                        .abs()
                        .total_cmp(&polygon_area(&contractible[b].points()).abs())
                })
                .expect("len > 1");
            let outer = contractible.remove(outer_index);
            let outer_loop = TrimLoop {
                segments: outer.segments,
            };
            place_holes(&mut contractible, &outer_loop, &periods, notes);
            loops.push(outer_loop);
        }
        loops.extend(contractible.into_iter().map(|c| TrimLoop {
            segments: c.segments,
        }));
        return Ok(loops);
    }
    let axis = wrapping[0].1;
    if wrapping.iter().any(|w| w.1 != axis) {
        return Err(TrimError::Wrapping(
            "loops go around the surface in both directions".into(),
        ));
    }
    let period = periods[axis].expect("wrapping implies a period");
    let w = 1 - axis;
    // Face side of each chain along w: left of its direction. Going +u the left is +v; going
    // +v the left is -u.
    let side = |sign: f64| if axis == 0 { sign } else { -sign };
    let mean_w = |c: &Chain| {
        let pts = c.points();
        pts.iter().map(|p| p.uv[w]).sum::<f64>() / pts.len() as f64
    };
    // Bring every chain into one period of w when w is periodic too (torus).
    if let Some(pw) = periods[w] {
        let base = mean_w(&wrapping[0].0);
        for (c, _, _) in wrapping.iter_mut() {
            let m = mean_w(c);
            let k = ((m - base) / pw).floor();
            if k != 0.0 {
                shift_chain(c, -unit(w) * k * pw);
            }
        }
    }
    wrapping.sort_by(|a, b| mean_w(&a.0).total_cmp(&mean_w(&b.0)));
    if let Some(pw) = periods[w]
        && wrapping.first().is_some_and(|c| side(c.2) < 0.0)
    {
        // On a torus the lowest chain may face down, towards the highest one a period below.
        let mut c = wrapping.remove(0);
        shift_chain(&mut c.0, unit(w) * pw);
        wrapping.push(c);
    }
    let holes_d: Vec<(f64, f64)> = contractible
        .iter()
        .map(|c| {
            let pts = c.points();
            let lo = pts.iter().map(|p| p.uv[axis]).fold(f64::INFINITY, f64::min);
            let hi = pts
                .iter()
                .map(|p| p.uv[axis])
                .fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        })
        .collect();
    // Everything a seam line must not cross: the chains as they lie (each line is tried
    // against every period's copy of them).
    let obstacles: Vec<Vec<Vec2>> = wrapping
        .iter()
        .map(|w| &w.0)
        .chain(contractible.iter())
        .map(|c| c.points().iter().map(|p| p.uv).collect())
        .collect();
    let mut i = 0;
    while i < wrapping.len() {
        let (ref b_chain, _, b_sign) = wrapping[i];
        let b_side = side(b_sign);
        let paired = b_side > 0.0 && i + 1 < wrapping.len() && side(wrapping[i + 1].2) < 0.0;
        let b_tagged = tagged_points(b_chain);
        let b_pts: Vec<TrimPoint> = b_tagged.iter().map(|t| t.0).collect();
        let b_shift = b_sign * period * unit(axis);
        let t_tagged = paired.then(|| tagged_points(&wrapping[i + 1].0));
        // Where the seam line would end for a start at B's point `at`: on the partner's
        // nearest point around (the T point and its shift), or on the closing side.
        let closing_w = if paired {
            None
        } else {
            let lo = b_pts.iter().map(|p| p.uv[w]).fold(f64::INFINITY, f64::min);
            let hi = b_pts
                .iter()
                .map(|p| p.uv[w])
                .fold(f64::NEG_INFINITY, f64::max);
            closing(surface, axis, b_side, Some((lo, hi)))
        };
        let seam_line = |at: usize| -> Option<(Vec2, Vec2)> {
            let end = b_pts[at].uv + b_shift;
            match &t_tagged {
                Some(t) => {
                    let (t_at, by) = partner_point(t, end[axis], period, axis);
                    Some((end, t[t_at].0.uv + unit(axis) * by))
                }
                None => {
                    let (wc, _) = closing_w?;
                    let mut q = end;
                    q[w] = wc;
                    Some((end, q))
                }
            }
        };
        let b_at = seam_start(&b_tagged, &holes_d, period, axis, |at| {
            seam_line(at).is_some_and(|(p, q)| !crosses_any(p, q, &obstacles, period, axis))
        });
        let b_segments = rotate(b_chain, &b_tagged, b_at, b_shift);
        let b_start = b_pts[b_at];
        let b_end = TrimPoint {
            uv: b_start.uv + b_shift,
            ..b_start
        };
        // The loop keeps the chains' edge segments (and their exact curves); the lines
        // added to close it are seam or boundary segments.
        let mut segments: Vec<TrimSegment> = b_segments;
        if let Some(t_tagged) = &t_tagged {
            let (ref t_chain, _, t_sign) = wrapping[i + 1];
            // The T point nearest, in the wrapping direction, to where B ended.
            let (t_at, k) = partner_point(t_tagged, b_end.uv[axis], period, axis);
            let t_shift = t_sign * period * unit(axis);
            let mut t_segments = rotate(t_chain, t_tagged, t_at, t_shift);
            let t_first = t_tagged[t_at].0;
            let by = unit(axis) * k;
            shift_segments(&mut t_segments, by);
            let t_start = TrimPoint {
                uv: t_first.uv + by,
                ..t_first
            };
            let t_end = TrimPoint {
                uv: t_start.uv + t_shift,
                ..t_start
            };
            let up = maker.line(b_end.uv, t_start.uv, false);
            let down = way_back(&up, b_shift);
            segments.push(straight(SegmentSource::Seam, b_end, up, t_start));
            segments.extend(t_segments);
            segments.push(straight(SegmentSource::Seam, t_end, down, b_start));
            i += 2;
        } else {
            if periods[w].is_some() {
                return Err(TrimError::Wrapping(
                    "a loop goes around a closed surface with no partner loop".into(),
                ));
            }
            let Some((wc, pole)) = closing_w else {
                return Err(TrimError::Wrapping(
                    "the face goes around the surface and nothing closes it on one side".into(),
                ));
            };
            if !pole {
                notes.push("closed along a free side of the surface's domain".into());
            }
            let with_w = |p: Vec2| {
                let mut q = p;
                q[w] = wc;
                q
            };
            let c_end = with_w(b_end.uv);
            let c_start = with_w(b_start.uv);
            let up = maker.line(b_end.uv, c_end, false);
            let corner_end = maker.point(c_end, pole);
            let across = maker.line(c_end, c_start, pole);
            let corner_start = maker.point(c_start, pole);
            let down = way_back(&up, b_shift);
            segments.push(straight(SegmentSource::Seam, b_end, up, corner_end));
            segments.push(straight(
                SegmentSource::Boundary,
                corner_end,
                across,
                corner_start,
            ));
            segments.push(straight(SegmentSource::Seam, corner_start, down, b_start));
            i += 1;
        }
        loops.push(TrimLoop { segments });
    }
    if let Some(outer) = loops.first().cloned() {
        place_holes(&mut contractible, &outer, &periods, notes);
    }
    loops.extend(contractible.into_iter().map(|c| TrimLoop {
        segments: c.segments,
    }));
    Ok(loops)
}

/// The seam line `up` walked back one period over (`shift` is the period the wrapping chain
/// advanced by): the same points with the same keys, in reverse.
fn way_back(up: &[TrimPoint], shift: Vec2) -> Vec<TrimPoint> {
    up.iter()
        .rev()
        .map(|p| TrimPoint {
            uv: p.uv - shift,
            ..*p
        })
        .collect()
}

/// Distance to the nearest multiple of `period`.
fn circ(x: f64, period: f64) -> f64 {
    (x - (x / period).round() * period).abs()
}

/// Most seam starts tried for one chain before the first choice is kept, crossing or not
/// (each try costs a pass over every chain's points).
const MAX_SEAM_TRIES: usize = 256;

/// Index of the chain point where the seam line starts: the first, in the order of
/// [`seam_point`]'s preference, whose line is `clear` (crosses no chain); the preferred one
/// when none within [`MAX_SEAM_TRIES`] is. A line from a vertex at the foot of a slot runs up
/// the slot's side or across its end (trj3_s1-md-214.stp face #1710, a cylinder band whose
/// chain starts at such a corner): the loop would cross itself there.
fn seam_start(
    pts: &[(TrimPoint, usize)],
    holes: &[(f64, f64)],
    period: f64,
    axis: usize,
    clear: impl Fn(usize) -> bool,
) -> usize {
    let order = seam_points(pts, holes, period, axis);
    order
        .iter()
        .take(MAX_SEAM_TRIES)
        .copied()
        .find(|&at| clear(at))
        .unwrap_or(order.first().copied().unwrap_or(0))
}

/// The point of the partner chain `t` nearest, around the wrapping direction, to `target`
/// (never its last point, which is its first one a period on), and the multiple of the
/// period that brings it nearest.
fn partner_point(t: &[(TrimPoint, usize)], target: f64, period: f64, axis: usize) -> (usize, f64) {
    let at = (0..t.len().saturating_sub(1))
        .min_by(|&a, &b| {
            let da = circ(t[a].0.uv[axis] - target, period);
            let db = circ(t[b].0.uv[axis] - target, period);
            da.total_cmp(&db)
        })
        .unwrap_or(0);
    let k = ((target - t[at].0.uv[axis]) / period).round();
    (at, k * period)
}

/// Whether the (u, v) segment `p`–`q` crosses, touches or runs along any obstacle polyline,
/// or a copy of one moved by whole periods in `axis`, anywhere but at `p` or `q` themselves.
fn crosses_any(p: Vec2, q: Vec2, obstacles: &[Vec<Vec2>], period: f64, axis: usize) -> bool {
    let eps = 1e-9 * (1.0 + p.abs().max_element().max(q.abs().max_element()));
    let (lo, hi) = (p[axis].min(q[axis]), p[axis].max(q[axis]));
    obstacles.iter().any(|poly| {
        let min = poly.iter().map(|a| a[axis]).fold(f64::INFINITY, f64::min);
        let max = poly
            .iter()
            .map(|a| a[axis])
            .fold(f64::NEG_INFINITY, f64::max);
        if !(min.is_finite() && max.is_finite()) {
            return false;
        }
        // Copies of the polyline that can reach the segment's span.
        let k0 = ((lo - max) / period).floor() as i64;
        let k1 = ((hi - min) / period).ceil() as i64;
        (k0..=k1.min(k0 + 8)).any(|k| {
            let by = unit(axis) * (k as f64 * period);
            poly.windows(2)
                .any(|e| segment_conflict(p, q, e[0] + by, e[1] + by, eps))
        })
    })
}

/// Whether segment `a`–`b` meets segment `p`–`q` anywhere but at `p` or `q` (within `eps`),
/// a collinear overlap longer than `eps` included.
fn segment_conflict(p: Vec2, q: Vec2, a: Vec2, b: Vec2, eps: f64) -> bool {
    let cross = |x: Vec2, y: Vec2| x.x * y.y - x.y * y.x;
    let (d, e) = (q - p, b - a);
    let (ld, le) = (d.length(), e.length());
    if ld <= eps {
        return false;
    }
    let denom = cross(d, e);
    if denom.abs() > 1e-12 * ld * le.max(eps) {
        let t = cross(a - p, e) / denom;
        let s = cross(a - p, d) / denom;
        let (tt, ts) = (eps / ld, eps / le.max(eps));
        if t < -tt || t > 1.0 + tt || s < -ts || s > 1.0 + ts {
            return false;
        }
        let x = p + d * t;
        return (x - p).length() > eps && (x - q).length() > eps;
    }
    // Parallel: a conflict only when on the same line and overlapping by more than eps.
    if cross(d, a - p).abs() / ld > eps {
        return false;
    }
    let (ta, tb) = ((a - p).dot(d) / (ld * ld), (b - p).dot(d) / (ld * ld));
    let (s0, s1) = (ta.min(tb).max(0.0), ta.max(tb).min(1.0));
    (s1 - s0) * ld > eps
}

/// The chain's points in the order they are preferred as the start of a seam line: the
/// farthest, around the wrapping direction, from every hole first, the starts of segments
/// (vertices) before the points inside them so that no edge is cut and every edge keeps its
/// exact curve.
fn seam_points(
    pts: &[(TrimPoint, usize)],
    holes: &[(f64, f64)],
    period: f64,
    axis: usize,
) -> Vec<usize> {
    if pts.len() < 2 {
        return vec![0];
    }
    let n = pts.len() - 1;
    let score = |i: usize| hole_clearance(pts[i].0.uv[axis], holes, period);
    let first = seam_point(pts, holes, period, axis);
    let is_vertex = |i: usize| i == 0 || pts[i].1 != pts[i - 1].1;
    let mut vertices: Vec<usize> = (0..n).filter(|&i| is_vertex(i) && i != first).collect();
    let mut inner: Vec<usize> = (0..n).filter(|&i| !is_vertex(i) && i != first).collect();
    // Stable sorts: with no holes every score is infinite and the chain order stands.
    vertices.sort_by(|&a, &b| score(b).total_cmp(&score(a)));
    inner.sort_by(|&a, &b| score(b).total_cmp(&score(a)));
    let mut order = vec![first];
    order.extend(vertices);
    order.extend(inner);
    order
}

/// How far, around the wrapping direction, `x` lies from the nearest hole's range
/// (infinite with no holes, 0 inside one).
fn hole_clearance(x: f64, holes: &[(f64, f64)], period: f64) -> f64 {
    holes
        .iter()
        .map(|&(lo, hi)| (circ(x - 0.5 * (lo + hi), period) - 0.5 * (hi - lo)).max(0.0))
        .fold(f64::INFINITY, f64::min)
}

/// Index of the chain point preferred as the seam line's start: the one farthest, around the
/// wrapping direction, from every hole, preferring the start of a segment (a vertex) so that
/// no edge is cut and every edge keeps its exact curve.
fn seam_point(pts: &[(TrimPoint, usize)], holes: &[(f64, f64)], period: f64, axis: usize) -> usize {
    if holes.is_empty() || pts.len() < 2 {
        return 0;
    }
    let n = pts.len() - 1;
    let score = |i: usize| hole_clearance(pts[i].0.uv[axis], holes, period);
    let best = |candidates: &mut dyn Iterator<Item = usize>| {
        candidates.max_by(|&a, &b| score(a).total_cmp(&score(b)))
    };
    let starts = best(&mut (0..n).filter(|&i| i == 0 || pts[i].1 != pts[i - 1].1));
    if let Some(i) = starts.filter(|&i| score(i) > 0.0) {
        return i;
    }
    let step = (n / 64).max(1);
    best(&mut (0..n).step_by(step)).unwrap_or(0)
}

/// A chain's points in order, each with the index of the segment it comes from; the point two
/// consecutive segments share appears once, with the first. The last point is the first one a
/// period on (the chain wraps).
fn tagged_points(chain: &Chain) -> Vec<(TrimPoint, usize)> {
    super::merge_repeats_tagged(
        chain
            .segments
            .iter()
            .enumerate()
            .flat_map(|(i, s)| s.points.iter().map(move |&p| (p, i)))
            .collect(),
    )
}

/// A wrapping chain (`tagged` from [`tagged_points`]) restarted at point `at`, as segments:
/// from `tagged[at]` to the chain's end, then its beginning moved on by `shift` (one period)
/// up to `tagged[at]` again (`at` 0: the chain as it is). A segment cut in two by the restart keeps its source but loses
/// its exact curve (its parameter range is no longer known); the others keep theirs, the
/// moved ones with `shift` added to their offset.
fn rotate(
    chain: &Chain,
    tagged: &[(TrimPoint, usize)],
    at: usize,
    shift: Vec2,
) -> Vec<TrimSegment> {
    // The last point is the first one a period on: the restarted chain runs from `at` to the
    // end, then over the beginning (its first point is that last one) moved on by `shift`.
    let moved = |&(p, tag): &(TrimPoint, usize)| {
        (
            TrimPoint {
                uv: p.uv + shift,
                ..p
            },
            tag,
            true,
        )
    };
    let order: Vec<(TrimPoint, usize, bool)> = tagged[at..]
        .iter()
        .map(|&(p, tag)| (p, tag, false))
        .chain(tagged[1..=at].iter().map(moved))
        .collect();
    // Groups of consecutive points from one segment on one side of the restart.
    let mut groups: Vec<(usize, bool, Vec<TrimPoint>)> = Vec::new();
    for (p, tag, shifted) in order {
        // Each segment starts where the one before ended.
        let previous_end = groups.last().and_then(|g| g.2.last().copied());
        match groups.last_mut() {
            Some((t, s, pts)) if *t == tag && *s == shifted => pts.push(p),
            _ => {
                let mut pts: Vec<TrimPoint> = previous_end.into_iter().collect();
                pts.push(p);
                groups.push((tag, shifted, pts));
            }
        }
    }
    let cut = |tag: usize| groups.iter().filter(|g| g.0 == tag).count() > 1;
    groups
        .iter()
        .map(|(tag, shifted, pts)| {
            let source = &chain.segments[*tag];
            let exact = source.exact.clone().filter(|_| !cut(*tag)).map(|mut e| {
                if *shifted {
                    e.offset += shift;
                }
                e
            });
            TrimSegment {
                source: source.source,
                exact,
                points: pts.clone(),
            }
        })
        .collect()
}

/// Moves segments by `by` in (u, v), exact curves with them.
fn shift_segments(segments: &mut [TrimSegment], by: Vec2) {
    for s in segments {
        for p in &mut s.points {
            p.uv += by;
        }
        if let Some(e) = &mut s.exact {
            e.offset += by;
        }
    }
}

/// A straight (u, v) segment added to close a loop (seam or pole/domain line): `inner` (points
/// strictly between, from [`Maker::line`] or [`way_back`]) with `first` before it and `last`
/// after it; its exact curve is the (u, v) line from `first` (t = 0) to `last` (t = 1).
fn straight(
    source: SegmentSource,
    first: TrimPoint,
    inner: Vec<TrimPoint>,
    last: TrimPoint,
) -> TrimSegment {
    let mut points = Vec::with_capacity(inner.len() + 2);
    points.push(first);
    points.extend(inner);
    points.push(last);
    TrimSegment {
        source,
        exact: Some(ExactTrim {
            curve: Curve2::Line {
                origin: first.uv,
                direction: last.uv - first.uv,
            },
            t0: 0.0,
            t1: 1.0,
            offset: Vec2::ZERO,
        }),
        points,
    }
}

/// The w value closing a face that goes around in `axis` on its `side` of w (±1): a pole
/// (sphere, cone apex, B-spline or revolution ending on its axis; second value `true`) or a
/// finite end of the domain (`false`). `range`: the w values the chain spans.
fn closing(
    surface: &Surface,
    axis: usize,
    side: f64,
    range: Option<(f64, f64)>,
) -> Option<(f64, bool)> {
    let w = 1 - axis;
    let ((u0, u1), (v0, v1)) = surface.domain();
    let (w0, w1) = if w == 0 { (u0, u1) } else { (v0, v1) };
    let mut candidate = if side > 0.0 { w1 } else { w0 };
    if let Surface::Cone {
        radius, semi_angle, ..
    } = surface
        && w == 1
    {
        let apex = -radius / semi_angle.tan();
        let ok = match range {
            Some((lo, hi)) => (side > 0.0 && apex >= hi) || (side < 0.0 && apex <= lo),
            None => true,
        };
        candidate = if ok { apex } else { f64::NAN };
    }
    if !candidate.is_finite() {
        return None;
    }
    let (a0, a1) = if axis == 0 { (u0, u1) } else { (v0, v1) };
    let (a0, a1) = if (a1 - a0).is_finite() {
        (a0, a1)
    } else {
        (0.0, std::f64::consts::TAU)
    };
    let at = |s: f64| {
        let a = a0 + (a1 - a0) * s;
        if axis == 0 {
            surface.eval(a, candidate)
        } else {
            surface.eval(candidate, a)
        }
    };
    let p0 = at(0.0);
    let size = (0..8)
        .map(|i| (at(i as f64 / 8.0) - p0).length())
        .fold(0.0, f64::max);
    let scale = (at(0.5)
        - surface.eval(
            0.5 * (u0.max(-1e9) + u1.min(1e9)),
            0.5 * (v0.max(-1e9) + v1.min(1e9)),
        ))
    .length();
    let pole = size <= 1e-9 * (1.0 + scale + p0.length());
    Some((candidate, pole))
}

/// A rectangle of the domain, counter-clockwise; sides along periods are seams (welded),
/// sides that are poles collapse to one key.
fn domain_box(maker: &mut Maker, ur: (f64, f64), vr: (f64, f64)) -> TrimLoop {
    let corners = [
        Vec2::new(ur.0, vr.0),
        Vec2::new(ur.1, vr.0),
        Vec2::new(ur.1, vr.1),
        Vec2::new(ur.0, vr.1),
    ];
    let surface = maker.surface;
    let same = maker.same;
    let is_pole = |a: Vec2, b: Vec2| {
        let pa = surface.eval(a.x, a.y);
        (0..=4).all(|i| {
            let p = a + (b - a) * (i as f64 / 4.0);
            (surface.eval(p.x, p.y) - pa).length() <= same
        })
    };
    let mut pts = Vec::new();
    for i in 0..4 {
        let (a, b) = (corners[i], corners[(i + 1) % 4]);
        let pole = is_pole(a, b);
        pts.push(maker.point(a, pole || is_pole(corners[(i + 3) % 4], a)));
        pts.extend(maker.line(a, b, pole));
    }
    TrimLoop {
        segments: vec![segment(SegmentSource::Boundary, pts)],
    }
}

/// Where to put the seam of periodic parameter `k` (period `period`) so that it crosses no
/// hole: the middle of the widest gap between the holes' ranges, in the period starting at
/// `default`; `default` when there are no holes or they cover the whole period.
fn seam_between_holes(holes: &[Chain], k: usize, period: f64, default: f64) -> f64 {
    let mut ranges: Vec<(f64, f64)> = Vec::new();
    for hole in holes {
        let pts = hole.points();
        let lo = pts.iter().map(|p| p.uv[k]).fold(f64::INFINITY, f64::min);
        let hi = pts
            .iter()
            .map(|p| p.uv[k])
            .fold(f64::NEG_INFINITY, f64::max);
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        if hi - lo >= period {
            return default;
        }
        let shift = ((lo - default) / period).floor() * period;
        ranges.push((lo - shift, hi - shift));
    }
    if ranges.is_empty() {
        return default;
    }
    ranges.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Sweep once around the circle, tracking how far the covered part reaches.
    let mut best = (f64::NEG_INFINITY, default);
    let mut reach = ranges[0].1;
    for w in 1..=ranges.len() {
        let next = if w < ranges.len() {
            ranges[w].0
        } else {
            ranges[0].0 + period
        };
        if next - reach > best.0 {
            best = (next - reach, 0.5 * (next + reach));
        }
        if w < ranges.len() {
            reach = reach.max(ranges[w].1);
        }
    }
    if best.0 <= 0.0 {
        return default;
    }
    let s = best.1;
    s - ((s - default) / period).floor() * period
}

/// Moves each hole by whole periods so it lies inside `outer`.
fn place_holes(
    holes: &mut [Chain],
    outer: &TrimLoop,
    periods: &[Option<f64>; 2],
    notes: &mut Vec<String>,
) {
    let poly = outer.polygon();
    if poly.len() < 3 {
        return;
    }
    for hole in holes.iter_mut() {
        let pts = hole.points();
        let Some(probe) = pts.first() else { continue };
        if inside(&poly, probe.uv) {
            continue;
        }
        let ks = |k: usize| -> Vec<f64> {
            if periods[k].is_some() {
                vec![0.0, 1.0, -1.0, 2.0, -2.0]
            } else {
                vec![0.0]
            }
        };
        let mut placed = false;
        'search: for a in ks(0) {
            for b in ks(1) {
                let by = Vec2::new(a * periods[0].unwrap_or(0.0), b * periods[1].unwrap_or(0.0));
                if inside(&poly, probe.uv + by) {
                    shift_chain(hole, by);
                    placed = true;
                    break 'search;
                }
            }
        }
        if !placed {
            notes.push("a hole lies outside its face's outer loop".into());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hole(u: (f64, f64)) -> Chain {
        let p = |x: f64, y: f64| TrimPoint {
            uv: Vec2::new(x, y),
            xyz: Vec3::ZERO,
            key: 0,
        };
        Chain {
            segments: vec![segment(
                SegmentSource::Polygon,
                vec![p(u.0, 0.0), p(u.1, 0.0), p(u.1, 1.0)],
            )],
            closes_at_pole: false,
        }
    }

    #[test]
    fn seams_go_through_the_widest_gap_between_holes() {
        let tau = std::f64::consts::TAU;
        // No holes: the default.
        assert_eq!(seam_between_holes(&[], 0, tau, 0.0), 0.0);
        // One hole across 0: the seam goes opposite it.
        let s = seam_between_holes(&[hole((-0.3, 0.3))], 0, tau, 0.0);
        assert!((s - std::f64::consts::PI).abs() < 1e-12, "{s}");
        // Two holes: the wider gap is between 4 and 1 + 2π.
        let s = seam_between_holes(&[hole((1.0, 2.0)), hole((3.0, 4.0))], 0, tau, 0.0);
        assert!((s - 0.5 * (4.0 + 1.0 + tau)).abs() < 1e-12, "{s}");
        // A hole around the whole period leaves the default.
        assert_eq!(seam_between_holes(&[hole((0.0, 7.0))], 0, tau, 0.5), 0.5);
    }

    #[test]
    fn seam_lines_see_crossings_overlaps_and_copies_a_period_on() {
        let v = Vec2::new;
        let eps = 1e-9;
        // Sharing an end point is not a conflict; crossing, touching inside and running
        // along are.
        assert!(!segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(0.0, 0.0),
            v(1.0, 0.0),
            eps
        ));
        assert!(segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(-1.0, 0.5),
            v(1.0, 0.5),
            eps
        ));
        assert!(segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(0.0, 0.5),
            v(1.0, 0.5),
            eps
        ));
        assert!(segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(0.0, 0.0),
            v(0.0, 0.3),
            eps
        ));
        assert!(!segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(0.1, 0.0),
            v(0.1, 1.0),
            eps
        ));
        assert!(!segment_conflict(
            v(0.0, 0.0),
            v(0.0, 1.0),
            v(0.0, 1.0),
            v(0.0, 2.0),
            eps
        ));
        // The slot of trj3_s1-md-214.stp face #1710, its foot at u = -1.59, seen from a line
        // starting one period on.
        let tau = std::f64::consts::TAU;
        let slot = vec![v(-1.6, 0.0), v(-1.6, 35.0), v(-1.55, 35.0), v(-1.55, 0.0)];
        let obstacles = vec![slot];
        let start = v(-1.6 + tau, 0.0);
        assert!(crosses_any(start, v(-1.57 + tau, 68.0), &obstacles, tau, 0));
        assert!(crosses_any(start, v(-1.6 + tau, 68.0), &obstacles, tau, 0));
        assert!(!crosses_any(
            v(-1.5 + tau, 0.0),
            v(-1.5 + tau, 68.0),
            &obstacles,
            tau,
            0
        ));
    }
}
