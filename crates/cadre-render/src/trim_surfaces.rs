//! The faces drawn from their exact definition (seed 000, Part III): each face's support
//! surface, evaluated on the GPU over its trim tree's (u, v) box at a tessellation chosen per
//! frame from a screen-space error, and its trim tree (`cadre_trim`), tested per fragment.
//! [`TrimScene::build`] decides which faces the trim back-end draws
//! (`passes/visibility/trim`); every other face keeps its mesh, and says why.

use cadre_brep::{FaceId, Model};
use cadre_geom::Surface;
use cadre_trim::{ModelTrees, model_trees};
use glam::DVec3;

/// [`TrimFaceSurface::kind`]: `o + u x + v y`.
pub const SURFACE_PLANE: u32 = 0;
/// [`TrimFaceSurface::kind`]: `o + r (cos u x + sin u y) + v z`.
pub const SURFACE_CYLINDER: u32 = 1;
/// [`TrimFaceSurface::kind`]: `o + (r + v tan α)(cos u x + sin u y) + v z`.
pub const SURFACE_CONE: u32 = 2;
/// [`TrimFaceSurface::kind`]: `o + r cos v (cos u x + sin u y) + r sin v z`.
pub const SURFACE_SPHERE: u32 = 3;
/// [`TrimFaceSurface::kind`]: `o + (R + r cos v)(cos u x + sin u y) + r sin v z`.
pub const SURFACE_TORUS: u32 = 4;
/// [`TrimFaceSurface::kind`]: a (rational) B-spline, evaluated from its packed knots and
/// homogeneous control points ([`TrimScene::bspline_data`] at [`TrimFaceSurface::data`]).
pub const SURFACE_BSPLINE: u32 = 5;
/// [`TrimFaceSurface::kind`]: `C(u) + v d`, a surface of linear extrusion: its profile `C`
/// packed at [`TrimFaceSurface::data`] (`trim_sweeps`), `d` the frame's z (not unit).
pub const SURFACE_EXTRUSION: u32 = 6;
/// [`TrimFaceSurface::kind`]: `c + R_a(u) (C(v) − c)`, a surface of revolution: its profile
/// `C` packed at [`TrimFaceSurface::data`] (`trim_sweeps`), `c` the frame's origin and the
/// unit axis `a` its z.
pub const SURFACE_REVOLUTION: u32 = 7;

/// The highest B-spline degree the trim back-end draws (its WGSL's basis tables hold 16
/// functions); higher-degree faces keep their meshes.
pub const MAX_BSPLINE_DEGREE: usize = 15;

/// One face the trim back-end draws: its surface in closed form and where its trim tree is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimFaceSurface {
    /// One of the `SURFACE_*` kinds.
    pub kind: u32,
    /// The surface's frame: origin, x, y, z (model units, the mesh's coordinates).
    pub frame: [DVec3; 4],
    /// The kind's two numbers: radius and 0 (cylinder, sphere), radius and tan α (cone),
    /// major and minor radius (torus), 0 and 0 (plane).
    pub params: [f64; 2],
    /// Its tree's index in [`TrimScene::trees`]' buffers.
    pub tree: u32,
    /// The tree's (u, v) box: lower corner and size (the tessellated domain).
    pub uv_origin: [f64; 2],
    /// The box's size.
    pub uv_size: [f64; 2],
    /// Bounds of the surface's second derivatives over the box: |S_uu|, |S_uv|, |S_vv| (model
    /// units per parameter unit²), from which a tessellation's chord error follows.
    pub curvature: [f64; 3],
    /// A B-spline's packed record, or a sweep's packed profile, in
    /// [`TrimScene::bspline_data`] (0 for the closed forms).
    pub data: u32,
    /// Where the face's grid lines must fall ([`NO_BREAKS`] for one span each way): its
    /// record in [`TrimScene::bspline_data`], the number of spans along u and v (as `u32`
    /// bits), then the u and v breakpoints from the box's lower corner (both ends included).
    /// A B-spline's are its knots within the box: across them it may bend sharply (a
    /// degree-1 surface folds there), so every knot line is a grid line.
    pub breaks: u32,
}

/// [`TrimFaceSurface::breaks`] of a face tessellated as one span each way.
pub const NO_BREAKS: u32 = u32::MAX;

/// Spans a face's grid holds per direction at most (`TRIM_MAX_LEVEL` in surface.wgsl): past
/// it, knot lines are dropped evenly.
pub const MAX_SPANS: usize = 256;

/// Which faces of a model the trim back-end draws, and the trees it reads.
#[derive(Clone, Debug, Default)]
pub struct TrimScene {
    /// The trim trees of the model's faces, packed.
    pub trees: ModelTrees,
    /// Per model face, what the trim back-end draws of it (`None`: its mesh draws it).
    pub faces: Vec<Option<TrimFaceSurface>>,
    /// The faces left to their meshes: STEP id and why.
    pub fallback: Vec<(u64, String)>,
    /// The object-space tolerance the trims were fitted within (model units).
    pub tolerance: f64,
    /// The least bound the tessellation needs keep in depth (model units, [`DEPTH_REL`] of
    /// the model's diagonal): each face's record carries it.
    pub depth_tolerance: f64,
    /// The B-spline faces drawn as the planes, cylinders or spheres they are
    /// ([`crate::trim_quadrics`]): their trees and records are the closed forms'.
    pub closed_form_faces: Vec<FaceId>,
    /// The B-spline faces' surfaces, packed as the GPU reads them: per surface its degrees
    /// and control-net size (as `u32` bits), its u and v knots, then its control points
    /// row by row (along u), relative to the face's frame origin, as homogeneous
    /// (x w, y w, z w, w), all `f32`.
    pub bspline_data: Vec<f32>,
}

impl TrimScene {
    /// The trees of `model`'s faces within `tolerance` model units of the exact trims, and
    /// the faces the trim back-end can draw: planes, cylinders, cones, spheres, tori,
    /// B-splines up to [`MAX_BSPLINE_DEGREE`] and sweeps of B-spline, line and conic profiles
    /// (a rectangular trim of one counts as it); faces on other surfaces or without a tree
    /// keep their meshes.
    pub fn build(model: &Model, tolerance: f64) -> TrimScene {
        let (closed_form_faces, replaced) =
            crate::trim_quadrics::closed_form_faces(model, tolerance);
        let model = replaced.as_ref().unwrap_or(model);
        let trees = model_trees(model, tolerance);
        let mut fallback: Vec<(u64, String)> = trees.failures.clone();
        let mut bspline_data = Vec::new();
        let faces = (0..model.faces.len())
            .map(|i| {
                let tree = trees.face_index[i]?;
                let face = &model.faces[i];
                let surface = &model.surfaces[face.surface.index()];
                let record = &trees.buffers.faces[tree as usize];
                let origin = [record.origin.x, record.origin.y];
                let size = [f64::from(record.size[0]), f64::from(record.size[1])];
                let mut breaks = NO_BREAKS;
                let exact = match basis(surface) {
                    Surface::BSpline(b) => packed_bspline(b, origin, size, &mut bspline_data)
                        .inspect(|_| {
                            breaks = pack_breaks(
                                (&b.u_knots, &b.v_knots),
                                origin,
                                size,
                                &mut bspline_data,
                            );
                        }),
                    sweep @ (Surface::Extrusion { .. } | Surface::Revolution { .. }) => {
                        match crate::trim_sweeps::sweep_surface(
                            sweep,
                            tree,
                            (origin, size),
                            &mut bspline_data,
                        ) {
                            Ok(record) => return Some(record),
                            Err(why) => {
                                fallback.push((face.step_id, why));
                                return None;
                            }
                        }
                    }
                    other => closed_form(other, origin, size).ok_or_else(|| {
                        format!(
                            "{} surface: no GPU evaluator yet",
                            surface_name(model, FaceId(i as u32))
                        )
                    }),
                };
                match exact {
                    Ok((kind, frame, params, curvature, data)) => Some(TrimFaceSurface {
                        kind,
                        frame,
                        params,
                        tree,
                        uv_origin: origin,
                        uv_size: size,
                        curvature,
                        data,
                        breaks,
                    }),
                    Err(why) => {
                        fallback.push((face.step_id, why));
                        None
                    }
                }
            })
            .collect();
        fallback.sort_by_key(|(id, _)| *id);
        TrimScene {
            trees,
            faces,
            fallback,
            tolerance,
            depth_tolerance: DEPTH_REL * cadre_mesh::deflection_diagonal(model),
            closed_form_faces,
            bspline_data,
        }
    }

    /// How many faces the trim back-end draws.
    pub fn drawn(&self) -> usize {
        self.faces.iter().flatten().count()
    }
}

/// A surface without its rectangular trims (their (u, v) are the basis').
fn basis(surface: &Surface) -> &Surface {
    match surface {
        Surface::Trimmed { basis, .. } => self::basis(basis),
        other => other,
    }
}

/// What [`TrimScene::build`] makes of one face's surface: kind, frame, numbers, curvature
/// bounds and packed data offset.
type Exact = (u32, [DVec3; 4], [f64; 2], [f64; 3], u32);

/// The WGSL of the trim back-end's surface evaluators (`surface.wgsl` and `bspline.wgsl`):
/// `face_point` of a `TrimSurface`, `bspline_point` of a packed B-spline, reading the
/// includer's `trim_bspline: array<f32>` (for the tests that run them in compute).
pub fn surface_wgsl() -> String {
    [
        include_str!("passes/visibility/trim/surface.wgsl"),
        include_str!("passes/visibility/trim/bspline.wgsl"),
        include_str!("passes/visibility/trim/sweep.wgsl"),
    ]
    .join("\n")
}

/// Packs `b` at the end of `data` as [`TrimScene::bspline_data`] holds it, its control
/// points relative to `anchor` (the face record's origin, which the evaluators add back);
/// returns its offset, or why the GPU cannot evaluate it.
pub fn pack_bspline(
    b: &cadre_geom::bspline::BSplineSurface,
    anchor: DVec3,
    data: &mut Vec<f32>,
) -> Result<u32, String> {
    let (p, q) = (b.u_degree, b.v_degree);
    if p > MAX_BSPLINE_DEGREE || q > MAX_BSPLINE_DEGREE {
        return Err(format!(
            "B-spline surface of degree ({p}, {q}): the GPU evaluates degrees up to {MAX_BSPLINE_DEGREE}"
        ));
    }
    if !b.is_well_formed() {
        return Err("B-spline surface not well formed".to_string());
    }
    let (nu, nv) = (b.control_points.len(), b.control_points[0].len());
    let at = data.len();
    if at + 4 + b.u_knots.len() + b.v_knots.len() + 4 * nu * nv >= u32::MAX as usize {
        return Err("B-spline data past 2³² floats".to_string());
    }
    data.extend([p, q, nu, nv].map(|n| f32::from_bits(n as u32)));
    data.extend(b.u_knots.iter().map(|&k| k as f32));
    data.extend(b.v_knots.iter().map(|&k| k as f32));
    for (i, row) in b.control_points.iter().enumerate() {
        for (j, c) in row.iter().enumerate() {
            let w = b.weights.as_ref().map_or(1.0, |w| w[i][j]);
            let c = *c - anchor;
            data.extend([c.x * w, c.y * w, c.z * w, w].map(|x| x as f32));
        }
    }
    Ok(at as u32)
}

/// The knot lines `u_knots`, `v_knots` within the box `origin + [0, size]` packed at the end of `data` as
/// [`TrimFaceSurface::breaks`] reads them; returns their offset.
pub(crate) fn pack_breaks(
    (u_knots, v_knots): (&[f64], &[f64]),
    origin: [f64; 2],
    size: [f64; 2],
    data: &mut Vec<f32>,
) -> u32 {
    let breaks = |knots: &[f64], lo: f64, size: f64| -> Vec<f64> {
        // Knots closer than a millionth of the box to a kept one add nothing.
        let gap = 1e-6 * size;
        let mut out = vec![0.0];
        for &k in knots {
            let t = k - lo;
            if t > gap && t < size - gap && t - out[out.len() - 1] > gap {
                out.push(t);
            }
        }
        out.push(size);
        if out.len() > MAX_SPANS + 1 {
            let n = out.len() - 1;
            out = (0..=MAX_SPANS).map(|i| out[i * n / MAX_SPANS]).collect();
        }
        out
    };
    let u = breaks(u_knots, origin[0], size[0]);
    let v = breaks(v_knots, origin[1], size[1]);
    let at = data.len() as u32;
    data.extend([u.len() - 1, v.len() - 1].map(|n| f32::from_bits(n as u32)));
    data.extend(u.iter().chain(&v).map(|&t| t as f32));
    at
}

/// The centre of the bounding box of `points` (zero for none): the anchor a face's packed
/// control points are stored relative to. `f32` holds a point 1,661 mm from the origin to
/// 0.12 µm, three pixels of a 0.5 mm face magnified 100× (corpus bug29478); relative to
/// the face's own centre, to a ten-millionth of the face.
pub(crate) fn net_centre(points: impl Iterator<Item = DVec3>) -> DVec3 {
    let (lo, hi) = points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    if lo.is_finite() && hi.is_finite() {
        0.5 * (lo + hi)
    } else {
        DVec3::ZERO
    }
}

/// A B-spline surface packed at the end of `data` (see [`TrimScene::bspline_data`]), with
/// bounds of its second derivatives over the box `origin + [0, size]`.
fn packed_bspline(
    b: &cadre_geom::bspline::BSplineSurface,
    origin: [f64; 2],
    size: [f64; 2],
    data: &mut Vec<f32>,
) -> Result<Exact, String> {
    let anchor = net_centre(b.control_points.iter().flatten().copied());
    let at = pack_bspline(b, anchor, data)?;
    let curvature = bspline_curvature(b, origin, size);
    Ok((
        SURFACE_BSPLINE,
        [anchor, DVec3::X, DVec3::Y, DVec3::Z],
        [0.0; 2],
        curvature,
        at,
    ))
}

/// Bounds of |S_uu|, |S_uv|, |S_vv| of a B-spline. Polynomial: the largest control point of
/// each second derivative (a B-spline lies in its control points' hull), exact, but for the
/// derivative control points of knot spans narrower than a millionth of the domain: files
/// hold such slivers (spans 4·10⁻⁸ wide, corpus trj4_pm2), whose derivatives are huge and
/// whose whole extent is far below any pixel. Rational: the largest of the derivatives
/// sampled over the box clamped to the domain (8 samples per knot span and direction,
/// slivers skipped, at most 65), doubled, since the hull bound does not hold through the
/// weights.
fn bspline_curvature(
    b: &cadre_geom::bspline::BSplineSurface,
    origin: [f64; 2],
    size: [f64; 2],
) -> [f64; 3] {
    if b.weights.is_none() {
        return polynomial_curvature(b);
    }
    // Parameters sampled along one direction: 8 per knot span within the box, sliver spans
    // (see above) skipped, the box's ends clamped to the domain.
    let samples = |knots: &[f64], n: usize, p: usize, lo: f64, size: f64| -> Vec<f64> {
        let (first, last) = (knots[p], knots[n]);
        let sliver = 1e-6 * (last - first);
        let (lo, hi) = (lo.max(first), (lo + size).min(last));
        let mut out = Vec::new();
        for w in knots[p..=n].windows(2) {
            let (a, b) = (w[0].max(lo), w[1].min(hi));
            if b - a > sliver {
                out.extend((0..=8).map(|k| a + (b - a) * f64::from(k) / 8.0));
            }
        }
        if out.is_empty() {
            out.push(0.5 * (lo + hi));
        }
        out
    };
    let (nu, nv) = (b.control_points.len(), b.control_points[0].len());
    let us = samples(&b.u_knots, nu, b.u_degree, origin[0], size[0]);
    let vs = samples(&b.v_knots, nv, b.v_degree, origin[1], size[1]);
    // At most 65 samples each way: every k-th.
    let thin = |v: Vec<f64>| -> Vec<f64> {
        let k = v.len().div_ceil(65).max(1);
        v.into_iter().step_by(k).collect()
    };
    let (us, vs) = (thin(us), thin(vs));
    let mut m = [0.0f64; 3];
    for &u in &us {
        for &v in &vs {
            let d = b.derivatives(u, v, 2);
            m[0] = m[0].max(d[2][0].length());
            m[1] = m[1].max(d[1][1].length());
            m[2] = m[2].max(d[0][2].length());
        }
    }
    m.map(|x| 2.0 * x)
}

/// [`bspline_curvature`] of a polynomial B-spline: the control points of its second
/// derivatives (*The NURBS Book* eq. 3.17, applied twice).
fn polynomial_curvature(b: &cadre_geom::bspline::BSplineSurface) -> [f64; 3] {
    let net = &b.control_points;
    // Spans narrower than this (a millionth of the larger domain) are slivers.
    let width = |k: &[f64]| k[k.len() - 1] - k[0];
    let sliver = 1e-6 * width(&b.u_knots).max(width(&b.v_knots));
    // The derivative of a row of control points along knots `k` of degree `p`.
    let derive = |points: &[DVec3], k: &[f64], p: usize| -> Vec<DVec3> {
        points
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let span = k[i + p + 1] - k[i + 1];
                if span > sliver {
                    (w[1] - w[0]) * (p as f64 / span)
                } else {
                    DVec3::ZERO
                }
            })
            .collect()
    };
    let (p, q) = (b.u_degree, b.v_degree);
    let columns: Vec<Vec<DVec3>> = (0..net[0].len())
        .map(|j| net.iter().map(|row| row[j]).collect())
        .collect();
    let max = |v: &[DVec3]| v.iter().map(|d| d.length()).fold(0.0, f64::max);
    let mut m = [0.0f64; 3];
    if p >= 2 {
        for col in &columns {
            let d1 = derive(col, &b.u_knots, p);
            m[0] = m[0].max(max(&derive(&d1, &b.u_knots[1..], p - 1)));
        }
    }
    if q >= 2 {
        for row in net {
            let d1 = derive(row, &b.v_knots, q);
            m[2] = m[2].max(max(&derive(&d1, &b.v_knots[1..], q - 1)));
        }
    }
    // Mixed: derive the columns in u, then the resulting rows in v.
    let du: Vec<Vec<DVec3>> = columns
        .iter()
        .map(|col| derive(col, &b.u_knots, p))
        .collect();
    for i in 0..du.first().map_or(0, Vec::len) {
        let row: Vec<DVec3> = du.iter().map(|col| col[i]).collect();
        m[1] = m[1].max(max(&derive(&row, &b.v_knots, q)));
    }
    m
}

/// The point of a packed B-spline at (u, v), relative to the anchor it was packed with, as
/// `bspline.wgsl` evaluates it (in `f64` from the same `f32` data): the CPU twin the tests
/// check the packing with.
pub fn packed_bspline_point(data: &[f32], at: u32, u: f64, v: f64) -> DVec3 {
    let at = at as usize;
    let [p, q, nu, nv] = [0, 1, 2, 3].map(|k| data[at + k].to_bits() as usize);
    let ku: Vec<f64> = data[at + 4..at + 4 + nu + p + 1]
        .iter()
        .map(|&k| f64::from(k))
        .collect();
    let kv_at = at + 4 + nu + p + 1;
    let kv: Vec<f64> = data[kv_at..kv_at + nv + q + 1]
        .iter()
        .map(|&k| f64::from(k))
        .collect();
    let cp = kv_at + nv + q + 1;
    let basis = |knots: &[f64], n: usize, p: usize, t: f64| -> (usize, Vec<f64>) {
        use cadre_geom::nurbs::basis::{BasisDers, basis_funs, find_span};
        let span = find_span(knots, n, p, t);
        // The stack-only basis stops at degree 8; files hold degree 11 (corpus
        // trj7_b1-ec-214), whose points were NaN here and whose faces were culled.
        let funs = match basis_funs(span, t, p, knots) {
            Some(f) => f[..=p].to_vec(),
            None => BasisDers::new(span, t, p, 0, knots).row(0).to_vec(),
        };
        (span, funs)
    };
    let (su, bu) = basis(&ku, nu, p, u);
    let (sv, bv) = basis(&kv, nv, q, v);
    let mut sum = glam::DVec4::ZERO;
    for (r, a) in bu.iter().enumerate() {
        for (t, b) in bv.iter().enumerate() {
            let k = cp + 4 * ((su - p + r) * nv + sv - q + t);
            let c = glam::DVec4::new(
                f64::from(data[k]),
                f64::from(data[k + 1]),
                f64::from(data[k + 2]),
                f64::from(data[k + 3]),
            );
            sum += c * (a * b);
        }
    }
    sum.truncate() / sum.w
}

/// The STEP type name of a face's surface.
fn surface_name(model: &Model, face: FaceId) -> &'static str {
    model.surfaces[model.faces[face.index()].surface.index()].type_name()
}

/// A surface's kind, frame, numbers and second-derivative bounds over the (u, v) box
/// `origin + [0, size]`, for the kinds the GPU evaluates in closed form. The linear
/// parameters (a plane's u and v, a cylinder's and cone's v) are measured from the box's
/// corner: the frame's origin is moved there, and a cone's radius is the one there (see
/// `surface.wgsl`'s `surface_point`).
fn closed_form(surface: &Surface, origin: [f64; 2], size: [f64; 2]) -> Option<Exact> {
    let [u0, v0] = origin;
    let axes = |f: &cadre_geom::Frame| [f.origin, f.x, f.y, f.z];
    let along_z = |f: &cadre_geom::Frame| [f.origin + f.z * v0, f.x, f.y, f.z];
    // The largest |cos v| over the box's v range (the sphere's parallels).
    let v_range = (origin[1], origin[1] + size[1]);
    Some(match surface {
        Surface::Trimmed { basis, .. } => return closed_form(basis, origin, size),
        Surface::Plane { frame } => (
            SURFACE_PLANE,
            [
                frame.origin + frame.x * u0 + frame.y * v0,
                frame.x,
                frame.y,
                frame.z,
            ],
            [0.0; 2],
            [0.0; 3],
            0,
        ),
        Surface::Cylinder { frame, radius } => (
            SURFACE_CYLINDER,
            along_z(frame),
            [*radius, 0.0],
            [radius.abs(), 0.0, 0.0],
            0,
        ),
        Surface::Cone {
            frame,
            radius,
            semi_angle,
        } => {
            let tan = semi_angle.tan();
            // |S_uu| is the radius at v, largest at one end of the v range.
            let rho = (radius + v_range.0 * tan)
                .abs()
                .max((radius + v_range.1 * tan).abs());
            (
                SURFACE_CONE,
                along_z(frame),
                [radius + v0 * tan, tan],
                [rho, tan.abs(), 0.0],
                0,
            )
        }
        Surface::Sphere { frame, radius } => {
            let r = radius.abs();
            (SURFACE_SPHERE, axes(frame), [*radius, 0.0], [r, r, r], 0)
        }
        Surface::Torus {
            frame,
            major_radius,
            minor_radius,
        } => {
            let (big, small) = (major_radius.abs(), minor_radius.abs());
            (
                SURFACE_TORUS,
                axes(frame),
                [*major_radius, *minor_radius],
                [big + small, small, small],
                0,
            )
        }
        _ => return None,
    })
}

/// The point of a closed-form surface at (u, v), as the GPU evaluates it (`surface.wgsl`'s
/// `surface_point`, its linear parameters from the box's corner): the CPU twin the tests
/// check the records against.
pub fn closed_form_point(s: &TrimFaceSurface, u: f64, v: f64) -> DVec3 {
    let [o, x, y, z] = s.frame;
    let radial = x * u.cos() + y * u.sin();
    let [a, b] = s.params;
    let (lu, lv) = (u - s.uv_origin[0], v - s.uv_origin[1]);
    match s.kind {
        SURFACE_PLANE => o + x * lu + y * lv,
        SURFACE_CYLINDER => o + radial * a + z * lv,
        SURFACE_CONE => o + radial * (a + lv * b) + z * lv,
        SURFACE_SPHERE => o + radial * (a * v.cos()) + z * (a * v.sin()),
        _ => o + radial * (a + b * v.cos()) + z * (b * v.sin()),
    }
}

/// The direction of S_u × S_v of a closed-form surface at (u, v), as `surface.wgsl`
/// evaluates it (the limit direction where it vanishes).
pub fn closed_form_normal(s: &TrimFaceSurface, u: f64, v: f64) -> DVec3 {
    let [_, x, y, z] = s.frame;
    let radial = x * u.cos() + y * u.sin();
    let [a, b] = s.params;
    let sign = |t: f64| if t < 0.0 { -1.0 } else { 1.0 };
    let meridian = radial * v.cos() + z * v.sin();
    match s.kind {
        SURFACE_PLANE => z,
        SURFACE_CYLINDER => radial * a,
        // The nappe of the box's middle: at the apex ρ is zero (either sign rounded).
        SURFACE_CONE => (radial - z * b) * sign(a + 0.5 * s.uv_size[1] * b),
        SURFACE_SPHERE => meridian * sign(a),
        _ => meridian * sign((a + b * v.cos()) * b),
    }
}

/// The point of a face's surface at (u, v) as the GPU evaluates it: its closed form, or its
/// packed B-spline in `data`.
pub fn face_point(s: &TrimFaceSurface, data: &[f32], u: f64, v: f64) -> DVec3 {
    match s.kind {
        SURFACE_BSPLINE => s.frame[0] + packed_bspline_point(data, s.data, u, v),
        SURFACE_EXTRUSION | SURFACE_REVOLUTION => crate::trim_sweeps::sweep_point(s, data, u, v).0,
        _ => closed_form_point(s, u, v),
    }
}

/// The direction of S_u × S_v of a face's surface at (u, v) (a B-spline's by central
/// differences a ten-thousandth of its box wide).
fn face_normal(s: &TrimFaceSurface, data: &[f32], u: f64, v: f64) -> DVec3 {
    if matches!(s.kind, SURFACE_EXTRUSION | SURFACE_REVOLUTION) {
        return crate::trim_sweeps::sweep_point(s, data, u, v).1;
    }
    if s.kind != SURFACE_BSPLINE {
        return closed_form_normal(s, u, v);
    }
    let (hu, hv) = (1e-4 * s.uv_size[0], 1e-4 * s.uv_size[1]);
    let p = |u, v| packed_bspline_point(data, s.data, u, v);
    let su = p(u + hu, v) - p(u - hu, v);
    let sv = p(u, v + hv) - p(u, v - hv);
    su.cross(sv)
}

/// Samples per side of the (u, v) box when bounding a face's surface.
const SPHERE_SAMPLES: usize = 9;

/// The tessellation's bound in depth relative to the model's diagonal: a face's grid is
/// refined to within `TOLERANCE_REL` of its radius (a thin wall's far side must not show
/// through its sagging near side) only down to this. A quarter of the static mesh's
/// deflection (10⁻³ of the diagonal), which lets walls as thin show through the same way;
/// below it the radius bound over-tessellated small faces tens of times over their
/// half-pixel bound (trj7_b1-ec-214 at 640 × 480: 480 k triangles against the mesh's 14 k).
pub const DEPTH_REL: f64 = 2.5e-4;

/// The GPU record of face id `face_id` drawn from `s`, its tessellation kept within `depth`
/// model units of the surface at least ([`TrimScene::depth_tolerance`]). `points` are its
/// mesh's vertices (position, normal, (u, v)), which say which side of the surface is the
/// face's outside (the mesh's normals follow the shell's orientation). Positions in the
/// record are relative to `mesh_origin`, the point the mesh's vertices are stored from
/// (`gpu_scene`), which its draw records add back in `f64`.
pub fn surface_record(
    s: &TrimFaceSurface,
    (data, depth): (&[f32], f64),
    face_id: u32,
    points: impl Iterator<Item = ([f32; 3], [f32; 3], [f32; 2])>,
    mesh_origin: DVec3,
) -> crate::layout::TrimSurface {
    let mut agreement = 0.0;
    for (position, normal, uv) in points {
        let (u, v) = (f64::from(uv[0]), f64::from(uv[1]));
        // A cylinder's or sphere's normal at the point's own angles: a B-spline face drawn
        // as the cylinder or sphere it is (`trim_quadrics`) has its mesh's (u, v) on the
        // B-spline. (A plane's normal is the same everywhere.)
        let (mut u, mut v) = (u, v);
        if s.kind == SURFACE_CYLINDER || s.kind == SURFACE_SPHERE {
            let [o, x, y, z] = s.frame;
            let d = DVec3::from(position.map(f64::from)) - o;
            u = d.dot(y).atan2(d.dot(x));
            if s.kind == SURFACE_SPHERE {
                v = (d.dot(z) / d.length().max(f64::MIN_POSITIVE))
                    .clamp(-1.0, 1.0)
                    .asin();
            }
        }
        let exact = face_normal(s, data, u, v);
        agreement += exact
            .normalize_or_zero()
            .dot(DVec3::from(normal.map(f64::from)));
    }
    let sign = if agreement < 0.0 { -1.0 } else { 1.0 };
    // The box's surface sampled on a grid, widened by the grid's chord error: a sphere that
    // holds every point of the box, so of the face (relative to the mesh's origin).
    let n = SPHERE_SAMPLES - 1;
    let samples: Vec<[f32; 3]> = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| {
            let u = s.uv_origin[0] + s.uv_size[0] * i as f64 / n as f64;
            let v = s.uv_origin[1] + s.uv_size[1] * j as f64 / n as f64;
            (face_point(s, data, u, v) - mesh_origin)
                .as_vec3()
                .to_array()
        })
        .collect();
    // A box whose points cannot all be evaluated gets no bound, so it is never culled
    // (rather than a zero sphere at the origin, culled whenever the origin is off screen).
    let finite = samples.iter().flatten().all(|x| x.is_finite());
    let (centre, radius) = if finite {
        crate::coverage::bounding_sphere(samples.into_iter())
    } else {
        tracing::warn!(
            face_id,
            "face surface not finite over its box: never culled"
        );
        (DVec3::ZERO, f64::from(f32::MAX))
    };
    let h = [s.uv_size[0] / n as f64, s.uv_size[1] / n as f64];
    let [muu, muv, mvv] = s.curvature;
    let chord = (h[0] * h[0] * muu + 2.0 * h[0] * h[1] * muv + h[1] * h[1] * mvv) / 8.0;
    let o = (s.frame[0] - mesh_origin).as_vec3();
    let [x, y, z] = [s.frame[1], s.frame[2], s.frame[3]].map(|a| a.as_vec3());
    let f = |v: glam::Vec3, w: f64| [v.x, v.y, v.z, w as f32];
    crate::layout::TrimSurface {
        origin: f(o, s.params[0]),
        axis_x: f(x, s.params[1]),
        axis_y: f(y, sign),
        axis_z: f(z, depth),
        uv: [
            s.uv_origin[0] as f32,
            s.uv_origin[1] as f32,
            s.uv_size[0] as f32,
            s.uv_size[1] as f32,
        ],
        sphere: [
            centre.x as f32,
            centre.y as f32,
            centre.z as f32,
            ((radius + chord) * (1.0 + 1e-5)).min(f64::from(f32::MAX)) as f32,
        ],
        curvature: [muu as f32, muv as f32, mvv as f32, f32::from_bits(s.breaks)],
        ids: [s.kind, face_id, s.tree, s.data],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(path: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(path);
        let file = cadre_step::syntax::StepFile::read(&path).expect("reads");
        cadre_step::map_file(&file)
    }

    /// The closed forms and packed B-splines the GPU evaluates are the model's surfaces:
    /// every drawn face's record gives the model's point at (u, v) across its box.
    #[test]
    fn closed_forms_are_the_model_surfaces() {
        let mut kinds = std::collections::BTreeSet::new();
        for path in [
            "examples/pin-assembly.step",
            "crates/cadre-render/tests/data/dome-and-cone.step",
            "crates/cadre-mesh/tests/data/quarter_sphere_collapsed_sides.step",
        ] {
            check_surfaces(&model(path), &mut kinds);
        }
        assert!(kinds.contains(&SURFACE_BSPLINE), "{kinds:?}");
        assert!(kinds.contains(&SURFACE_SPHERE), "{kinds:?}");
        assert!(kinds.contains(&SURFACE_CONE), "{kinds:?}");
    }

    /// A cone face whose box reaches the apex: the normal keeps the face's nappe's sense at
    /// the apex row, where ρ (the radius, here from the box's lower corner) is zero and
    /// rounds to either sign (per point, a ρ of −10⁻¹⁵ there turned the normal round);
    /// negative control: the other nappe's box gives the other sense.
    #[test]
    fn a_cone_keeps_its_nappe_sense_at_the_apex() {
        // `radius` at the box's lower side, tan α = 0.5, the box 10 long in v.
        let cone = |radius: f64| TrimFaceSurface {
            kind: SURFACE_CONE,
            frame: [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            params: [radius, 0.5],
            tree: 0,
            uv_origin: [0.0, 0.0],
            uv_size: [1.0, 10.0],
            curvature: [0.0; 3],
            data: 0,
            breaks: NO_BREAKS,
        };
        let radial = DVec3::new(0.5f64.cos(), 0.5f64.sin(), 0.0);
        let outward = |s: &TrimFaceSurface, v: f64| closed_form_normal(s, 0.5, v).dot(radial);
        // The apex on the box's lower side, ρ from 0 to 5: its radius rounded either way.
        for apex_radius in [0.0, -1e-15, 1e-15] {
            let upper = cone(apex_radius);
            assert!(outward(&upper, 0.0) > 0.0, "radius {apex_radius}");
            assert!(outward(&upper, 5.0) > 0.0);
        }
        // The apex on its upper side, ρ from −5 to 0: the other nappe faces the other way.
        let lower = cone(-5.0);
        assert!(outward(&lower, 10.0) < 0.0 && outward(&lower, 5.0) < 0.0);
    }

    /// A B-spline of degree 11 (files hold them; the stack-only basis stops at 8): the CPU
    /// evaluator of its packed form is the model's surface, and its record's bounding
    /// sphere holds the face and is tight (it was a zero sphere at the origin, so the face
    /// was culled whenever the origin was off screen: corpus trj7_b1-ec-214 at 10×).
    #[test]
    fn high_degree_bsplines_are_bounded_where_they_are() {
        use cadre_geom::Vec3;
        let (p, q) = (1, 11);
        let knots = |d: usize| [vec![0.0; d + 1], vec![1.0; d + 1]].concat();
        let net: Vec<Vec<Vec3>> = (0..=p)
            .map(|i| {
                (0..=q)
                    .map(|j| {
                        let t = j as f64 / q as f64;
                        Vec3::new(100.0 + 5.0 * i as f64, 50.0 + 20.0 * t, (3.0 * t).sin())
                    })
                    .collect()
            })
            .collect();
        let b = cadre_geom::bspline::BSplineSurface::try_new(p, q, knots(p), knots(q), net, None)
            .expect("well formed");
        let mut data = Vec::new();
        let (kind, frame, params, curvature, at) =
            packed_bspline(&b, [0.0, -1e-6], [1.0, 1.0 + 2e-6], &mut data).expect("packs");
        let s = TrimFaceSurface {
            kind,
            frame,
            params,
            tree: 0,
            uv_origin: [0.0, -1e-6],
            uv_size: [1.0, 1.0 + 2e-6],
            curvature,
            data: at,
            breaks: NO_BREAKS,
        };
        let record = surface_record(&s, (&data, 0.0), 1, std::iter::empty(), DVec3::ZERO);
        let [x, y, z, r] = record.sphere.map(f64::from);
        let (centre, radius) = (DVec3::new(x, y, z), r);
        let mut farthest: f64 = 0.0;
        for k in 0..=32 {
            for l in 0..=32 {
                let (u, v) = (f64::from(k) / 32.0, f64::from(l) / 32.0);
                let ours = face_point(&s, &data, u, v);
                assert!(
                    (ours - b.point_at(u, v)).length() < 1e-3,
                    "({u}, {v}): {ours}"
                );
                farthest = farthest.max((ours - centre).length());
            }
        }
        assert!(farthest <= radius, "{farthest} > {radius}");
        // Tight: about half the 20 × 5 box's diagonal, not an unbounded fallback.
        assert!(radius < 15.0, "{radius}");
        // Negative control: the origin, where the old record put it, is far outside.
        assert!(centre.length() > radius, "{centre} {radius}");
    }

    fn check_surfaces(model: &Model, kinds: &mut std::collections::BTreeSet<u32>) {
        let scene = TrimScene::build(model, 0.01);
        assert!(scene.drawn() > 0);
        assert_eq!(scene.drawn() + scene.fallback.len(), model.faces.len());
        let mut checked = 0;
        for (i, face) in scene.faces.iter().enumerate() {
            let Some(s) = face else { continue };
            let surface = &model.surfaces[model.faces[i].surface.index()];
            for k in 0..8 {
                let t = [f64::from(k) / 7.0, f64::from((k * 3) % 8) / 7.0];
                let u = s.uv_origin[0] + t[0] * s.uv_size[0];
                let v = s.uv_origin[1] + t[1] * s.uv_size[1];
                let exact = surface.eval(u, v);
                let ours = face_point(s, &scene.bspline_data, u, v);
                // B-splines are packed in f32.
                let tol = if s.kind == SURFACE_BSPLINE {
                    1e-4
                } else {
                    1e-9
                };
                assert!((exact - ours).length() < tol, "face {i}: {exact} vs {ours}");
                kinds.insert(s.kind);
                checked += 1;
            }
        }
        assert!(checked > 0);
        // Negative control: another face's record misses this face's surface.
        let drawn: Vec<(usize, &TrimFaceSurface)> = scene
            .faces
            .iter()
            .enumerate()
            .filter_map(|(i, f)| f.as_ref().map(|f| (i, f)))
            .collect();
        let surface_of = |i: usize| model.faces[i].surface;
        if let Some(w) = drawn
            .windows(2)
            .find(|w| surface_of(w[0].0) != surface_of(w[1].0))
        {
            let (a, b) = (w[0].1, w[1].1);
            let surface = &model.surfaces[surface_of(w[0].0).index()];
            let missed = (0..8).any(|k| {
                let u = a.uv_origin[0] + a.uv_size[0] * f64::from(k) / 7.0;
                let v = a.uv_origin[1] + a.uv_size[1] * f64::from(7 - k) / 7.0;
                (surface.eval(u, v) - face_point(b, &scene.bspline_data, u, v)).length() > 1e-6
            });
            assert!(missed, "another face's record matched");
        }
    }
}
