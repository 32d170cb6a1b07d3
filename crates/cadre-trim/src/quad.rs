//! Quadratic Bézier pieces of trim curves in (u, v), and their local implicit forms.
//!
//! Loop and Blinn (SIGGRAPH 2005) evaluate a quadratic curve's side per pixel from an implicit
//! form: the affine map that takes the control points `p0, p1, p2` to `(0, 0), (½, 0), (1, 1)`
//! takes the curve to the parabola `y = x²` (`B(t) ↦ (t, t²)`), so the sign of `x² − y` says on
//! which side of the curve a point lies. The seed's thesis uses the same form for its trim
//! quadtree's leaves; the GPU evaluates it per fragment, the CPU classifier here on the same
//! numbers.

use crate::Uv;

/// A quadratic Bézier piece of a trim loop, in (u, v), oriented as its loop runs (the face on
/// its left).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadPiece {
    /// Start, control point, end.
    pub p: [Uv; 3],
}

impl QuadPiece {
    /// The straight piece from `a` to `b` (its control point halfway).
    pub fn line(a: Uv, b: Uv) -> QuadPiece {
        QuadPiece {
            p: [a, 0.5 * (a + b), b],
        }
    }

    /// The point at `t` in [0, 1].
    pub fn eval(&self, t: f64) -> Uv {
        let s = 1.0 - t;
        s * s * self.p[0] + 2.0 * s * t * self.p[1] + t * t * self.p[2]
    }

    /// The derivative at `t`.
    pub fn derivative(&self, t: f64) -> Uv {
        2.0 * ((1.0 - t) * (self.p[1] - self.p[0]) + t * (self.p[2] - self.p[1]))
    }

    /// The two pieces before and after `t` (de Casteljau).
    pub fn split(&self, t: f64) -> (QuadPiece, QuadPiece) {
        let q0 = self.p[0].lerp(self.p[1], t);
        let q1 = self.p[1].lerp(self.p[2], t);
        let m = q0.lerp(q1, t);
        (
            QuadPiece {
                p: [self.p[0], q0, m],
            },
            QuadPiece {
                p: [m, q1, self.p[2]],
            },
        )
    }

    /// The piece cut where it turns in u or in v, so that each part is monotone in both
    /// (a quadratic turns at most once per axis): one to three parts, in order, sharing
    /// their ends exactly.
    pub fn monotone_parts(&self) -> Vec<QuadPiece> {
        let mut cuts: Vec<f64> = (0..2)
            .filter_map(|axis| {
                let (a, b, c) = (self.p[0][axis], self.p[1][axis], self.p[2][axis]);
                let denominator = a - 2.0 * b + c;
                let t = (a - b) / denominator;
                (denominator != 0.0 && t > 1e-9 && t < 1.0 - 1e-9).then_some(t)
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let mut parts = Vec::with_capacity(cuts.len() + 1);
        let mut rest = *self;
        let mut done = 0.0;
        for t in cuts {
            // `rest` spans [done, 1] of the original piece.
            let (head, tail) = rest.split((t - done) / (1.0 - done));
            parts.push(head);
            rest = tail;
            done = t;
        }
        parts.push(rest);
        parts
    }

    /// The (u, v) box of the piece (of its control points: for a monotone piece, its ends').
    pub fn bounds(&self) -> (Uv, Uv) {
        (
            self.p[0].min(self.p[1]).min(self.p[2]),
            self.p[0].max(self.p[1]).max(self.p[2]),
        )
    }

    /// Its implicit form.
    pub fn implicit(&self) -> Implicit {
        Implicit::of(self)
    }
}

/// A piece's local implicit form: [`Implicit::value`] is positive on the piece's left (the
/// face's side), negative on its right, 0 on it, near the piece: within its hull, and beyond
/// its chord (on the far side from the control point). Beyond the piece's ends its sign is
/// the chord's or the parabola's, which the trim quadtree never asks for (a cell holding an
/// end is also crossed by the next piece).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Implicit {
    /// The affine map (u, v) ↦ (x, y): rows (a, b, c) with x = a u + b v + c.
    pub rows: [[f64; 3]; 2],
    /// A straight piece: the value is `y` alone (a signed distance to its line).
    pub line: bool,
    /// +1 or −1: which side of the parabola is the piece's left.
    pub sign: f64,
}

impl Implicit {
    /// The form of `piece`: the Loop–Blinn map, or a signed distance to the line through its
    /// ends where its control points are (nearly) collinear.
    pub fn of(piece: &QuadPiece) -> Implicit {
        let [p0, p1, p2] = piece.p;
        let e1 = p1 - p0;
        let e2 = p2 - p0;
        let det = e1.perp_dot(e2);
        let scale = e1.length_squared().max(e2.length_squared());
        // Nearly straight pieces (their control point within a millionth of their size of the
        // chord) are lines: their map would divide by a determinant that `f32` cannot resolve.
        if det.abs() <= 1e-6 * scale || scale == 0.0 {
            // y = signed distance from the chord, positive on its left.
            let len = e2.length().max(f64::MIN_POSITIVE);
            let n = e2.perp() / len;
            return Implicit {
                rows: [[0.0, 0.0, 0.0], [n.x, n.y, -n.dot(p0)]],
                line: true,
                sign: 1.0,
            };
        }
        // (u, v) − p0 = α e1 + β e2 ⇒ x = ½ α + β, y = β (p1 ↦ (½, 0), p2 ↦ (1, 1)).
        // α = (d × e2) / (e1 × e2), β = (e1 × d) / (e1 × e2) for d = (u, v) − p0.
        let alpha = [e2.y / det, -e2.x / det];
        let beta = [-e1.y / det, e1.x / det];
        let row = |c: [f64; 2]| [c[0], c[1], -(c[0] * p0.x + c[1] * p0.y)];
        let x = [0.5 * alpha[0] + beta[0], 0.5 * alpha[1] + beta[1]];
        Implicit {
            rows: [row(x), row(beta)],
            line: false,
            // x² − y > 0 on the control point's side, which is the piece's left when p1 lies
            // left of the chord p0 → p2 (e2 × e1 > 0).
            sign: if det < 0.0 { 1.0 } else { -1.0 },
        }
    }

    /// The mapped point (x, y).
    pub fn map(&self, p: Uv) -> Uv {
        let [a, b] = self.rows;
        Uv::new(
            a[0] * p.x + a[1] * p.y + a[2],
            b[0] * p.x + b[1] * p.y + b[2],
        )
    }

    /// Positive on the piece's left, negative on its right: `min(x² − y, x − y)` (the
    /// parabola within the hull, the chord beyond it), signed.
    pub fn value(&self, p: Uv) -> f64 {
        let q = self.map(p);
        if self.line {
            q.y
        } else {
            self.sign * (q.x * q.x - q.y).min(q.x - q.y)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map takes the control points where Loop and Blinn put them.
    #[test]
    fn the_map_takes_the_control_points_to_the_canonical_triangle() {
        let piece = QuadPiece {
            p: [Uv::new(1.0, 2.0), Uv::new(3.0, 5.0), Uv::new(6.0, 1.0)],
        };
        let f = piece.implicit();
        for (p, want) in piece.p.iter().zip([(0.0, 0.0), (0.5, 0.0), (1.0, 1.0)]) {
            let q = f.map(*p);
            assert!((q - Uv::new(want.0, want.1)).length() < 1e-12, "{p} ↦ {q}");
        }
        // Points of the curve lie on the parabola.
        for k in 0..=10 {
            let t = f64::from(k) / 10.0;
            assert!(f.value(piece.eval(t)).abs() < 1e-12);
        }
    }

    /// Monotone parts share their ends and turn in neither axis.
    #[test]
    fn monotone_parts_are_monotone_and_connected() {
        let piece = QuadPiece {
            p: [Uv::new(0.0, 0.0), Uv::new(2.0, 3.0), Uv::new(-1.0, 1.0)],
        };
        let parts = piece.monotone_parts();
        assert_eq!(parts.len(), 3, "turns in u and in v");
        assert_eq!(parts[0].p[0], piece.p[0]);
        assert_eq!(parts[2].p[2], piece.p[2]);
        for pair in parts.windows(2) {
            assert_eq!(pair[0].p[2], pair[1].p[0]);
        }
        for part in &parts {
            for axis in 0..2 {
                let d0 = part.derivative(0.0)[axis];
                let d1 = part.derivative(1.0)[axis];
                assert!(d0 * d1 >= -1e-12, "{part:?} turns in axis {axis}");
            }
        }
    }
}
