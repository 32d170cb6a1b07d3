//! Weld keys: which trim points are the same vertex of a mesh.

use crate::{EdgeId, FaceId, VertexId};

/// Constructors of the `u64` weld keys carried by [`TrimPoint`](super::TrimPoint)s. The two
/// top bits say what the key names; edge and face keys keep 32 bits of id and 28 bits of
/// index.
pub struct TrimKey;

const KIND_SHIFT: u32 = 62;
const ID_SHIFT: u32 = 28;
const INDEX_MASK: u64 = (1 << ID_SHIFT) - 1;

impl TrimKey {
    /// A B-Rep vertex.
    pub fn vertex(v: VertexId) -> u64 {
        v.index() as u64
    }

    /// The `i`-th inner sample of an edge.
    pub fn edge(e: EdgeId, i: usize) -> u64 {
        (1 << KIND_SHIFT) | ((e.index() as u64) << ID_SHIFT) | (i as u64 & INDEX_MASK)
    }

    /// A point a face adds itself (seam or pole line), `i`-th of that face.
    pub fn face(f: FaceId, i: usize) -> u64 {
        (2 << KIND_SHIFT) | ((f.index() as u64) << ID_SHIFT) | (i as u64 & INDEX_MASK)
    }

    /// A point of a polygonal (`POLY_LOOP`) boundary, keyed by its exact coordinates so that
    /// faceted faces sharing a corner weld.
    pub fn position(p: cadre_geom::Vec3) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for c in [p.x, p.y, p.z] {
            // +0.0 and -0.0 are the same point.
            (c + 0.0).to_bits().hash(&mut h);
        }
        (3 << KIND_SHIFT) | (h.finish() >> 2)
    }
}
