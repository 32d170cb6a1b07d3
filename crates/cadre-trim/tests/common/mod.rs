//! What the trim tests share: the even-odd rule on closed polygons and the distance to them.

use cadre_trim::Uv;

/// Even-odd over closed polygons.
pub fn even_odd(loops: &[Vec<Uv>], p: Uv) -> bool {
    let mut inside = false;
    for l in loops {
        for k in 0..l.len() {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            if (a.y <= p.y) != (b.y <= p.y) {
                let u = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if u > p.x {
                    inside = !inside;
                }
            }
        }
    }
    inside
}

/// Distance from `p` to the polygons' sides, each axis divided by `scale`.
pub fn to_boundary(loops: &[Vec<Uv>], p: Uv, scale: Uv) -> f64 {
    let q = p / scale;
    let mut best = f64::INFINITY;
    for l in loops {
        for k in 0..l.len() {
            let (a, b) = (l[k] / scale, l[(k + 1) % l.len()] / scale);
            let ab = b - a;
            let t = ((q - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
            best = best.min((a + t * ab - q).length());
        }
    }
    best
}
