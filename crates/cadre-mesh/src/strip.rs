//! Triangulation of a thin closed polygon as a strip between its two halves, for faces and
//! cracks too thin for anything inside them.

use cadre_geom::Vec3;

/// Triangulates the strip between the two chains of the loop `xyz` (loop order, face on the
/// left) that join its two farthest points: both chains are walked from one tip to the
/// other, advancing the one whose next point comes first by relative length along its
/// chain. `n − 2` triangles of loop indices, counter-clockwise, that use every side once
/// and every rung twice.
pub(crate) fn zip_strip(xyz: &[Vec3]) -> Vec<[usize; 3]> {
    let n = xyz.len();
    let (mut t1, mut t2, mut far) = (0, 1, -1.0);
    for i in 0..n {
        for j in i + 1..n {
            let d = (xyz[i] - xyz[j]).length_squared();
            if d > far {
                (t1, t2, far) = (i, j, d);
            }
        }
    }
    // Chain `a` runs t1 → t2 along the loop (face on its left), chain `b` t1 → t2 against
    // it (face on its right).
    let a: Vec<usize> = (t1..=t2).collect();
    let b: Vec<usize> = (0..=(n + t1 - t2)).map(|k| (t1 + n - k) % n).collect();
    let along = |c: &[usize]| -> Vec<f64> {
        let mut s = vec![0.0];
        for w in c.windows(2) {
            s.push(s[s.len() - 1] + (xyz[w[1]] - xyz[w[0]]).length());
        }
        let total = s[s.len() - 1];
        s.iter()
            .map(|x| if total > 0.0 { x / total } else { 0.0 })
            .collect()
    };
    let (sa, sb) = (along(&a), along(&b));
    let (la, lb) = (a.len() - 1, b.len() - 1);
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::with_capacity(n.saturating_sub(2));
    while i < la || j < lb {
        let tri = if i < la && (j == lb || sa[i + 1] <= sb[j + 1]) {
            i += 1;
            [a[i - 1], a[i], b[j]]
        } else {
            j += 1;
            [b[j], b[j - 1], a[i]]
        };
        // The first and last steps start or end on a tip, shared by both chains.
        if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
            out.push(tri);
        }
    }
    out
}

/// Height of the triangle `abc` over its longest side (0 for a point, NaN for NaN input):
/// how thin a strip or fold triangle is.
pub(crate) fn height(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    let twice_area = (b - a).cross(c - a).length();
    if longest == 0.0 {
        0.0
    } else {
        twice_area / longest
    }
}
