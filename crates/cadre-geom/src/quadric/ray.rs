//! The `f64` ray intersection of a cut quadric: the oracle the GPU ray caster is tested
//! against. Along the ray o + t d the quadric is A t² + 2B t + C with A = dᵀQd, B = dᵀQo,
//! C = oᵀQo (d with w = 0, o with w = 1); its roots come from the stable form
//! q = −(B + sign(B)√(B² − AC)), t = q / A and C / q, which never subtracts nearly equal
//! numbers. The ray's origin is first moved along it to the point nearest the quadric's own
//! origin, so that a small quadric seen from far away is not lost in C = oᵀQo (1 µm seen
//! from 1 km: C would be 10¹² − 10⁻⁶).

use glam::DVec3;

use super::{CutKind, CutQuadric, Quadric};

/// Which boundary of a cut quadric a ray met.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HitBoundary {
    /// The quadric surface.
    Quadric,
    /// The cutting plane of this index (a volume's flat face).
    Plane(usize),
}

/// Where a ray meets a cut quadric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricHit {
    /// The ray parameter.
    pub t: f64,
    /// The point o + t d.
    pub point: DVec3,
    /// Unit normal of the boundary met, pointing out of Q ≤ 0 (the quadric's gradient) or
    /// out of the kept half-space (a plane's normal).
    pub normal: DVec3,
    /// What was met.
    pub boundary: HitBoundary,
}

/// The quadric along a ray: A s² + 2B s + C, with t = `shift` + s.
#[derive(Clone, Copy, Debug)]
struct AlongRay {
    a: f64,
    b: f64,
    c: f64,
    shift: f64,
}

impl AlongRay {
    fn new(q: &Quadric, o: DVec3, d: DVec3) -> AlongRay {
        let dd = d.dot(d);
        let shift = if dd > 0.0 { -o.dot(d) / dd } else { 0.0 };
        let (ho, hd) = ((o + shift * d).extend(1.0), d.extend(0.0));
        let qo = q.matrix * ho;
        AlongRay {
            a: hd.dot(q.matrix * hd),
            b: hd.dot(qo),
            c: ho.dot(qo),
            shift,
        }
    }

    /// The real roots in t, ascending (none, one for a linear or tangent ray, or two).
    fn roots(&self) -> Vec<f64> {
        let mut roots = self.shifted_roots();
        for r in &mut roots {
            *r += self.shift;
        }
        roots
    }

    /// The real roots in s.
    fn shifted_roots(&self) -> Vec<f64> {
        let AlongRay { a, b, c, .. } = *self;
        if a == 0.0 {
            return if b == 0.0 {
                Vec::new()
            } else {
                vec![-c / (2.0 * b)]
            };
        }
        let disc = b * b - a * c;
        if disc < 0.0 {
            return Vec::new();
        }
        let q = -(b + b.signum() * disc.sqrt());
        if q == 0.0 {
            // b = 0 and a c = 0: a double root at 0.
            return vec![0.0];
        }
        let (t0, t1) = (q / a, c / q);
        vec![t0.min(t1), t0.max(t1)]
    }

    /// The parameter intervals where the quadric is ≤ 0, as (from, to) with ±∞ ends.
    fn inside(&self) -> Vec<(f64, f64)> {
        let inf = f64::INFINITY;
        let roots = self.roots();
        match roots.as_slice() {
            [] => {
                // One sign all along: the sign of A, or of C when A is zero.
                let sign = if self.a != 0.0 { self.a } else { self.c };
                if sign <= 0.0 {
                    vec![(-inf, inf)]
                } else {
                    vec![]
                }
            }
            [r] if self.a == 0.0 => {
                // Linear: 2B t + C ≤ 0.
                if self.b > 0.0 {
                    vec![(-inf, *r)]
                } else {
                    vec![(*r, inf)]
                }
            }
            [r] => {
                // Tangent: inside only at the root (A > 0) or everywhere (A < 0).
                if self.a > 0.0 {
                    vec![(*r, *r)]
                } else {
                    vec![(-inf, inf)]
                }
            }
            [r0, r1, ..] => {
                if self.a > 0.0 {
                    vec![(*r0, *r1)]
                } else {
                    vec![(-inf, *r0), (*r1, inf)]
                }
            }
        }
    }
}

impl CutQuadric {
    /// The first boundary point of this primitive along o + t d with t > `t_min`, or
    /// `None`. A patch: the nearest root kept by every plane (the back sheet where the front
    /// is cut away). A volume: the nearest end of an interval of the ray inside Q ≤ 0 and
    /// every half-space — where a plane ends it, the plane is what is met.
    pub fn hit(&self, o: DVec3, d: DVec3, t_min: f64) -> Option<QuadricHit> {
        let along = AlongRay::new(&self.quadric, o, d);
        let at = |t: f64, boundary: HitBoundary| {
            let point = o + t * d;
            let normal = match boundary {
                HitBoundary::Quadric => self.quadric.gradient(point),
                HitBoundary::Plane(k) => self.planes[k].normal,
            };
            QuadricHit {
                t,
                point,
                normal: normal.normalize_or_zero(),
                boundary,
            }
        };
        match self.kind {
            CutKind::Patch => along
                .roots()
                .into_iter()
                .filter(|&t| t > t_min)
                .find(|&t| self.planes.iter().all(|h| h.value(o + t * d) <= 0.0))
                .map(|t| at(t, HitBoundary::Quadric)),
            CutKind::Volume => {
                let (from, to) = self.plane_interval(o, d)?;
                along
                    .inside()
                    .into_iter()
                    .filter_map(|(a, b)| {
                        let start = if a >= from.0 {
                            (a, HitBoundary::Quadric)
                        } else {
                            from
                        };
                        let end = if b <= to.0 {
                            (b, HitBoundary::Quadric)
                        } else {
                            to
                        };
                        (start.0 <= end.0).then_some([start, end])
                    })
                    .flatten()
                    .find(|&(t, _)| t > t_min && t.is_finite())
                    .map(|(t, boundary)| at(t, boundary))
            }
        }
    }

    /// The interval of the ray kept by every half-space, each end with what bounds it
    /// (±∞ with the quadric as a placeholder when nothing does); `None` when empty.
    #[allow(clippy::type_complexity)]
    fn plane_interval(
        &self,
        o: DVec3,
        d: DVec3,
    ) -> Option<((f64, HitBoundary), (f64, HitBoundary))> {
        let mut from = (f64::NEG_INFINITY, HitBoundary::Quadric);
        let mut to = (f64::INFINITY, HitBoundary::Quadric);
        for (k, h) in self.planes.iter().enumerate() {
            // n·o + d + t n·d ≤ 0.
            let (v, s) = (h.value(o), h.normal.dot(d));
            if s == 0.0 {
                if v > 0.0 {
                    return None;
                }
                continue;
            }
            let t = -v / s;
            if s > 0.0 {
                if t < to.0 {
                    to = (t, HitBoundary::Plane(k));
                }
            } else if t > from.0 {
                from = (t, HitBoundary::Plane(k));
            }
        }
        (from.0 <= to.0).then_some((from, to))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadric::HalfSpace;

    fn sphere(kind: CutKind, planes: Vec<HalfSpace>) -> CutQuadric {
        CutQuadric {
            quadric: Quadric::sphere(1.0),
            planes,
            kind,
        }
    }

    #[test]
    fn a_ray_meets_a_sphere_at_its_front() {
        let s = sphere(CutKind::Patch, vec![]);
        let hit = s.hit(DVec3::new(0.0, 0.0, -5.0), DVec3::Z, 0.0).unwrap();
        assert!((hit.t - 4.0).abs() < 1e-15);
        assert_eq!(hit.normal, -DVec3::Z);
    }

    #[test]
    fn a_cut_patch_shows_its_back_sheet_and_a_cut_volume_its_plane() {
        // Cut by z ≤ −0.5 … keep z ≥ −0.5: the front (z = −1) is cut away.
        let keep_back = vec![HalfSpace::through(DVec3::new(0.0, 0.0, -0.5), -DVec3::Z)];
        let o = DVec3::new(0.0, 0.0, -5.0);
        let patch = sphere(CutKind::Patch, keep_back.clone())
            .hit(o, DVec3::Z, 0.0)
            .unwrap();
        assert!((patch.point.z - 1.0).abs() < 1e-12);
        assert_eq!(patch.boundary, HitBoundary::Quadric);
        let volume = sphere(CutKind::Volume, keep_back)
            .hit(o, DVec3::Z, 0.0)
            .unwrap();
        assert!((volume.point.z + 0.5).abs() < 1e-12);
        assert_eq!(volume.boundary, HitBoundary::Plane(0));
        assert_eq!(volume.normal, -DVec3::Z);
    }

    #[test]
    fn a_ray_through_a_hyperboloid_s_two_sheets_and_its_gap() {
        // z² − x² − y² = 1: inside is |z| ≥ √(1 + x² + y²) (Q ≤ 0 there).
        let h = CutQuadric {
            quadric: Quadric::hyperboloid_two_sheets(1.0, 1.0, 1.0),
            planes: vec![],
            kind: CutKind::Volume,
        };
        let o = DVec3::new(0.0, 0.0, -5.0);
        let first = h.hit(o, DVec3::Z, 0.0).unwrap();
        assert!((first.point.z + 1.0).abs() < 1e-12);
        let second = h.hit(o, DVec3::Z, first.t + 1e-9).unwrap();
        assert!((second.point.z - 1.0).abs() < 1e-12);
        // A ray across the gap, off the axis, misses.
        assert!(h.hit(DVec3::new(-5.0, 0.0, 0.0), DVec3::X, 0.0).is_none());
    }

    #[test]
    fn a_far_ray_keeps_its_precision() {
        // The stable root: a sphere of 1 µm seen from 1 km.
        let s = CutQuadric {
            quadric: Quadric::sphere(1e-3),
            planes: vec![],
            kind: CutKind::Patch,
        };
        let hit = s.hit(DVec3::new(0.0, 0.0, -1e6), DVec3::Z, 0.0).unwrap();
        // Within the rounding of a point 1 km out (1e-10), not lost in C (1e-2 off).
        assert!((hit.point.z + 1e-3).abs() < 1e-9, "{}", hit.point.z);
    }
}
