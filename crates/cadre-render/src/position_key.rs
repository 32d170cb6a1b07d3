//! Exact keys of mesh-local positions: the mesher gives every face its own vertices, and the
//! faces along a B-Rep edge the edge's own samples, so equal bits mean one point. The upload
//! welds positions (`solid`), finds face boundaries (`feature_edges`) and the faces along
//! edges (`edge_faces`) by these keys.

/// The bits of a position; −0 and +0 weld.
pub(crate) fn point_key(p: [f32; 3]) -> [u32; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

/// Exact bits of a segment's two ends, the lower end first.
pub(crate) type SideKey = [u32; 6];

/// The key of the segment from `a` to `b`, the same both ways.
pub(crate) fn side_key(a: [f32; 3], b: [f32; 3]) -> SideKey {
    let (ka, kb) = (point_key(a), point_key(b));
    let (lo, hi) = if ka <= kb { (ka, kb) } else { (kb, ka) };
    [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A side's key does not depend on its direction; signed zeros weld; distinct points
    /// keep distinct keys.
    #[test]
    fn keys_weld_what_is_one_point() {
        let a = [0.0, 1.0, 2.0];
        let b = [-0.0, 1.0, 2.5];
        assert_eq!(side_key(a, b), side_key(b, a));
        assert_eq!(point_key([0.0, 0.0, 0.0]), point_key([-0.0, -0.0, -0.0]));
        assert_ne!(point_key(a), point_key(b));
    }
}
