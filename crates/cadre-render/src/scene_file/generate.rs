//! Generated crowds of quadrics (the benchmarks' 10⁶ and 10⁷ objects): spheres, cylinders
//! and cones cut by up to 6 planes, scattered in a cube. Each kind comes in
//! [`VARIANTS`] sizes and cuts shared by every object of that variant (one box computed per
//! variant, not per object); each object has its own position, axis and colour.

use std::sync::Arc;

use cadre_geom::{CutKind, CutQuadric, Frame, HalfSpace, Quadric};
use glam::DVec3;
use serde::Deserialize;

use crate::{AnalyticPrimitive, AnalyticShape, QuadricShape};

/// Sizes and cuts per kind.
pub const VARIANTS: usize = 8;

/// A crowd of generated objects.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Generate {
    /// How many.
    pub count: u64,
    /// Which kinds, drawn in turn at random.
    #[serde(default = "all_kinds")]
    pub kinds: Vec<GeneratedKind>,
    /// Oblique cutting planes added to each object (0 to 6; cylinders and cones also have
    /// their two end planes).
    #[serde(default)]
    pub planes: usize,
    /// Seed of the generator: the same seed gives the same scene.
    #[serde(default = "one")]
    pub seed: u64,
    /// Side of the cube they are scattered in, centred on the origin.
    #[serde(default = "hundred")]
    pub extent: f64,
    /// Typical object size (a sphere's radius; a cylinder's and a cone's height is twice it).
    #[serde(default = "unit")]
    pub size: f64,
    /// Volumes instead of surface patches.
    #[serde(default)]
    pub volume: bool,
}

/// A kind of generated object.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum GeneratedKind {
    /// A sphere.
    Sphere,
    /// A circular cylinder between two planes.
    Cylinder,
    /// A circular cone between two planes.
    Cone,
}

fn all_kinds() -> Vec<GeneratedKind> {
    vec![
        GeneratedKind::Sphere,
        GeneratedKind::Cylinder,
        GeneratedKind::Cone,
    ]
}

fn one() -> u64 {
    1
}

fn hundred() -> f64 {
    100.0
}

fn unit() -> f64 {
    1.0
}

/// SplitMix64: a small deterministic generator (the scene must not depend on a crate's
/// stream changing between versions).
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A unit vector, uniform on the sphere.
    fn direction(&mut self) -> DVec3 {
        let z = 2.0 * self.unit() - 1.0;
        let a = std::f64::consts::TAU * self.unit();
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * a.cos(), r * a.sin(), z)
    }
}

impl Generate {
    /// The crowd's objects, face ids from `first`; an error when its numbers are unusable.
    pub fn primitives(&self, first: u32) -> Result<Vec<AnalyticPrimitive>, String> {
        if !(self.extent.is_finite()
            && self.extent > 0.0
            && self.size.is_finite()
            && self.size > 0.0)
        {
            return Err("extent and size must be positive numbers".into());
        }
        if self.planes > 6 {
            return Err(format!("{} planes asked for; at most 6", self.planes));
        }
        if self.kinds.is_empty() {
            return Err("no kind of object".into());
        }
        let mut rng = SplitMix(self.seed);
        let shapes: Vec<Vec<Arc<QuadricShape>>> = self
            .kinds
            .iter()
            .map(|&kind| {
                (0..VARIANTS)
                    .map(|v| self.variant(kind, v, &mut rng))
                    .collect::<Result<Vec<_>, String>>()
            })
            .collect::<Result<_, _>>()?;
        let count = usize::try_from(self.count).map_err(|_| "too many objects".to_string())?;
        let mut out = Vec::with_capacity(count);
        for k in 0..count {
            let kind = (rng.next() % self.kinds.len() as u64) as usize;
            let variant = (rng.next() % VARIANTS as u64) as usize;
            let origin = (DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5) * self.extent;
            let axis = rng.direction();
            let frame = Frame::from_axis(origin, axis, None).ok_or("a degenerate axis")?;
            // 32 colours: each a material, shared by the objects that have it.
            let hue = (rng.next() % 32) as f32 / 31.0;
            out.push(AnalyticPrimitive {
                shape: AnalyticShape::Quadric(Arc::clone(&shapes[kind][variant])),
                frame,
                face_id: first.wrapping_add(k as u32),
                colour: [
                    0.25 + 0.6 * hue,
                    0.35 + 0.4 * (1.0 - hue),
                    0.85 - 0.5 * hue,
                    1.0,
                ],
            });
        }
        Ok(out)
    }

    /// Variant `v` of `kind`: its size and its cuts.
    fn variant(
        &self,
        kind: GeneratedKind,
        v: usize,
        rng: &mut SplitMix,
    ) -> Result<Arc<QuadricShape>, String> {
        let r = self.size * (0.6 + 0.8 * v as f64 / VARIANTS as f64);
        let ends = |z0: f64, z1: f64| {
            vec![
                HalfSpace::through(DVec3::new(0.0, 0.0, z1), DVec3::Z),
                HalfSpace::through(DVec3::new(0.0, 0.0, z0), -DVec3::Z),
            ]
        };
        let (quadric, mut planes, centre) = match kind {
            GeneratedKind::Sphere => (Quadric::sphere(r), Vec::new(), DVec3::ZERO),
            GeneratedKind::Cylinder => (Quadric::cylinder(0.5 * r), ends(-r, r), DVec3::ZERO),
            // Apex at the origin, opening 0.5 wide per unit of height, cut 0.2 r from it.
            GeneratedKind::Cone => (
                Quadric::cone(0.5, 0.5, 1.0),
                ends(0.2 * r, 2.0 * r),
                DVec3::new(0.0, 0.0, 1.1 * r),
            ),
        };
        // Oblique planes through points 0.3 r out from the middle, facing away from it: each
        // keeps the middle, so no cut empties the object.
        for _ in 0..self.planes {
            let n = rng.direction();
            planes.push(HalfSpace::through(centre + 0.3 * r * n, n));
        }
        let cut = CutQuadric {
            quadric,
            planes,
            kind: CutKind::volume_if(self.volume),
        };
        QuadricShape::new(cut).map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_crowd() {
        let crowd = Generate {
            count: 200,
            kinds: all_kinds(),
            planes: 6,
            seed: 9,
            extent: 50.0,
            size: 1.0,
            volume: false,
        };
        let a = crowd.primitives(1).unwrap();
        let b = crowd.primitives(1).unwrap();
        assert_eq!(a.len(), 200);
        assert!(a.iter().zip(&b).all(|(x, y)| x.frame == y.frame));
        let other = Generate { seed: 10, ..crowd }.primitives(1).unwrap();
        assert!(a.iter().zip(&other).any(|(x, y)| x.frame != y.frame));
        // Every object lies in the cube.
        assert!(a.iter().all(|p| p.frame.origin.abs().max_element() <= 25.0));
    }
}
