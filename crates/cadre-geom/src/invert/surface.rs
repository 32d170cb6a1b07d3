//! Projection of a point onto a surface.

use std::f64::consts::{PI, TAU};

use super::newton::{Bounds, surface_newton};
use super::wrap;
use crate::bounds::{golden_min, sample_pieces};
use crate::{Accuracy, Surface, Vec3};

/// Seed grid per smooth piece and in all, per direction.
const SEED_PER_PIECE: usize = 4;
const SEED_MAX: usize = 48;
/// Newton runs at most from the closest local minima of the sampled distance.
const NEWTON_STARTS: usize = 12;

/// A local minimum found from the hint is taken as the answer when the point lies within this
/// many times the accuracy of the surface (1e-4 mm by default): no other sheet of a sound
/// surface comes that close. Points of edges written with a file tolerance (1e-6 to 1e-3 mm
/// off their faces) otherwise all paid for the global search, a fifth of meshing time.
const HINT_TRUST: f64 = 1e3;

impl Surface {
    /// The `(u, v)` of the point of the surface closest to `p`.
    ///
    /// Planes, cylinders, cones, spheres and tori are solved in closed form; at points
    /// where a parameter is undetermined (on the axis, at the centre, at a pole or apex)
    /// the hint's value (or the domain start) is used for it. B-splines, revolutions,
    /// extrusions, offsets and trimmed surfaces use Newton's method on the squared distance
    /// from the hint and from the best points of a coarse grid (with the closed-form best
    /// angle or height along the sweep for revolutions and extrusions), clamped to the
    /// domain and limited to `acc.max_iterations`.
    ///
    /// Periodic parameters are shifted by whole periods to be nearest the hint when given,
    /// else into the domain's first period. `None` for non-finite input or a surface that
    /// does not evaluate finitely.
    pub fn project(&self, p: Vec3, hint: Option<(f64, f64)>, acc: Accuracy) -> Option<(f64, f64)> {
        if !p.is_finite() {
            return None;
        }
        let hint = hint.filter(|h| h.0.is_finite() && h.1.is_finite());
        let (u, v) = self.project_raw(p, hint, acc)?;
        let ((u0, _), (v0, _)) = self.domain();
        let u = wrap(u, self.u_period(), u0, hint.map(|h| h.0));
        let v = wrap(v, self.v_period(), v0, hint.map(|h| h.1));
        (u.is_finite() && v.is_finite()).then_some((u, v))
    }

    /// Projection before periodic normalisation.
    fn project_raw(&self, p: Vec3, hint: Option<(f64, f64)>, acc: Accuracy) -> Option<(f64, f64)> {
        let hu = hint.map_or(0.0, |h| h.0);
        let hv = hint.map(|h| h.1);
        match self {
            Surface::Plane { frame } => {
                let q = frame.to_local(p);
                Some((q.x, q.y))
            }
            Surface::Cylinder { frame, .. } => {
                let q = frame.to_local(p);
                Some((angle(q.x, q.y, hu), q.z))
            }
            Surface::Cone {
                frame,
                radius,
                semi_angle,
            } => {
                let q = frame.to_local(p);
                let u = angle(q.x, q.y, hu);
                let rho = q.x.hypot(q.y);
                let (s, c) = semi_angle.sin_cos();
                // Generator through the half-plane at u: points (r + v tanα, v) in (ρ, z);
                // nearest v = cos α ((ρ − r) sin α + z cos α). The other nappe (past the
                // apex) lies in the opposite half-plane, where ρ counts negative.
                let foot = |rho: f64| c * ((rho - radius) * s + q.z * c);
                let v1 = foot(rho);
                let v2 = foot(-rho);
                let d1 = (self.eval(u, v1) - p).length();
                let d2 = (self.eval(u + PI, v2) - p).length();
                if d2 < d1 && rho > 0.0 {
                    Some((u + PI, v2))
                } else {
                    Some((u, v1))
                }
            }
            Surface::Sphere { frame, .. } => {
                let q = frame.to_local(p);
                let rho = q.x.hypot(q.y);
                let v = if rho == 0.0 && q.z == 0.0 {
                    hv.unwrap_or(0.0)
                } else {
                    q.z.atan2(rho)
                };
                Some((angle(q.x, q.y, hu), v))
            }
            Surface::Torus {
                frame,
                major_radius,
                ..
            } => {
                let q = frame.to_local(p);
                let u = angle(q.x, q.y, hu);
                let rho = q.x.hypot(q.y);
                let tube_v = |rho: f64| {
                    let x = rho - major_radius;
                    if x == 0.0 && q.z == 0.0 {
                        hv.unwrap_or(0.0)
                    } else {
                        q.z.atan2(x)
                    }
                };
                // The tube circle in the opposite half-plane matters for spindle tori and
                // points near the axis.
                let (v1, v2) = (tube_v(rho), tube_v(-rho));
                let d1 = (self.eval(u, v1) - p).length();
                let d2 = (self.eval(u + PI, v2) - p).length();
                if d2 < d1 {
                    Some((u + PI, v2))
                } else {
                    Some((u, v1))
                }
            }
            Surface::BSpline(_) | Surface::Revolution { .. } | Surface::Extrusion { .. } => {
                let ((u0, u1), (v0, v1)) = self.domain();
                self.seeded_newton(p, hint, (u0, u1, v0, v1), Vec::new(), acc)
            }
            Surface::Offset { basis, .. } => {
                // The foot on the basis is the foot on the offset wherever the offset is
                // regular (|d| below the radii of curvature): an excellent seed.
                let ((u0, u1), (v0, v1)) = self.domain();
                let extra: Vec<(f64, f64)> = basis.project_raw(p, hint, acc).into_iter().collect();
                self.seeded_newton(p, hint, (u0, u1, v0, v1), extra, acc)
            }
            Surface::Trimmed { basis, .. } => {
                let ((u0, u1), (v0, v1)) = self.domain();
                let mut extra = Vec::new();
                if let Some((u, v)) = basis.project_raw(p, hint, acc) {
                    // Move periodic answers into the trimmed range before judging them.
                    let u = wrap(u, basis.u_period(), u0, None);
                    let v = wrap(v, basis.v_period(), v0, None);
                    if u >= u0 && u <= u1 && v >= v0 && v <= v1 {
                        return Some((u, v));
                    }
                    extra.push((u.clamp(u0, u1), v.clamp(v0, v1)));
                }
                self.seeded_newton(p, hint, (u0, u1, v0, v1), extra, acc)
            }
        }
    }

    /// Newton from the hint (kept if it lands within [`HINT_TRUST`] × the accuracy of the
    /// surface), then from `extra` seeds and the best points of a grid over the (finite part
    /// of the) rectangle.
    fn seeded_newton(
        &self,
        p: Vec3,
        hint: Option<(f64, f64)>,
        rect: (f64, f64, f64, f64),
        extra: Vec<(f64, f64)>,
        acc: Accuracy,
    ) -> Option<(f64, f64)> {
        let (u0, u1, v0, v1) = rect;
        let bu = if self.u_period().is_some() {
            Bounds::FREE
        } else {
            Bounds::new(u0, u1)
        };
        let bv = if self.v_period().is_some() {
            Bounds::FREE
        } else {
            Bounds::new(v0, v1)
        };
        if let Some(h) = hint
            && let Some((u, v, d)) = surface_newton(self, p, h, (bu, bv), acc)
            && d <= HINT_TRUST * acc.distance
        {
            return Some((u, v));
        }
        let dist = |u: f64, v: f64| {
            let (u, v) = (u.clamp(bu.lo, bu.hi), v.clamp(bv.lo, bv.hi));
            let d = (self.eval(u, v) - p).length();
            if d.is_finite() { d } else { f64::INFINITY }
        };
        // Starting points: local minima of the sampled distance within each smooth piece,
        // each bracketing a local minimum of the true distance.
        let mut starts: Vec<((f64, f64), f64)> = Vec::new();
        if let Some(axis) = self.profile_axis() {
            // Sweeps: the best other parameter for each profile parameter t is known in
            // closed form, leaving a 1D search over t.
            let (t0, t1) = if axis == 0 { (u0, u1) } else { (v0, v1) };
            let along = |t: f64| {
                self.sweep_point(p, t)
                    .map_or(f64::INFINITY, |(u, v)| dist(u, v))
            };
            // d/dt of the distance at the best other parameter is (S − p)·S_t there
            // (envelope theorem).
            let slope = |t: f64| {
                self.sweep_point(p, t).map_or(0.0, |(u, v)| {
                    let d = self.ders(u, v, 1);
                    let st = if axis == 0 { d[1][0] } else { d[0][1] };
                    (d[0][0] - p).dot(st)
                })
            };
            for ts in &self.profile_seeds(p, t0, t1) {
                let ds: Vec<f64> = ts.iter().map(|&t| along(t)).collect();
                let gs: Vec<f64> = ts.iter().map(|&t| slope(t)).collect();
                let last = ts.len().saturating_sub(1);
                let mut cands = Vec::new();
                for k in local_minima_1d(&ds) {
                    cands.push(ts[k]);
                    // Golden section on each side of the sample (see the curve case).
                    for n in [k.saturating_sub(1), (k + 1).min(last)] {
                        if n != k {
                            let (a, b) = (ts[n].min(ts[k]), ts[n].max(ts[k]));
                            cands.push(golden_min(along, a, b, 24));
                        }
                    }
                }
                for k in 1..ts.len() {
                    if gs[k - 1] < 0.0 && gs[k] > 0.0 {
                        cands.push(golden_min(along, ts[k - 1], ts[k], 24));
                    }
                }
                for t in cands {
                    if let Some((u, v)) = self.sweep_point(p, t) {
                        starts.push(((u, v), dist(u, v)));
                    }
                }
            }
        } else if v0.is_finite() && v1.is_finite() {
            let u_pieces = self.seed_pieces_u(u0, u1);
            let vb = self.v_breaks_within(v0, v1);
            let v_pieces = sample_pieces(v0, v1, &vb, self.seed_per_piece().1, SEED_MAX);
            for us in &u_pieces {
                for vs in &v_pieces {
                    let grid: Vec<Vec<f64>> = us
                        .iter()
                        .map(|&u| vs.iter().map(|&v| dist(u, v)).collect())
                        .collect();
                    for (i, j) in local_minima_2d(&grid) {
                        starts.push(((us[i], vs[j]), grid[i][j]));
                    }
                }
            }
        }
        starts.retain(|s| s.1.is_finite());
        starts.sort_by(|a, b| a.1.total_cmp(&b.1));
        starts.truncate(NEWTON_STARTS);
        starts.extend(extra.into_iter().chain(hint).map(|s| (s, 0.0)));
        let mut best: Option<(f64, f64, f64)> = None;
        for &(s, _) in &starts {
            if let Some((u, v, d)) = surface_newton(self, p, s, (bu, bv), acc) {
                let take = match best {
                    None => true,
                    Some((bu_, bv_, bd)) => {
                        d < bd - acc.distance
                            || (d <= bd + acc.distance
                                && hint.is_some_and(|h| {
                                    (u - h.0).abs() + (v - h.1).abs()
                                        < (bu_ - h.0).abs() + (bv_ - h.1).abs()
                                }))
                    }
                };
                if take {
                    best = Some((u, v, d));
                }
            }
        }
        best.map(|b| (b.0, b.1))
    }

    /// Seed u values by smooth piece: a grid over the finite u range.
    fn seed_pieces_u(&self, u0: f64, u1: f64) -> Vec<Vec<f64>> {
        if u0.is_finite() && u1.is_finite() {
            sample_pieces(
                u0,
                u1,
                &self.u_breaks_within(u0, u1),
                self.seed_per_piece().0,
                SEED_MAX,
            )
        } else {
            vec![vec![0.0]]
        }
    }

    /// For sweeps, the parameter that runs along the profile: u (0) for extrusions, v (1)
    /// for revolutions.
    fn profile_axis(&self) -> Option<usize> {
        match self {
            Surface::Extrusion { .. } => Some(0),
            Surface::Revolution { .. } => Some(1),
            _ => None,
        }
    }

    /// For sweeps, seed profile parameters by smooth piece over `[t0, t1]`; for unbounded
    /// profiles the profile's own projection of `p`.
    fn profile_seeds(&self, p: Vec3, t0: f64, t1: f64) -> Vec<Vec<f64>> {
        let (Surface::Revolution { profile, .. } | Surface::Extrusion { profile, .. }) = self
        else {
            return Vec::new();
        };
        if t0.is_finite() && t1.is_finite() {
            profile.seeds(t0, t1)
        } else {
            vec![
                profile
                    .project(p, None, Accuracy::new(1e-9))
                    .into_iter()
                    .collect(),
            ]
        }
    }

    /// For sweeps, the (u, v) at profile parameter `t` whose other parameter (extrusion
    /// length, rotation angle) brings the surface closest to `p`.
    fn sweep_point(&self, p: Vec3, t: f64) -> Option<(f64, f64)> {
        match self {
            Surface::Extrusion { profile, direction } => {
                let dd = direction.length_squared();
                (dd > 0.0).then(|| (t, (p - profile.eval(t)).dot(*direction) / dd))
            }
            Surface::Revolution {
                profile,
                axis_origin,
                axis_direction,
            } => {
                let a = axis_direction.try_normalize()?;
                let q = profile.eval(t) - *axis_origin;
                let w = p - *axis_origin;
                let (x, y) = ((q - a * a.dot(q)).dot(w), a.cross(q).dot(w));
                let angle = if x == 0.0 && y == 0.0 {
                    0.0
                } else {
                    y.atan2(x).rem_euclid(TAU)
                };
                Some((angle, t))
            }
            _ => None,
        }
    }

    /// Seed grid density per smooth piece in (u, v).
    fn seed_per_piece(&self) -> (usize, usize) {
        match self {
            Surface::BSpline(b) => (
                SEED_PER_PIECE.max(b.u_degree + 1),
                SEED_PER_PIECE.max(b.v_degree + 1),
            ),
            Surface::Offset { basis, .. } | Surface::Trimmed { basis, .. } => {
                let (a, b) = basis.seed_per_piece();
                (a.max(8), b.max(8))
            }
            _ => (8, 8),
        }
    }
}

/// Indices of samples no farther than their neighbours.
fn local_minima_1d(d: &[f64]) -> Vec<usize> {
    let last = d.len().saturating_sub(1);
    (0..d.len())
        .filter(|&k| (k == 0 || d[k] <= d[k - 1]) && (k == last || d[k] <= d[k + 1]))
        .collect()
}

/// Grid nodes no farther than their (up to eight) neighbours.
fn local_minima_2d(g: &[Vec<f64>]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..g.len() {
        for j in 0..g[i].len() {
            let d = g[i][j];
            let mut is_min = true;
            for row in &g[i.saturating_sub(1)..=(i + 1).min(g.len() - 1)] {
                let hi = (j + 1).min(row.len().saturating_sub(1));
                is_min &= row[j.saturating_sub(1)..=hi].iter().all(|&x| x >= d);
            }
            if is_min {
                out.push((i, j));
            }
        }
    }
    out
}

/// `atan2(y, x)`, or `fallback` on the axis where every angle is as good.
fn angle(x: f64, y: f64, fallback: f64) -> f64 {
    if x == 0.0 && y == 0.0 {
        fallback
    } else {
        y.atan2(x)
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, TAU};

    use crate::{Accuracy, Frame, Surface, Vec3};

    #[test]
    fn sphere_pole_uses_hint() {
        let s = Surface::Sphere {
            frame: Frame::WORLD,
            radius: 1.0,
        };
        let acc = Accuracy::default();
        let (u, v) = s
            .project(Vec3::new(0.0, 0.0, 2.0), Some((1.25, 1.0)), acc)
            .unwrap();
        assert_eq!(u, 1.25);
        assert!((v - FRAC_PI_2).abs() < 1e-15);
        let (u, _) = s.project(Vec3::new(0.0, -1.0, 0.0), None, acc).unwrap();
        assert!((u - 1.5 * std::f64::consts::PI).abs() < 1e-15);
        let (u, _) = s
            .project(Vec3::new(1.0, -1e-9, 0.0), Some((TAU, 0.0)), acc)
            .unwrap();
        assert!((u - TAU).abs() < 1e-8);
    }

    #[test]
    fn cone_other_nappe() {
        let s = Surface::Cone {
            frame: Frame::WORLD,
            radius: 0.0,
            semi_angle: 0.5,
        };
        let p = s.eval(0.3, -2.0);
        let (u, v) = s.project(p, None, Accuracy::default()).unwrap();
        assert!((s.eval(u, v) - p).length() < 1e-12, "{u} {v}");
    }
}
