//! A quadric cut by planes (seed 001) prepared for the ray caster: its box, and the quadric
//! and planes rewritten in the box's own frame (its canonical axes, from the box's centre),
//! where the GPU casts each pixel's ray. There the quadric is Σ λᵢ zᵢ² + 2 bᵀz + c and every
//! coordinate is of the primitive's size, so `f32` keeps it at any distance from the origin.

use std::sync::Arc;

use cadre_geom::quadric::{QuadricBounds, QuadricBoundsError, QuadricClass};
use cadre_geom::{CutKind, CutQuadric};
use glam::{DAffine3, DVec3, DVec4};

/// How far from its canonical origin a primitive is searched for its box (model units): a
/// side still this far out means that the planes do not close it.
const SEARCH_LIMIT: f64 = 1e9;

/// A cut quadric ready to draw, in its [`crate::AnalyticPrimitive::frame`]'s coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadricShape {
    cut: CutQuadric,
    bounds: QuadricBounds,
    local: LocalQuadric,
}

/// The quadric and its planes in the box's frame (see the module's comment).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LocalQuadric {
    /// Box frame → the primitive's frame.
    pub placement: DAffine3,
    /// Half the box's sides.
    pub half: DVec3,
    /// λ (the diagonal of the quadratic part).
    pub lambda: DVec3,
    /// b (half the linear part).
    pub linear: DVec3,
    /// c.
    pub constant: f64,
    /// The half-spaces (n, d): n·z + d ≤ 0 is kept.
    pub planes: Vec<DVec4>,
    /// Whether the uncut quadric is an ellipsoid (its screen bounds then come from its dual).
    pub ellipsoid: bool,
    /// Whether the rays tangent to it are its silhouettes: not for two intersecting planes,
    /// whose rays through their common line are double roots inside the surface.
    pub smooth: bool,
}

impl QuadricShape {
    /// Prepares `cut` (given in the primitive's frame); an error when its planes keep no
    /// point of it or do not close it.
    pub fn new(cut: CutQuadric) -> Result<Arc<QuadricShape>, QuadricBoundsError> {
        let bounds = cut.bounds(SEARCH_LIMIT)?;
        let canon = cut.quadric.canonical();
        let mid = 0.5 * (bounds.lo + bounds.hi);
        let origin = bounds.centre + bounds.rotation * mid;
        let placement = DAffine3::from_mat3_translation(bounds.rotation, origin);
        // y = mid + z: λ(mid + z)² + 2β(mid + z) + k.
        let (lambda, beta) = (canon.lambda, canon.beta);
        let linear = lambda * mid + beta;
        let constant = (lambda * mid * mid + 2.0 * beta * mid).element_sum() + canon.constant;
        let planes = cut
            .planes
            .iter()
            .map(|h| {
                let n = bounds.rotation.transpose() * h.normal;
                let len = n.length().max(f64::MIN_POSITIVE);
                n.extend(h.value(origin)) / len
            })
            .collect();
        let local = LocalQuadric {
            placement,
            half: 0.5 * (bounds.hi - bounds.lo),
            lambda,
            linear,
            constant,
            planes,
            ellipsoid: canon.class == QuadricClass::Ellipsoid,
            smooth: canon.class != QuadricClass::IntersectingPlanes,
        };
        Ok(Arc::new(QuadricShape { cut, bounds, local }))
    }

    /// The primitive, in its frame's coordinates.
    pub fn cut(&self) -> &CutQuadric {
        &self.cut
    }

    /// Its box, in its frame's coordinates.
    pub fn bounds(&self) -> &QuadricBounds {
        &self.bounds
    }

    /// Surface patch or volume.
    pub fn kind(&self) -> CutKind {
        self.cut.kind
    }

    /// The quadric and its planes in the box's frame.
    pub(crate) fn local(&self) -> &LocalQuadric {
        &self.local
    }

    /// The box's centre and half-diagonal, in the frame's coordinates.
    pub fn sphere(&self) -> (DVec3, f64) {
        self.bounds.sphere()
    }
}
