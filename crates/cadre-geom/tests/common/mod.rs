//! Random geometry for the property tests, built from a flat list of numbers in [0, 1) so
//! that proptest can generate and shrink it.

#![allow(dead_code, missing_docs)]

use std::f64::consts::{PI, TAU};

use cadre_geom::bspline::{BSplineCurve, BSplineSurface};
use cadre_geom::curve::{CompositeSegment, Curve, CurveFrame};
use cadre_geom::{Curve2, Curve3, Frame, Surface, Vec2, Vec3};

/// Consumes numbers in [0, 1) one at a time (cycling if it runs out).
pub struct Src<'a> {
    xs: &'a [f64],
    i: usize,
}

impl<'a> Src<'a> {
    pub fn new(xs: &'a [f64]) -> Self {
        Self { xs, i: 0 }
    }
    pub fn unit(&mut self) -> f64 {
        let x = self.xs[self.i % self.xs.len()];
        self.i += 1;
        x
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn int(&mut self, a: usize, b: usize) -> usize {
        (a + (self.unit() * (b - a + 1) as f64) as usize).min(b)
    }
    pub fn vec3(&mut self, s: f64) -> Vec3 {
        Vec3::new(self.range(-s, s), self.range(-s, s), self.range(-s, s))
    }
    pub fn vec2(&mut self, s: f64) -> Vec2 {
        Vec2::new(self.range(-s, s), self.range(-s, s))
    }
    pub fn unit_vec3(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let a = self.range(0.0, TAU);
        let r = (1.0 - z * z).sqrt();
        Vec3::new(r * a.cos(), r * a.sin(), z)
    }
    pub fn frame(&mut self) -> Frame {
        let o = self.vec3(10.0);
        let z = self.unit_vec3();
        let x = self.unit_vec3();
        Frame::from_axis(o, z, Some(x)).unwrap()
    }
    pub fn frame2(&mut self) -> CurveFrame<Vec2> {
        let a = self.range(0.0, TAU);
        let x = Vec2::new(a.cos(), a.sin());
        CurveFrame {
            origin: self.vec2(10.0),
            x,
            y: x.perp(),
        }
    }
    /// Clamped knots with `spans` distinct spans of random lengths, multiplicity 1 inside.
    pub fn knots(&mut self, degree: usize, spans: usize) -> Vec<f64> {
        let start = self.range(-2.0, 2.0);
        let mut k = vec![start; degree + 1];
        let mut t = start;
        for s in 0..spans {
            t += self.range(0.3, 1.5);
            if s + 1 == spans {
                k.extend(std::iter::repeat_n(t, degree + 1));
            } else {
                k.push(t);
            }
        }
        k
    }
    pub fn weights(&mut self, n: usize) -> Option<Vec<f64>> {
        if self.unit() < 0.5 {
            None
        } else {
            Some((0..n).map(|_| self.range(0.5, 2.0)).collect())
        }
    }
    pub fn bspline3(&mut self) -> BSplineCurve<Vec3> {
        let degree = self.int(1, 4);
        let spans = self.int(1, 4);
        let knots = self.knots(degree, spans);
        let n = knots.len() - degree - 1;
        let pts = (0..n).map(|_| self.vec3(5.0)).collect();
        let w = self.weights(n);
        BSplineCurve::try_new(degree, knots, pts, w).unwrap()
    }
    pub fn bspline2(&mut self) -> BSplineCurve<Vec2> {
        let degree = self.int(1, 4);
        let spans = self.int(1, 4);
        let knots = self.knots(degree, spans);
        let n = knots.len() - degree - 1;
        let pts = (0..n).map(|_| self.vec2(5.0)).collect();
        let w = self.weights(n);
        BSplineCurve::try_new(degree, knots, pts, w).unwrap()
    }
    /// A smooth (degree ≥ 2), regular B-spline whose control points advance steadily, so
    /// its offsets have no cusps: the offset tests' dense sampling must see every feature.
    pub fn tame_bspline3(&mut self) -> BSplineCurve<Vec3> {
        let degree = self.int(2, 4);
        let spans = self.int(1, 4);
        let knots = self.knots(degree, spans);
        let n = knots.len() - degree - 1;
        let f = self.frame();
        let pts = (0..n)
            .map(|i| {
                let (y, z) = (self.range(-0.5, 0.5), self.range(-0.5, 0.5));
                f.to_world(Vec3::new(2.0 * i as f64, y, z))
            })
            .collect();
        BSplineCurve::try_new(degree, knots, pts, None).unwrap()
    }
    /// 2D counterpart of [`Src::tame_bspline3`].
    pub fn tame_bspline2(&mut self) -> BSplineCurve<Vec2> {
        let c = self.tame_bspline3();
        let pts = c.control_points.iter().map(|p| p.truncate()).collect();
        BSplineCurve::try_new(c.degree, c.knots, pts, None).unwrap()
    }
    pub fn bspline_surface(&mut self) -> BSplineSurface {
        self.bspline_surface_of_degree(1)
    }
    /// A B-spline surface with degrees at least `min_degree`.
    pub fn bspline_surface_of_degree(&mut self, min_degree: usize) -> BSplineSurface {
        let (p, q) = (self.int(min_degree, 3), self.int(min_degree, 3));
        let (su, sv) = (self.int(1, 3), self.int(1, 3));
        let uk = self.knots(p, su);
        let vk = self.knots(q, sv);
        let (nu, nv) = (uk.len() - p - 1, vk.len() - q - 1);
        // A gently curved sheet so normals exist everywhere.
        let base = self.frame();
        let net: Vec<Vec<Vec3>> = (0..nu)
            .map(|i| {
                (0..nv)
                    .map(|j| {
                        base.to_world(Vec3::new(
                            2.0 * i as f64 + self.range(-0.5, 0.5),
                            2.0 * j as f64 + self.range(-0.5, 0.5),
                            self.range(-1.5, 1.5),
                        ))
                    })
                    .collect()
            })
            .collect();
        let w = if self.unit() < 0.5 {
            None
        } else {
            Some(
                (0..nu)
                    .map(|_| (0..nv).map(|_| self.range(0.5, 2.0)).collect())
                    .collect(),
            )
        };
        BSplineSurface::try_new(p, q, uk, vk, net, w).unwrap()
    }
}

pub const CURVE_KINDS: usize = 11;

/// One curve of each kind (`kind < CURVE_KINDS`) with random shape.
pub fn curve3(kind: usize, s: &mut Src) -> Curve3 {
    match kind {
        0 => Curve::Line {
            origin: s.vec3(10.0),
            direction: s.vec3(3.0),
        },
        1 => Curve::Circle {
            frame: s.frame().into(),
            radius: s.range(0.1, 10.0),
        },
        2 => Curve::Ellipse {
            frame: s.frame().into(),
            a: s.range(0.1, 10.0),
            b: s.range(0.1, 10.0),
        },
        3 => Curve::Parabola {
            frame: s.frame().into(),
            focal: s.range(0.1, 5.0),
        },
        4 => Curve::Hyperbola {
            frame: s.frame().into(),
            a: s.range(0.1, 5.0),
            b: s.range(0.1, 5.0),
        },
        5 => Curve::Polyline((0..s.int(2, 6)).map(|_| s.vec3(5.0)).collect()),
        6 => Curve::BSpline(s.bspline3()),
        7 => {
            let t0 = s.range(-PI, PI);
            Curve::Trimmed {
                basis: Box::new(curve3(2, s)),
                t0,
                t1: s.range(-PI, PI),
                sense: s.unit() < 0.5,
            }
        }
        8 => Curve::Composite(vec![
            CompositeSegment {
                curve: curve3(7, s),
                same_sense: s.unit() < 0.5,
            },
            CompositeSegment {
                curve: curve3(6, s),
                same_sense: s.unit() < 0.5,
            },
        ]),
        9 => {
            // STEP's ref_direction for a planar basis is (close to) the plane's normal;
            // a skew one makes N swing wildly where B' nearly aligns with it.
            let f = s.frame();
            Curve::Offset {
                basis: Box::new(Curve::Circle {
                    frame: f.into(),
                    radius: s.range(0.1, 10.0),
                }),
                distance: s.range(-0.5, 2.0),
                ref_direction: (f.z + s.vec3(0.3)).normalize(),
            }
        }
        _ => Curve::Offset {
            basis: Box::new(Curve::BSpline(s.tame_bspline3())),
            distance: s.range(-0.3, 0.3),
            ref_direction: s.unit_vec3(),
        },
    }
}

/// 2D counterpart of [`curve3`] for the kinds that make sense in 2D.
pub fn curve2(kind: usize, s: &mut Src) -> Curve2 {
    match kind {
        0 => Curve::Line {
            origin: s.vec2(10.0),
            direction: s.vec2(3.0),
        },
        1 => Curve::Circle {
            frame: s.frame2(),
            radius: s.range(0.1, 10.0),
        },
        2 => Curve::Ellipse {
            frame: s.frame2(),
            a: s.range(0.1, 10.0),
            b: s.range(0.1, 10.0),
        },
        3 => Curve::Parabola {
            frame: s.frame2(),
            focal: s.range(0.1, 5.0),
        },
        4 => Curve::Hyperbola {
            frame: s.frame2(),
            a: s.range(0.1, 5.0),
            b: s.range(0.1, 5.0),
        },
        5 => Curve::Polyline((0..s.int(2, 6)).map(|_| s.vec2(5.0)).collect()),
        6 => Curve::BSpline(s.bspline2()),
        7 => {
            let t0 = s.range(-PI, PI);
            Curve::Trimmed {
                basis: Box::new(curve2(1, s)),
                t0,
                t1: s.range(-PI, PI),
                sense: s.unit() < 0.5,
            }
        }
        8 => Curve::Composite(vec![
            CompositeSegment {
                curve: curve2(7, s),
                same_sense: s.unit() < 0.5,
            },
            CompositeSegment {
                curve: curve2(6, s),
                same_sense: s.unit() < 0.5,
            },
        ]),
        9 => Curve::Offset {
            basis: Box::new(curve2(2, s)),
            distance: s.range(-0.05, 0.05),
            ref_direction: Vec3::Z,
        },
        _ => Curve::Offset {
            basis: Box::new(Curve::BSpline(s.tame_bspline2())),
            distance: s.range(-0.3, 0.3),
            ref_direction: Vec3::Z,
        },
    }
}

pub const SURFACE_KINDS: usize = 11;

/// One surface of each kind (`kind < SURFACE_KINDS`) with random shape.
pub fn surface(kind: usize, s: &mut Src) -> Surface {
    match kind {
        0 => Surface::Plane { frame: s.frame() },
        1 => Surface::Cylinder {
            frame: s.frame(),
            radius: s.range(0.1, 10.0),
        },
        2 => Surface::Cone {
            frame: s.frame(),
            radius: s.range(0.0, 10.0),
            semi_angle: s.range(0.05, 1.5),
        },
        3 => Surface::Sphere {
            frame: s.frame(),
            radius: s.range(0.1, 10.0),
        },
        4 => {
            let major = s.range(0.5, 10.0);
            Surface::Torus {
                frame: s.frame(),
                major_radius: major,
                minor_radius: s.range(0.05, 0.95) * major,
            }
        }
        5 => Surface::BSpline(Box::new(s.bspline_surface())),
        6 => {
            // A profile away from the axis so the revolution is regular.
            let f = s.frame();
            let mut c = s.bspline3();
            for p in &mut c.control_points {
                *p = f.to_world(Vec3::new(p.x.abs() + 2.0, 0.0, p.z));
            }
            Surface::Revolution {
                profile: Box::new(Curve::BSpline(c)),
                axis_origin: f.origin,
                axis_direction: f.z,
            }
        }
        7 => Surface::Extrusion {
            profile: Box::new(if s.unit() < 0.5 {
                Curve::BSpline(s.bspline3())
            } else {
                curve3(2, s)
            }),
            direction: s.vec3(3.0),
        },
        8 => Surface::Offset {
            basis: Box::new(surface(3, s)),
            distance: s.range(-0.05, 2.0),
        },
        9 => Surface::Offset {
            // Degree ≥ 2: the offset of a surface with kinks has gaps at the kinks.
            basis: Box::new(Surface::BSpline(Box::new(s.bspline_surface_of_degree(2)))),
            distance: s.range(-0.1, 0.1),
        },
        _ => {
            let basis = surface(4, s);
            Surface::Trimmed {
                basis: Box::new(basis),
                u0: s.range(0.0, 3.0),
                u1: s.range(3.0, 6.0),
                v0: s.range(-1.0, 1.0),
                v1: s.range(1.0, 3.0),
            }
        }
    }
}

/// A finite parameter interval to exercise: the domain, or a window for unbounded curves.
pub fn curve_range<P>(c: &Curve<P>) -> (f64, f64)
where
    P: cadre_geom::GeomPoint,
{
    match c.domain() {
        Some((a, b)) => (a, b),
        None => (-2.0, 2.0),
    }
}

/// A finite parameter rectangle to exercise.
pub fn surface_range(s: &Surface) -> ((f64, f64), (f64, f64)) {
    let ((u0, u1), (v0, v1)) = s.domain();
    let fix = |a: f64, b: f64| {
        if a.is_finite() && b.is_finite() {
            (a, b)
        } else {
            (-3.0, 3.0)
        }
    };
    (fix(u0, u1), fix(v0, v1))
}
