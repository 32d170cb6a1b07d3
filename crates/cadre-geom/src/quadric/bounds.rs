//! A box holding a cut quadric, in its canonical frame: where the ray caster's proxy is
//! drawn and what culling tests.
//!
//! In the canonical coordinates y (Q = Σ λᵢ yᵢ² + 2 Σ βᵢ yᵢ + k) a box is tightened, from
//! one of half-size `limit`, by two steps repeated until it stops shrinking:
//! - the planes: the box becomes the box of the polytope (box ∩ half-spaces), from the
//!   vertices where three of their planes meet;
//! - the quadric: each yᵢ keeps only the values where λᵢ yᵢ² + 2βᵢ yᵢ can equal (a patch) or
//!   stay below (a volume) −(k + Σⱼ≠ᵢ λⱼ yⱼ² + 2βⱼ yⱼ) over the box.
//!
//! Both steps only remove points that are not on the primitive, so the result holds it
//! whatever the class (a cylinder is held by its radius across and by its planes along). A
//! side still at the limit means that the planes do not close the primitive.

use glam::{DMat3, DVec3};
use thiserror::Error;

use super::{CutKind, CutQuadric, HalfSpace};

/// Why a cut quadric has no finite box.
#[derive(Clone, Copy, Debug, Error, PartialEq)]
pub enum QuadricBoundsError {
    /// No point of the quadric is kept by its planes.
    #[error("the planes keep no point of the quadric")]
    Empty,
    /// The planes leave the primitive unbounded along a canonical axis.
    #[error("the primitive is unbounded along its canonical axis {axis}: cut it by planes")]
    Unbounded {
        /// 0, 1 or 2.
        axis: usize,
    },
}

/// A box holding a cut quadric: `lo..hi` in the canonical coordinates y, x = centre + R y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricBounds {
    /// R.
    pub rotation: DMat3,
    /// The canonical origin.
    pub centre: DVec3,
    /// Low corner, canonical coordinates.
    pub lo: DVec3,
    /// High corner, canonical coordinates.
    pub hi: DVec3,
}

impl QuadricBounds {
    /// The box's eight corners in world coordinates.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|i| {
            let y = DVec3::new(
                if i & 1 == 0 { self.lo.x } else { self.hi.x },
                if i & 2 == 0 { self.lo.y } else { self.hi.y },
                if i & 4 == 0 { self.lo.z } else { self.hi.z },
            );
            self.centre + self.rotation * y
        })
    }

    /// The axis-aligned box of the corners (low, high).
    pub fn aabb(&self) -> (DVec3, DVec3) {
        let c = self.corners();
        c.iter()
            .fold((c[0], c[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    /// The smallest sphere about the box's centre holding it (centre, radius).
    pub fn sphere(&self) -> (DVec3, f64) {
        let mid = 0.5 * (self.lo + self.hi);
        (
            self.centre + self.rotation * mid,
            0.5 * (self.hi - self.lo).length(),
        )
    }
}

impl CutQuadric {
    /// A box holding this primitive (see the module's comment), searched within `limit` of
    /// the quadric's canonical origin.
    pub fn bounds(&self, limit: f64) -> Result<QuadricBounds, QuadricBoundsError> {
        let canon = self.quadric.canonical();
        let planes: Vec<HalfSpace> = self
            .planes
            .iter()
            .map(|h| HalfSpace {
                normal: canon.rotation.transpose() * h.normal,
                offset: h.value(canon.centre),
            })
            .collect();
        let mut lo = DVec3::splat(-limit);
        let mut hi = DVec3::splat(limit);
        for _ in 0..24 {
            let before = (lo, hi);
            if !planes.is_empty() {
                (lo, hi) = polytope_box(lo, hi, &planes).ok_or(QuadricBoundsError::Empty)?;
            }
            for i in 0..3 {
                let range =
                    |j: usize| quadratic_range(canon.lambda[j], canon.beta[j], lo[j], hi[j]);
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                let (rj, rk) = (range(j), range(k));
                let r1 = -(canon.constant + rj.0 + rk.0);
                let r0 = match self.kind {
                    CutKind::Patch => -(canon.constant + rj.1 + rk.1),
                    CutKind::Volume => f64::NEG_INFINITY,
                };
                let (l, h) =
                    preimage_hull(canon.lambda[i], canon.beta[i], (r0, r1), (lo[i], hi[i]))
                        .ok_or(QuadricBoundsError::Empty)?;
                lo[i] = l;
                hi[i] = h;
            }
            let change = (lo - before.0)
                .abs()
                .max((hi - before.1).abs())
                .max_element();
            if change <= 1e-12 * (hi - lo).max_element().max(f64::MIN_POSITIVE) {
                break;
            }
        }
        for axis in 0..3 {
            if lo[axis] <= -0.5 * limit || hi[axis] >= 0.5 * limit {
                return Err(QuadricBoundsError::Unbounded { axis });
            }
        }
        // A hair wider: the tests above accept points within rounding of the boundary.
        let pad = 1e-9 * (hi - lo).max_element() + 1e-300;
        Ok(QuadricBounds {
            rotation: canon.rotation,
            centre: canon.centre,
            lo: lo - pad,
            hi: hi + pad,
        })
    }
}

/// The range of λ y² + 2β y over y ∈ [lo, hi].
fn quadratic_range(lambda: f64, beta: f64, lo: f64, hi: f64) -> (f64, f64) {
    let f = |y: f64| lambda * y * y + 2.0 * beta * y;
    let (a, b) = (f(lo), f(hi));
    let (mut min, mut max) = (a.min(b), a.max(b));
    if lambda != 0.0 {
        let vertex = -beta / lambda;
        if vertex > lo && vertex < hi {
            min = min.min(f(vertex));
            max = max.max(f(vertex));
        }
    }
    (min, max)
}

/// The hull of {y ∈ [lo, hi] : λ y² + 2β y ∈ [r0, r1]}, `None` when empty. The set's ends
/// are among lo, hi and the roots of f = r0 and f = r1; each candidate, and each gap between
/// two, is tested (within rounding of f's terms).
fn preimage_hull(
    lambda: f64,
    beta: f64,
    (r0, r1): (f64, f64),
    (lo, hi): (f64, f64),
) -> Option<(f64, f64)> {
    let f = |y: f64| lambda * y * y + 2.0 * beta * y;
    let tolerance =
        |y: f64| 1e-12 * (lambda.abs() * y * y + 2.0 * (beta * y).abs() + finite(r0) + finite(r1));
    let member = |y: f64| {
        let v = f(y);
        v >= r0 - tolerance(y) && v <= r1 + tolerance(y)
    };
    let mut candidates = vec![lo, hi];
    for r in [r0, r1] {
        if !r.is_finite() {
            continue;
        }
        // λ y² + 2β y − r = 0.
        if lambda == 0.0 {
            if beta != 0.0 {
                candidates.push(r / (2.0 * beta));
            }
            continue;
        }
        let disc = beta * beta + lambda * r;
        if disc < 0.0 {
            continue;
        }
        let q = -(beta + beta.signum() * disc.sqrt());
        if q != 0.0 {
            candidates.push(q / lambda);
            candidates.push(-r / q);
        } else {
            candidates.push(0.0);
        }
    }
    let mut candidates: Vec<f64> = candidates
        .into_iter()
        .filter(|y| y.is_finite() && *y >= lo && *y <= hi)
        .collect();
    candidates.sort_by(f64::total_cmp);
    candidates.dedup();
    let n = candidates.len();
    let kept = |i: usize| {
        member(candidates[i])
            || (i + 1 < n && member(0.5 * (candidates[i] + candidates[i + 1])))
            || (i > 0 && member(0.5 * (candidates[i - 1] + candidates[i])))
    };
    let first = (0..n).find(|&i| kept(i))?;
    let last = (0..n).rev().find(|&i| kept(i))?;
    Some((candidates[first], candidates[last]))
}

/// |x|, or 0 for an infinite bound.
fn finite(x: f64) -> f64 {
    if x.is_finite() { x.abs() } else { 0.0 }
}

/// The box of the polytope {lo ≤ y ≤ hi} ∩ every half-space, from the points where three of
/// the bounding planes meet; `None` when no such point is kept.
fn polytope_box(lo: DVec3, hi: DVec3, planes: &[HalfSpace]) -> Option<(DVec3, DVec3)> {
    let mut all: Vec<HalfSpace> = Vec::with_capacity(6 + planes.len());
    for i in 0..3 {
        let e = DVec3::AXES[i];
        all.push(HalfSpace {
            normal: e,
            offset: -hi[i],
        });
        all.push(HalfSpace {
            normal: -e,
            offset: lo[i],
        });
    }
    all.extend(planes.iter().map(|h| {
        let n = h.normal.length();
        HalfSpace {
            normal: h.normal / n,
            offset: h.offset / n,
        }
    }));
    let scale = lo.abs().max(hi.abs()).max_element();
    let tolerance = 1e-9 * scale;
    let mut out: Option<(DVec3, DVec3)> = None;
    let n = all.len();
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                let m = DMat3::from_cols(all[a].normal, all[b].normal, all[c].normal).transpose();
                let det = m.determinant();
                if det.abs() < 1e-12 {
                    continue;
                }
                let p = m.inverse() * -DVec3::new(all[a].offset, all[b].offset, all[c].offset);
                if all.iter().all(|h| h.value(p) <= tolerance) {
                    out = Some(match out {
                        None => (p, p),
                        Some((l, h)) => (l.min(p), h.max(p)),
                    });
                }
            }
        }
    }
    out.map(|(l, h)| (l.max(lo), h.min(hi)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadric::Quadric;

    fn cut(quadric: Quadric, planes: Vec<HalfSpace>, kind: CutKind) -> CutQuadric {
        CutQuadric {
            quadric,
            planes,
            kind,
        }
    }

    fn slab(z0: f64, z1: f64) -> Vec<HalfSpace> {
        vec![
            HalfSpace::through(DVec3::new(0.0, 0.0, z1), DVec3::Z),
            HalfSpace::through(DVec3::new(0.0, 0.0, z0), -DVec3::Z),
        ]
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn a_sphere_s_box_is_its_cube() {
        let b = cut(Quadric::sphere(2.0), vec![], CutKind::Patch)
            .bounds(1e6)
            .unwrap();
        let (lo, hi) = b.aabb();
        assert!(
            close(lo, DVec3::splat(-2.0)) && close(hi, DVec3::splat(2.0)),
            "{lo} {hi}"
        );
    }

    #[test]
    fn a_cylinder_is_held_by_its_radius_and_its_planes() {
        let c = cut(Quadric::cylinder(1.0), slab(100.0, 103.0), CutKind::Patch);
        let (lo, hi) = c.bounds(1e6).unwrap().aabb();
        assert!(close(lo, DVec3::new(-1.0, -1.0, 100.0)), "{lo}");
        assert!(close(hi, DVec3::new(1.0, 1.0, 103.0)), "{hi}");
        let open = cut(
            Quadric::cylinder(1.0),
            slab(0.0, 1.0)[..1].to_vec(),
            CutKind::Patch,
        );
        assert!(matches!(
            open.bounds(1e6),
            Err(QuadricBoundsError::Unbounded { .. })
        ));
    }

    #[test]
    fn a_cone_widens_to_its_far_plane() {
        let c = cut(Quadric::cone(1.0, 1.0, 1.0), slab(1.0, 2.0), CutKind::Patch);
        let (lo, hi) = c.bounds(1e6).unwrap().aabb();
        assert!(close(lo, DVec3::new(-2.0, -2.0, 1.0)) && close(hi, DVec3::new(2.0, 2.0, 2.0)));
    }

    #[test]
    fn a_paraboloid_is_closed_by_one_plane() {
        let c = cut(
            Quadric::elliptic_paraboloid(1.0, 1.0),
            slab(-5.0, 4.0)[..1].to_vec(),
            CutKind::Volume,
        );
        let (lo, hi) = c.bounds(1e6).unwrap().aabb();
        assert!(close(lo, DVec3::new(-2.0, -2.0, 0.0)), "{lo}");
        assert!(close(hi, DVec3::new(2.0, 2.0, 4.0)), "{hi}");
    }

    #[test]
    fn planes_that_miss_the_quadric_leave_it_empty() {
        let c = cut(Quadric::sphere(1.0), slab(2.0, 3.0), CutKind::Patch);
        assert_eq!(c.bounds(1e6), Err(QuadricBoundsError::Empty));
    }
}
