//! Initial interior points: rows of constant v whose spacing, and the spacing of the points
//! along each row, follow the local curvature, clipped to the trim loops by a scanline.
//!
//! Rows adapt per row (not one global u step), so a sphere gets fewer points per latitude
//! ring towards its poles instead of a fan of crowded points.

use cadre_geom::{Surface, Vec2};

use super::domain::Prepared;
use super::metric::{Metric, StepTol, breaks};

/// Interior points in (u, v), and whether the point budget forced a coarser grid.
#[derive(Debug, Default)]
pub(crate) struct Grid {
    /// Points strictly inside the domain, away from its boundary.
    pub points: Vec<Vec2>,
    /// Set when the grid was thinned to respect the point budget.
    pub truncated: bool,
}

/// Positions along one parameter range: the interior divisions of each span into `n`
/// equal parts, plus the span breaks where a neighbouring span is divided. Each position
/// carries half of its local spacing (the clearance kept from the boundary).
fn divisions(brk: &[f64], counts: &[usize], out: &mut Vec<(f64, f64)>) {
    out.clear();
    for k in 0..counts.len() {
        let (a, b, n) = (brk[k], brk[k + 1], counts[k]);
        let h = (b - a) / n as f64;
        if k > 0 && (n > 1 || counts[k - 1] > 1) {
            let hp = (a - brk[k - 1]) / counts[k - 1] as f64;
            out.push((a, 0.5 * h.min(hp)));
        }
        out.extend((1..n).map(|i| (a + h * i as f64, 0.5 * h)));
    }
}

/// Most grid intervals in one span of one direction. Curvature estimates blow up near
/// degenerate B-spline edges (pr1db.stp face #565, degree 8 × 11, asked for ~10^7 rows and
/// hung); refinement adds whatever a capped grid misses.
const MAX_SPAN_COUNT: f64 = 2000.0;

/// Number of intervals of length at most `step` covering `len` (1 when `step` is infinite),
/// bounded so a pathological step cannot blow up the grid.
fn count(len: f64, step: f64) -> usize {
    let n = (len / step).ceil();
    if n.is_finite() && n >= 1.0 {
        n.min(MAX_SPAN_COUNT) as usize
    } else {
        1
    }
}

/// Generates the initial interior points of a curved face, at most about `budget` of them
/// (plus the pole rings, see [`pole_rings`]).
pub(crate) fn interior_points(
    surface: &Surface,
    prep: &Prepared,
    tol: &StepTol,
    metric: &Metric,
    budget: usize,
) -> Grid {
    let mut rings = pole_rings(surface, prep, tol, metric);
    if rings.points.len() > budget / 2 {
        let stride = rings.points.len().div_ceil((budget / 2).max(1));
        rings.points = rings.points.into_iter().step_by(stride).collect();
    }
    let mut grid = rows(surface, prep, tol, budget - rings.points.len());
    if !rings.keep_out.is_empty() {
        let scale = |p: Vec2| Vec2::new(p.x * metric.su, p.y * metric.sv);
        grid.points.retain(|&g| {
            let g = scale(g);
            rings
                .keep_out
                .iter()
                .all(|&([a, b], r)| seg_dist(g, scale(a), scale(b)) >= r)
        });
    }
    grid.points.extend(rings.points);
    grid
}

/// Distance from `p` to the segment `a b`.
fn seg_dist(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + d * t)
}

/// Spacing of ring points, in units of the ring's distance from its pole line (metric plane).
const RING_SPACING: f64 = 1.5;
/// Radius around a pole line kept free of grid points, in the same units.
const KEEP_OUT: f64 = 2.0;

/// Points near collapsed boundary lines, and the zone around those lines kept free of grid
/// points (segment, radius in the metric plane).
struct Rings {
    points: Vec<Vec2>,
    keep_out: Vec<([Vec2; 2], f64)>,
}

/// A row of points parallel to each collapsed boundary segment (a pole line, an apex),
/// a short curvature step inside it, dense in the metric plane.
///
/// All (u, v) along such a line map to one 3D point, so a triangle touching it is oriented
/// in 3D by the order of its other two corners around the pole, not by its (u, v) shape:
/// corners at different distances from the line can fold it over (or flatten it into the
/// meridian plane). With a dense ring close to the line, the Delaunay triangulation
/// connects the line only to ring points, all at the same distance, which orients every
/// such triangle correctly; grid points are kept out of the band behind the ring and
/// refinement does not enter it.
fn pole_rings(surface: &Surface, prep: &Prepared, tol: &StepTol, metric: &Metric) -> Rings {
    let mut out = Rings {
        points: Vec::new(),
        keep_out: Vec::new(),
    };
    let (lo, hi) = (prep.lo, prep.hi);
    let scaled_len = |v: Vec2| Vec2::new(v.x * metric.su, v.y * metric.sv).length();
    // Consecutive collinear pieces of one pole line make one ring, however finely the
    // boundary happens to be sampled there.
    let mut lines: Vec<[Vec2; 2]> = Vec::with_capacity(prep.collapsed.len());
    for &[p, q] in &prep.collapsed {
        if let Some(last) = lines.last_mut()
            && last[1] == p
            && (last[1] - last[0]).perp_dot(q - p).abs()
                <= 1e-12 * (last[1] - last[0]).length() * (q - p).length()
            && (last[1] - last[0]).dot(q - p) > 0.0
        {
            last[1] = q;
        } else {
            lines.push([p, q]);
        }
    }
    for [p, q] in lines {
        let d = q - p;
        let len = d.length();
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let dir = d / len;
        // The face is on the left of its loops.
        let n = Vec2::new(-dir.y, dir.x);
        let ext = n.x.abs() * (hi.x - lo.x) + n.y.abs() * (hi.y - lo.y);
        if ext.is_nan() || ext <= 0.0 {
            continue;
        }
        // The step across the line, sampled just inside it (the line itself is singular).
        let probe = 0.5 * (p + q) + n * (0.02 * ext);
        let across = tol
            .steps(surface, probe.x, probe.y)
            .map_or(f64::INFINITY, |(du, dv)| {
                1.0 / ((n.x / du).powi(2) + (n.y / dv).powi(2)).sqrt()
            });
        let delta = (0.5 * across).min(0.1 * ext);
        let ds = delta * scaled_len(n);
        if !ds.is_finite() || ds <= 0.0 {
            continue;
        }
        let count = (len * scaled_len(dir) / (RING_SPACING * ds))
            .ceil()
            .clamp(1.0, 4096.0) as usize;
        for k in 0..count {
            let c = p + d * ((k as f64 + 0.5) / count as f64) + n * delta;
            if inside(c, &prep.segments) && clear(c, &prep.segments, 0.5 * ds, metric) {
                out.points.push(c);
            }
        }
        out.keep_out.push(([p, q], KEEP_OUT * ds));
    }
    out
}

/// Even-odd test of `c` against all loop segments.
fn inside(c: Vec2, segs: &[[Vec2; 2]]) -> bool {
    let mut odd = false;
    for &[p, q] in segs {
        if (p.y > c.y) != (q.y > c.y) && c.x < p.x + (c.y - p.y) * (q.x - p.x) / (q.y - p.y) {
            odd = !odd;
        }
    }
    odd
}

/// Whether `c` is at least `r` (metric plane) from every loop segment.
fn clear(c: Vec2, segs: &[[Vec2; 2]], r: f64, metric: &Metric) -> bool {
    let scale = |p: Vec2| Vec2::new(p.x * metric.su, p.y * metric.sv);
    let c = scale(c);
    segs.iter()
        .all(|&[a, b]| seg_dist(c, scale(a), scale(b)) >= r)
}

/// The curvature-driven rows of interior points.
fn rows(surface: &Surface, prep: &Prepared, tol: &StepTol, budget: usize) -> Grid {
    let (lo, hi) = (prep.lo, prep.hi);
    if !(hi.x > lo.x && hi.y > lo.y) || budget == 0 {
        return Grid::default();
    }
    let ub = breaks(surface, lo.x, hi.x, true);
    let vb = breaks(surface, lo.y, hi.y, false);
    let with_mids = |b: &[f64]| -> Vec<f64> {
        let mut s = Vec::with_capacity(2 * b.len());
        for w in b.windows(2) {
            s.push(w[0]);
            s.push(0.5 * (w[0] + w[1]));
        }
        s.extend(b.last());
        s
    };
    let (us, vs) = (with_mids(&ub), with_mids(&vb));

    // Steps on the coarse sample table: rows (v spacing) per v span, and the smallest u step
    // per u span for the size estimate.
    let mut dv_span = vec![f64::INFINITY; vb.len() - 1];
    let mut du_span = vec![f64::INFINITY; ub.len() - 1];
    for (j, &v) in vs.iter().enumerate() {
        for (i, &u) in us.iter().enumerate() {
            let Some((du, dv)) = tol.steps(surface, u, v) else {
                continue;
            };
            // Sample j sits in span (j-1)/2 and j/2 (breaks are shared by two spans).
            for k in [j.saturating_sub(1) / 2, (j / 2).min(dv_span.len() - 1)] {
                dv_span[k] = dv_span[k].min(dv);
            }
            for k in [i.saturating_sub(1) / 2, (i / 2).min(du_span.len() - 1)] {
                du_span[k] = du_span[k].min(du);
            }
        }
    }
    let base_counts: Vec<usize> = (0..dv_span.len())
        .map(|k| count(vb[k + 1] - vb[k], dv_span[k]))
        .collect();
    // A direction needing no subdivision (a cylinder's rulings) gets no rows at all: the
    // boundary points alone triangulate it within tolerance.
    if base_counts.iter().all(|&n| n == 1) {
        return Grid::default();
    }
    let rows_est: usize = base_counts.iter().sum();
    let cols_est: usize = (0..du_span.len())
        .map(|k| count(ub[k + 1] - ub[k], du_span[k]))
        .sum();
    let setup = Setup {
        surface,
        prep,
        tol,
        ub: &ub,
        vb: &vb,
        us: &us,
    };
    // The product over-estimates (it ignores the domain shape and polar thinning), so start
    // coarsening only well beyond the budget; then coarsen until the grid leaves half of the
    // budget to refinement, which fixes what a coarse grid gets wrong.
    let est = rows_est as f64 * cols_est as f64;
    let mut coarsen = (est / (4.0 * budget as f64)).sqrt().max(1.0);
    let mut truncated = coarsen > 1.0;
    let mut points = setup.place(&base_counts, coarsen);
    for _ in 0..4 {
        let half = budget / 2;
        if points.len() <= half.max(1) {
            break;
        }
        coarsen *= (points.len() as f64 / half.max(1) as f64).sqrt() * 1.1;
        truncated = true;
        points = setup.place(&base_counts, coarsen);
    }
    if points.len() > budget {
        let stride = points.len().div_ceil(budget);
        points = points.into_iter().step_by(stride).collect();
        truncated = true;
    }
    Grid { points, truncated }
}

/// What placing the grid needs besides the coarsening factor.
struct Setup<'a> {
    surface: &'a Surface,
    prep: &'a Prepared,
    tol: &'a StepTol,
    ub: &'a [f64],
    vb: &'a [f64],
    us: &'a [f64],
}

impl Setup<'_> {
    /// Places the rows (`base_counts` per v span, divided by `coarsen`) and the points along
    /// them (local u step times `coarsen`), keeping those inside and clear of the boundary.
    fn place(&self, base_counts: &[usize], coarsen: f64) -> Vec<Vec2> {
        let (surface, prep, tol, ub, vb, us) =
            (self.surface, self.prep, self.tol, self.ub, self.vb, self.us);
        let v_counts: Vec<usize> = base_counts
            .iter()
            .map(|&n| ((n as f64 / coarsen).ceil() as usize).max(1))
            .collect();
        let mut rows = Vec::new();
        divisions(vb, &v_counts, &mut rows);
        let hv_max = rows.iter().map(|r| r.1).fold(0.0, f64::max);

        // Scanline over the loop segments sorted by their lower v.
        let segs = &prep.segments;
        let mut order: Vec<u32> = (0..segs.len() as u32).collect();
        let vmin = |s: &[Vec2; 2]| s[0].y.min(s[1].y);
        let vmax = |s: &[Vec2; 2]| s[0].y.max(s[1].y);
        order
            .sort_unstable_by(|&a, &b| vmin(&segs[a as usize]).total_cmp(&vmin(&segs[b as usize])));
        let mut active: Vec<u32> = Vec::new();
        let mut next = 0;

        let mut points = Vec::new();
        let mut cols = Vec::new();
        let mut u_counts = vec![1usize; ub.len() - 1];
        let mut row_du = vec![f64::INFINITY; us.len()];
        let mut crossings: Vec<f64> = Vec::new();
        let mut forbidden: Vec<(f64, f64)> = Vec::new();
        for &(v, hv) in &rows {
            // u spacing along this row, per u span.
            for (i, &u) in us.iter().enumerate() {
                row_du[i] = tol.steps(surface, u, v).map_or(f64::INFINITY, |s| s.0);
            }
            for (k, n) in u_counts.iter_mut().enumerate() {
                let du = row_du[2 * k].min(row_du[2 * k + 1]).min(row_du[2 * k + 2]) * coarsen;
                *n = count(ub[k + 1] - ub[k], du);
            }
            divisions(ub, &u_counts, &mut cols);
            if cols.is_empty() {
                continue;
            }

            while next < order.len() && vmin(&segs[order[next] as usize]) <= v + hv_max {
                active.push(order[next]);
                next += 1;
            }
            active.retain(|&s| vmax(&segs[s as usize]) >= v - hv_max);
            crossings.clear();
            forbidden.clear();
            for &s in &active {
                let [p, q] = segs[s as usize];
                if (p.y > v) != (q.y > v) {
                    crossings.push(p.x + (v - p.y) * (q.x - p.x) / (q.y - p.y));
                }
                // The part of the segment within the row's band, as a u interval.
                let (b0, b1) = (v - hv, v + hv);
                if vmax(&[p, q]) < b0 || vmin(&[p, q]) > b1 {
                    continue;
                }
                let (t0, t1) = if q.y == p.y {
                    (0.0, 1.0)
                } else {
                    let ta = ((b0 - p.y) / (q.y - p.y)).clamp(0.0, 1.0);
                    let tb = ((b1 - p.y) / (q.y - p.y)).clamp(0.0, 1.0);
                    (ta.min(tb), ta.max(tb))
                };
                let (ua, ubb) = (p.x + t0 * (q.x - p.x), p.x + t1 * (q.x - p.x));
                forbidden.push((ua.min(ubb), ua.max(ubb)));
            }
            crossings.sort_unstable_by(f64::total_cmp);
            forbidden.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
            // Merge into disjoint sorted intervals so one binary search answers "near?".
            let mut m = 0;
            for i in 0..forbidden.len() {
                if m > 0 && forbidden[i].0 <= forbidden[m - 1].1 {
                    forbidden[m - 1].1 = forbidden[m - 1].1.max(forbidden[i].1);
                } else {
                    forbidden[m] = forbidden[i];
                    m += 1;
                }
            }
            forbidden.truncate(m);

            let mut c = 0;
            for &(u, hu) in &cols {
                while c < crossings.len() && crossings[c] < u {
                    c += 1;
                }
                if c % 2 == 0 {
                    continue;
                }
                let k = forbidden.partition_point(|iv| iv.1 < u - hu);
                if k < forbidden.len() && forbidden[k].0 <= u + hu {
                    continue;
                }
                points.push(Vec2::new(u, v));
            }
        }

        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeshParams;
    use crate::face::domain::prepare;
    use crate::face::{BoundaryPoint, FaceDomain};
    use cadre_geom::{Frame, Vec3};

    fn rect(u0: f64, u1: f64, v0: f64, v1: f64) -> FaceDomain {
        let p = |u: f64, v: f64, k: u64| BoundaryPoint {
            uv: Vec2::new(u, v),
            xyz: Vec3::ZERO,
            key: k,
        };
        FaceDomain {
            loops: vec![vec![p(u0, v0, 0), p(u1, v0, 1), p(u1, v1, 2), p(u0, v1, 3)]],
        }
    }

    #[test]
    fn sphere_rows_thin_towards_the_pole() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 10.0,
        };
        let d = rect(0.0, std::f64::consts::TAU, 0.0, std::f64::consts::FRAC_PI_2);
        let prep = prepare(&d).unwrap();
        let tol = StepTol::new(&MeshParams {
            deflection: 0.01,
            angle: 0.5,
            max_face_points: 1_000_000,
        });
        let g = rows(&s, &prep, &tol, 1_000_000);
        assert!(!g.truncated);
        assert!(g.points.len() > 100);
        let near_equator = g.points.iter().filter(|p| p.y < 0.3).count();
        let near_pole = g.points.iter().filter(|p| p.y > 1.27).count();
        assert!(
            near_pole * 3 < near_equator,
            "{near_pole} vs {near_equator}"
        );
        for p in &g.points {
            assert!(p.x > 0.0 && p.x < std::f64::consts::TAU);
            assert!(p.y > 0.0 && p.y < std::f64::consts::FRAC_PI_2);
        }
    }

    #[test]
    fn budget_is_respected() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 10.0,
        };
        let d = rect(0.0, 3.0, -1.0, 1.0);
        let prep = prepare(&d).unwrap();
        let tol = StepTol::new(&MeshParams {
            deflection: 1e-6,
            angle: 0.5,
            max_face_points: 1000,
        });
        let g = rows(&s, &prep, &tol, 1000);
        assert!(g.truncated);
        assert!(g.points.len() <= 1000);
    }
}
