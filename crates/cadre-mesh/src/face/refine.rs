//! Refinement: split triangles and edges until the flat triangles are within the deflection
//! of the surface and the normals at their corners within the angle.

use cadre_geom::{Surface, Vec2, Vec3};
use spade::Triangulation;
use spade::handles::FixedUndirectedEdgeHandle;

use super::Points;
use super::cdt::{Cdt, EdgeSig, FaceSig, Vert, insert_interior};
use super::metric::{Metric, StepTol};

/// Upper bound on refinement rounds: every round re-checks only the triangles that changed,
/// and the cap guarantees termination where the tolerances cannot be met (creases, bad
/// parameterisations).
const MAX_ROUNDS: usize = 16;

/// Point and unit normal of the surface at `uv`; the normal is `None` at singular points.
pub(crate) fn sample(surface: &Surface, uv: Vec2) -> (Vec3, Option<Vec3>) {
    let d = surface.derivs(uv.x, uv.y);
    let n = d.du.cross(d.dv);
    let len = n.length();
    let normal = if len.is_finite() && len > 1e-12 * d.du.length() * d.dv.length() && len > 0.0 {
        Some(n / len)
    } else {
        surface.normal(uv.x, uv.y)
    };
    (d.point, normal)
}

/// Distance between surface point `p` (normal `n`) and the chord or facet point `q`,
/// measured along the surface normal so that a drift of the parameterisation along the
/// surface is not mistaken for deviation.
pub(crate) fn normal_gap(p: Vec3, n: Option<Vec3>, q: Vec3) -> f64 {
    match n {
        Some(n) => (p - q).dot(n).abs(),
        None => (p - q).length(),
    }
}

/// The surface's crease lines ([`Surface::creases`]), sorted, for range queries.
struct Creases {
    u: Vec<f64>,
    v: Vec<f64>,
}

impl Creases {
    fn of(surface: &Surface) -> Creases {
        let (mut u, mut v) = surface.creases();
        u.sort_by(f64::total_cmp);
        v.sort_by(f64::total_cmp);
        Creases { u, v }
    }

    /// Whether the segment `a`–`b` crosses or touches a crease line.
    fn between(&self, a: Vec2, b: Vec2) -> bool {
        fn hits(lines: &[f64], x0: f64, x1: f64) -> bool {
            if lines.is_empty() {
                return false;
            }
            let (lo, hi) = (x0.min(x1), x0.max(x1));
            let eps = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
            let first = lines.partition_point(|&l| l < lo - eps);
            lines.get(first).is_some_and(|&l| l <= hi + eps)
        }
        hits(&self.u, a.x, b.x) || hits(&self.v, a.y, b.y)
    }

    /// Where along `a`–`b` (0..1, strictly inside) it crosses a crease line, the crossing
    /// nearest the middle; `None` when it crosses none. A chord across a crease is farthest
    /// from the surface there, not at its midpoint.
    fn crossing(&self, a: Vec2, b: Vec2) -> Option<f64> {
        fn best(lines: &[f64], x0: f64, x1: f64, out: &mut Option<f64>) {
            let (lo, hi) = (x0.min(x1), x0.max(x1));
            let eps = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
            if hi - lo <= 2.0 * eps {
                return;
            }
            let first = lines.partition_point(|&l| l <= lo + eps);
            for &l in lines[first..].iter().take_while(|&&l| l < hi - eps) {
                let t = (l - x0) / (x1 - x0);
                if out.is_none_or(|o| (t - 0.5).abs() < (o - 0.5).abs()) {
                    *out = Some(t);
                }
            }
        }
        let mut out = None;
        best(&self.u, a.x, b.x, &mut out);
        best(&self.v, a.y, b.y, &mut out);
        out
    }
}

/// A point to insert: (u, v), position and normal (already evaluated by the check), and
/// whether it repairs a folded triangle (inserted first when the budget is short).
type Candidate = (Vec2, Vec3, Option<Vec3>, bool);

/// Interleaves the bits of two 16-bit coordinates (Z-order), for insertion locality.
fn morton(x: u32, y: u32) -> u32 {
    fn spread(mut v: u32) -> u32 {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        v = (v | (v << 1)) & 0x5555_5555;
        v
    }
    spread(x) | (spread(y) << 1)
}

/// Refines `cdt` in place, appending the new points to `pts`. `inside` is the face
/// classification ([`super::cdt::classify`]), kept up to date here: insertion only ever
/// subdivides inside faces and flips never cross a constraint, so classifying once suffices.
/// Returns whether the point budget `max_points` stopped it.
pub(crate) fn refine(
    surface: &Surface,
    metric: &Metric,
    tol: &StepTol,
    cdt: &mut Cdt,
    pts: &mut Points,
    inside: &mut Vec<bool>,
    max_points: usize,
) -> bool {
    let deflection = tol.deflection();
    let cos_angle = tol.angle().cos();
    // Below this size a triangle is left alone: a chord shorter than twice the deflection
    // cannot deviate more than it, and it stops the angle test chasing creases forever.
    let min_len = 0.1 * deflection;
    // Triangles are measured from the surface points of their corners. Where a boundary
    // corner lies a little off the surface (the file's edge strays from it), the triangle
    // gets what is left of the deflection (bug27693 face #141: gaps of 0.07 × the deflection
    // put its triangles 1.005 × away); a gap of half the deflection or more is the file's
    // and no refinement can absorb it, so the triangle gets the whole deflection.
    let within = |corner_gap: f64| {
        if corner_gap < 0.5 * deflection {
            deflection - corner_gap
        } else {
            deflection
        }
    };
    // Normals on either side of a crease differ at any distance: the angle test skips edges
    // touching one (the deflection tests still apply there).
    let creases = Creases::of(surface);

    let mut marked: Vec<bool> = Vec::new();
    let mut cands: Vec<Candidate> = Vec::new();
    let mut pass_faces = Vec::new();
    let mut pass_edges: Vec<(FixedUndirectedEdgeHandle, [u32; 2])> = Vec::new();
    let mut keyed: Vec<(bool, u32, Candidate)> = Vec::new();

    for _ in 0..MAX_ROUNDS {
        marked.clear();
        marked.resize(cdt.num_undirected_edges(), false);
        cands.clear();
        pass_faces.clear();
        pass_edges.clear();

        for fh in cdt.fixed_inner_faces() {
            if !inside[fh.index()] {
                continue;
            }
            let face = cdt.face(fh);
            let edges = face.adjacent_edges();
            let ids = edges.map(|e| e.from().data().id);
            let mut sig = ids;
            sig.sort_unstable();
            if face.data().0 == sig {
                continue;
            }
            let x = ids.map(|i| pts.on_surface(i));
            let uv = ids.map(|i| pts.uv[i as usize]);
            let constraint = edges.map(|e| e.is_constraint_edge());
            let len3 = [0, 1, 2].map(|i| x[i].distance(x[(i + 1) % 3]));

            // Edges first: a bad chord is split at its midpoint, which fixes both triangles
            // sharing it.
            let mut split_here = false;
            for i in 0..3 {
                let ue = edges[i].as_undirected();
                if constraint[i] || marked[ue.index()] {
                    split_here |= marked[ue.index()];
                    continue;
                }
                let (a, b) = (ids[i], ids[(i + 1) % 3]);
                let esig = [a.min(b), a.max(b)];
                if ue.data().data().0 == esig {
                    continue;
                }
                // Chords from a pole are the ring's business (see `grid`): the (u, v)
                // midpoint of such an edge is not the chord's.
                if pts.is_collapsed(a) || pts.is_collapsed(b) {
                    continue;
                }
                let j = (i + 1) % 3;
                let at = |t: f64| {
                    let m = uv[i].lerp(uv[j], t);
                    let (p, n) = sample(surface, m);
                    (normal_gap(p, n, x[i].lerp(x[j], t)), m, p, n)
                };
                let mut worst = at(0.5);
                if let Some(t) = creases.crossing(uv[i], uv[j]) {
                    let c = at(t);
                    if c.0 >= worst.0 {
                        worst = c;
                    }
                }
                let (gap, m, p, n) = worst;
                if gap > within(pts.gap(a).max(pts.gap(b))) && len3[i] >= min_len {
                    marked[ue.index()] = true;
                    cands.push((m, p, n, false));
                    split_here = true;
                } else {
                    pass_edges.push((ue.fix(), esig));
                }
            }
            if split_here {
                continue;
            }
            // Triangles with two welded corners (poles, collapsed seams) are dropped from the
            // output; only their edges matter.
            let keys = ids.map(|i| pts.key[i as usize]);
            let degenerate = (0..3).any(|i| keys[i].is_some() && keys[i] == keys[(i + 1) % 3]);
            // A point inserted next to a pole would fold the triangles around it in 3D.
            let at_pole = ids.iter().any(|&i| pts.is_collapsed(i));
            if degenerate || at_pole || len3.iter().all(|&l| l < min_len) {
                pass_faces.push((fh, sig));
                continue;
            }

            let c = (uv[0] + uv[1] + uv[2]) / 3.0;
            let (p, n) = sample(surface, c);
            let nt = (x[1] - x[0]).cross(x[2] - x[0]);
            let ln = nt.length();
            let dev = if ln > 0.0 && ln.is_finite() {
                (p - x[0]).dot(nt / ln).abs()
            } else {
                normal_gap(p, n, (x[0] + x[1] + x[2]) / 3.0)
            };
            // A facet facing against the surface (folded over a pole) is bad at any size.
            let folded = n.is_some_and(|n| nt.dot(n) <= 0.0);
            let corner_gap = ids.iter().map(|&i| pts.gap(i)).fold(0.0, f64::max);
            let mut bad = dev > within(corner_gap) || folded;
            if !bad {
                let nrm = ids.map(|i| pts.normal[i as usize]);
                bad = (0..3).any(|i| {
                    let j = (i + 1) % 3;
                    !constraint[i]
                        && !creases.between(uv[i], uv[j])
                        && matches!((nrm[i], nrm[j]), (Some(a), Some(b)) if a.dot(b) < cos_angle)
                });
            }
            if !bad {
                pass_faces.push((fh, sig));
                continue;
            }
            // Longest-edge bisection keeps triangles well shaped; lengths are taken in the
            // metric plane, where the wanted triangles are isotropic. A constraint cannot be
            // split, so then the centroid goes in.
            let scaled = edges.map(|e| e.length_2());
            let longest = (0..3)
                .max_by(|&a, &b| scaled[a].total_cmp(&scaled[b]))
                .unwrap_or(0);
            let ue = edges[longest].as_undirected();
            if !constraint[longest] {
                marked[ue.index()] = true;
                let m = 0.5 * (uv[longest] + uv[(longest + 1) % 3]);
                let (p, n) = sample(surface, m);
                cands.push((m, p, n, folded));
            } else {
                cands.push((c, p, n, folded));
            }
        }

        for &(fh, sig) in &pass_faces {
            *cdt.face_data_mut(fh) = FaceSig(sig);
        }
        for &(ue, sig) in &pass_edges {
            *cdt.undirected_edge_data_mut(ue).data_mut() = EdgeSig(sig);
        }
        if cands.is_empty() {
            return false;
        }

        // Z-order the batch so each insertion starts its walk next to the previous one.
        let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for c in &cands {
            lo = lo.min(c.0);
            hi = hi.max(c.0);
        }
        let ext = (hi - lo).max(Vec2::splat(1e-300));
        keyed.clear();
        keyed.extend(cands.iter().map(|&c| {
            let t = ((c.0 - lo) / ext * 65535.0).clamp(Vec2::ZERO, Vec2::splat(65535.0));
            (!c.3, morton(t.x as u32, t.y as u32), c)
        }));
        keyed.sort_unstable_by_key(|k| (k.0, k.1));

        let mut hint = None;
        for &(_, _, (uv, xyz, normal, _)) in &keyed {
            if pts.uv.len() >= max_points {
                return true;
            }
            let vert = Vert {
                pos: metric.to_plane(uv),
                id: pts.uv.len() as u32,
            };
            if let Some(h) = insert_interior(cdt, vert, hint, inside) {
                hint = Some(h);
                pts.push(uv, xyz, normal, None);
            }
        }
    }
    false
}
