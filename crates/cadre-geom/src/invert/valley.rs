//! Point inversion along the valley of a strongly anisotropic parametrisation.
//!
//! Where one partial derivative of a surface is thousands of times the other, the squared
//! distance to a point is a long, narrow, curved valley in `(u, v)`: a Newton step in both
//! parameters leaves the valley floor as soon as the floor bends, the line search cuts it
//! to a sliver, and 32 iterations creep a fraction of the way (trj6_b1-ec-214.stp's face
//! #6387, a B-spline wall changing 35,000 mm per unit v and 0.7 mm per unit u: edge points
//! were left 0.3 mm from a foot 2e-5 mm away). Solving the stiff parameter exactly for each
//! value of the soft one and running Newton on the soft one alone (with the reduced Hessian,
//! the Schur complement) follows the floor instead.

use super::newton::Bounds;
use crate::{Surface, SurfaceDerivs, Vec3};

/// Derivatives of a surface with the parameters named by their role: `t` soft, `w` stiff.
struct Roles {
    point: Vec3,
    dt: Vec3,
    dw: Vec3,
    dtt: Vec3,
    dtw: Vec3,
    dww: Vec3,
}

impl Roles {
    fn new(d: SurfaceDerivs, stiff_v: bool) -> Self {
        if stiff_v {
            Roles {
                point: d.point,
                dt: d.du,
                dw: d.dv,
                dtt: d.duu,
                dtw: d.duv,
                dww: d.dvv,
            }
        } else {
            Roles {
                point: d.point,
                dt: d.dv,
                dw: d.du,
                dtt: d.dvv,
                dtw: d.duv,
                dww: d.duu,
            }
        }
    }
}

/// Minimises `|S(u, v) − p|` from `(u, v)` by Newton on the soft parameter with the stiff
/// one solved exactly at each step. Returns `(u, v, distance)`, or `None` where the surface
/// does not evaluate finitely or the iteration makes no progress.
pub(crate) fn valley_newton(
    s: &Surface,
    p: Vec3,
    (u, v): (f64, f64),
    (bu, bv): (Bounds, Bounds),
    max_iterations: u32,
    tolerance: f64,
) -> Option<(f64, f64, f64)> {
    let d0 = s.derivs(u, v);
    let stiff_v = d0.dv.length_squared() >= d0.du.length_squared();
    let (bt, bw) = if stiff_v { (bu, bv) } else { (bv, bu) };
    let at = |t: f64, w: f64| {
        let d = if stiff_v {
            s.derivs(t, w)
        } else {
            s.derivs(w, t)
        };
        Roles::new(d, stiff_v)
    };
    // The stiff parameter's foot for a given soft one: 1D Newton (Gauss–Newton where the
    // exact second derivative is not positive), with a backtracking line search.
    let floor = |t: f64, mut w: f64| -> Option<(f64, Roles, f64)> {
        w = bw.clamp(w);
        let mut d = at(t, w);
        let mut dist = (d.point - p).length();
        for _ in 0..max_iterations {
            let r = d.point - p;
            let gn = d.dw.dot(d.dw);
            let h = gn + r.dot(d.dww);
            let h = if h > 1e-12 * gn { h } else { gn };
            if h.is_nan() || h <= 0.0 {
                break;
            }
            let mut step = -r.dot(d.dw) / h;
            let mut moved = None;
            for _ in 0..30 {
                let nw = bw.clamp(w + step);
                let nd = at(t, nw);
                let ndist = (nd.point - p).length();
                if ndist.is_finite() && ndist <= dist {
                    moved = Some((nd.point - d.point).length());
                    (w, d, dist) = (nw, nd, ndist);
                    break;
                }
                step *= 0.5;
            }
            match moved {
                Some(m) if m > 0.1 * tolerance => {}
                _ => break,
            }
        }
        dist.is_finite().then_some((w, d, dist))
    };
    let (mut t, w) = if stiff_v { (u, v) } else { (v, u) };
    t = bt.clamp(t);
    let (mut w, mut d, mut dist) = floor(t, w)?;
    for _ in 0..max_iterations {
        let r = d.point - p;
        let (a, b, c) = (d.dt.dot(d.dt), d.dt.dot(d.dw), d.dw.dot(d.dw));
        let (ha, hb, hc) = (a + r.dot(d.dtt), b + r.dot(d.dtw), c + r.dot(d.dww));
        // Reduced (Schur complement) Hessian of the distance along the floor; the
        // Gauss–Newton one where the exact one is not positive.
        let reduced = |a: f64, b: f64, c: f64| (c > 0.0).then(|| a - b * b / c);
        let (h, slope) = match reduced(ha, hb, hc).filter(|h| *h > 1e-12 * a) {
            Some(h) => (h, -hb / hc),
            None => match reduced(a, b, c).filter(|h| *h > 0.0) {
                Some(h) => (h, -b / c),
                None => break,
            },
        };
        let mut step = -r.dot(d.dt) / h;
        let full = (d.dt + d.dw * slope).length() * step.abs();
        let mut accepted = false;
        for _ in 0..30 {
            let nt = bt.clamp(t + step);
            if let Some((nw, nd, ndist)) = floor(nt, w + slope * (nt - t))
                && ndist <= dist
            {
                accepted = (nd.point - d.point).length() > 0.0;
                (t, w, d, dist) = (nt, nw, nd, ndist);
                break;
            }
            step *= 0.5;
        }
        if !accepted || full <= 0.1 * tolerance {
            break;
        }
    }
    let (u, v) = if stiff_v { (t, w) } else { (w, t) };
    Some((u, v, dist))
}

#[cfg(test)]
mod tests {
    use super::super::newton::{Bounds, newton_2d, surface_newton};
    use crate::{Accuracy, BSplineSurface, Surface, Vec3};

    /// trj6_b1-ec-214.stp #6402: a degree 8 × 8 Bézier wall, 35,000 mm per unit v.
    const WALL: [[[f64; 3]; 9]; 9] = [
        [
            [7.827078391972, -128.0964826121, -15385.33989777],
            [7.834599426274, -128.0917017647, -13403.0550302],
            [7.840185325892, -128.0854079441, -11505.32092138],
            [7.843835842361, -128.077617644, -9692.434986786],
            [7.8455470346, -128.0682912069, -7962.827885368],
            [7.845315096375, -128.0574935429, -6318.08069053],
            [7.843188725066, -128.0451219847, -4753.113520297],
            [7.839115603328, -128.0312601096, -3273.608753],
            [7.833106899599, -128.0158864942, -1878.317552154],
        ],
        [
            [8.204585401717, -128.038154433, -7942.60120004],
            [8.212106394206, -128.0333735207, -5960.262335323],
            [8.217691822434, -128.0270773127, -4062.560769918],
            [8.221344700896, -128.0192974285, -2250.069844048],
            [8.223050585335, -128.0099580088, -520.4827533147],
            [8.222813253215, -127.9991795216, 1123.334074908],
            [8.220689485087, -127.9868005183, 2688.73886722],
            [8.216618130788, -127.9729376541, 4168.385390455],
            [8.210609624194, -127.9575639459, 5563.712189658],
        ],
        [
            [8.532919390389, -127.9412333539, -2628.474529839],
            [8.540441426774, -127.9364520902, -646.0524338778],
            [8.546014395005, -127.9301610836, 1251.621223074],
            [8.549704109829, -127.9223726712, 3066.218758186],
            [8.551345507438, -127.9130566101, 4790.699048278],
            [8.551167580454, -127.9022504621, 6439.425716245],
            [8.549009210041, -127.8898977324, 8001.391585345],
            [8.544942552198, -127.8760269592, 9481.87759921],
            [8.538937258793, -127.8606508278, 10877.43365028],
        ],
        [
            [8.812071595595, -127.8057352728, 559.38906207593],
            [8.819582796693, -127.8009484494, 2542.116852137],
            [8.825203350199, -127.7946544403, 4439.028525822],
            [8.828793859253, -127.7868287486, 6247.773065621],
            [8.830578149257, -127.7776047721, 7982.30099345],
            [8.830291199126, -127.7667055187, 9622.471987198],
            [8.828178132043, -127.7543812082, 11189.08314932],
            [8.824093553545, -127.7405278797, 12666.52464735],
            [8.818087435755, -127.725150831, 14062.33131029],
        ],
        [
            [9.042049428383, -127.6316367755, 1611.874368996],
            [9.049584485474, -127.6268771849, 3595.226215802],
            [9.055137176676, -127.6205453056, 5495.890349112],
            [9.058839235592, -127.6127869152, 7312.136587611],
            [9.060470761772, -127.6034336524, 9033.335412334],
            [9.060320078036, -127.5926457594, 10684.63260569],
            [9.058149357348, -127.5802935077, 12243.58258941],
            [9.0540785408, -127.5664234899, 13725.34585009],
            [9.04807079474, -127.5510503418, 15120.39697111],
        ],
        [
            [9.222884548652, -127.418917693, 545.80157319726],
            [9.230383666084, -127.4141346761, 2528.342278914],
            [9.235963108685, -127.4079036237, 4425.736644428],
            [9.239577475986, -127.4000885332, 6235.508342066],
            [9.241344990444, -127.3907745532, 7967.207878822],
            [9.241092168036, -127.3799491898, 9610.134153011],
            [9.238958595186, -127.3675945432, 11175.4852306],
            [9.234884283768, -127.3537389792, 12653.12073747],
            [9.228878349675, -127.3383630783, 14048.94771499],
        ],
        [
            [9.354501615367, -127.1676550346, -2655.305825543],
            [9.362014247611, -127.1628919835, -672.6653887189],
            [9.367591123203, -127.1566000048, 1225.129404684],
            [9.371223960755, -127.1488139517, 3038.357515633],
            [9.372959667196, -127.1394962804, 4765.129506572],
            [9.37274142789, -127.1286587263, 6412.012793975],
            [9.370599994963, -127.1163164625, 7974.721806107],
            [9.366519908042, -127.1024558308, 9455.120541138],
            [9.36051193879, -127.0870816398, 10850.66862248],
        ],
        [
            [9.436967955536, -126.8777769292, -7982.862575736],
            [9.444476603361, -126.8730105439, -6000.460409899],
            [9.450049559125, -126.8667318207, -4102.621183133],
            [9.453700006809, -126.8589379171, -2290.529749462],
            [9.455405479008, -126.8496248144, -560.3151337321],
            [9.455215641901, -126.8387816306, 1083.051618596],
            [9.453058162962, -126.8264435622, 2648.623077199],
            [9.448979551891, -126.8125832149, 4128.220771799],
            [9.442974126656, -126.7972082673, 5523.567685179],
        ],
        [
            [9.470257981856, -126.5493098758, -15439.01609331],
            [9.477766393986, -126.5445439151, -13456.66705309],
            [9.483340808267, -126.538264783, -11558.84223728],
            [9.486989232904, -126.5304698817, -9746.124219579],
            [9.488699274816, -126.5211566277, -8016.211888662],
            [9.48850282133, -126.5103169662, -6371.673358383],
            [9.486346885499, -126.4979773613, -4806.624208075],
            [9.482269972711, -126.4841170789, -3327.14231455],
            [9.476264664546, -126.4687423498, -1931.824451342],
        ],
    ];
    const U: (f64, f64) = (-1.127555120455, 1.12958367813);
    const V: (f64, f64) = (-0.158305108175, 0.288436173589);

    fn wall() -> Surface {
        let knots = |(a, b): (f64, f64)| {
            let mut k = vec![a; 9];
            k.extend([b; 9]);
            k
        };
        let net = WALL
            .iter()
            .map(|row| row.iter().map(|&[x, y, z]| Vec3::new(x, y, z)).collect())
            .collect();
        Surface::BSpline(Box::new(
            BSplineSurface::try_new(8, 8, knots(U), knots(V), net, None).unwrap(),
        ))
    }

    /// An edge point 2e-5 mm from the wall, started from the previous edge point's foot
    /// (how edges are projected): Newton in both parameters creeps (the negative control),
    /// the valley walk reaches the foot.
    #[test]
    fn foot_on_anisotropic_wall() {
        let s = wall();
        let p = Vec3::new(8.994014459930838, -127.59244210895089, -4.980541608637143);
        let start = (-0.33, -0.107);
        let bounds = (Bounds::new(U.0, U.1), Bounds::new(V.0, V.1));
        let acc = Accuracy::default();
        let (_, _, plain, exhausted) = newton_2d(&s, p, start, bounds, acc).unwrap();
        assert!(exhausted && plain > 0.1, "plain Newton reached {plain}");
        let (u, v, d) = surface_newton(&s, p, start, bounds, acc).unwrap();
        assert!(d < 1e-4, "{d}");
        assert!((s.eval(u, v) - p).length() < 1e-4);
        let (u, v) = s.project(p, Some(start), acc).unwrap();
        assert!((s.eval(u, v) - p).length() < 1e-4);
    }
}
