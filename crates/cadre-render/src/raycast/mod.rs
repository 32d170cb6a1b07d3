//! A CPU ray caster of the exact B-Rep: each face is its support surface, cut by its trim
//! loops. It is the independent oracle for the GPU's face-id buffer, whichever back-end drew
//! it. Planes, cylinders, cones and spheres are intersected in closed form; every other
//! surface (tori, B-splines, revolutions, extrusions, offsets) through a tree of boxed
//! (u, v) cells and Newton's method from each leaf the ray enters ([`patch_tree`]).

mod closed_form;
mod patch_tree;

use cadre_brep::trim::{TrimTolerance, face_trim};
use cadre_brep::{Body, FaceId, Model};
use cadre_geom::{Accuracy, Surface, Transform};
use cadre_mesh::MeshParams;
use cadre_mesh::edges::EdgeDiscretisation;
use glam::{DVec2, DVec3, DVec4};
use rayon::prelude::*;

use crate::Camera;
use patch_tree::{PatchTree, REFINE_CACHE_CELLS, RefineCache, slab};

/// How a face's surface is intersected.
enum Intersect {
    /// A quadric or a plane, in closed form.
    ClosedForm,
    /// Any other surface, through its cell tree.
    Tree(PatchTree),
}

/// One face ready to be hit: its surface, its trim polygons in (u, v), its periods.
struct CastFace {
    step_id: u64,
    surface: Surface,
    intersect: Intersect,
    loops: Vec<Vec<DVec2>>,
    /// The loops' (u, v) box: `[u0, u1, v0, v1]`.
    uv_box: [f64; 4],
    /// Box holding the face in its part's space.
    bounds: (DVec3, DVec3),
    period_u: Option<f64>,
    period_v: Option<f64>,
}

/// The ray caster of one model.
pub struct RayCaster {
    faces: Vec<CastFace>,
    /// Per part instance: world → part transform, and the indices of its faces.
    instances: Vec<(Transform, Vec<usize>)>,
    /// STEP ids of faces skipped (unsupported surface, or no trim) and of tessellated items
    /// (not cast).
    pub skipped: Vec<u64>,
    /// Refined cells kept by every face's tree, shared so their memory is bounded.
    cache: RefineCache,
    /// Quadric primitives, cast exactly ([`cadre_geom::CutQuadric::hit`]).
    quadrics: Vec<CastQuadric>,
}

/// A quadric primitive ready to be hit: its id, world → frame map, the primitive in its
/// frame's coordinates and its box there.
struct CastQuadric {
    id: u64,
    to_frame: glam::DAffine3,
    cut: cadre_geom::CutQuadric,
    bounds: (DVec3, DVec3),
}

impl RayCaster {
    /// Prepares every face of every part instance of `model`; trims are computed from edges
    /// sampled at `deflection` (model units).
    pub fn new(model: &Model, deflection: f64) -> RayCaster {
        let params = MeshParams {
            deflection,
            angle: 0.2,
            ..MeshParams::default()
        };
        let acc = Accuracy::default();
        let edges = EdgeDiscretisation::new(model, &params, acc);
        let tol = TrimTolerance {
            deflection,
            angle: 0.2,
            accuracy: acc,
            keep_exact: false,
        };
        let cache = RefineCache::new(REFINE_CACHE_CELLS);
        let prepared: Vec<Option<CastFace>> = model
            .faces
            .par_iter()
            .enumerate()
            .map(|(i, face)| {
                let trim = face_trim(model, FaceId(i as u32), &edges, &tol).ok()?;
                let loops = trim
                    .loops
                    .iter()
                    .map(|l| l.polygon().iter().map(|p| p.uv).collect())
                    .collect();
                CastFace::new(
                    face.step_id,
                    model.surfaces[face.surface.index()].clone(),
                    loops,
                    &cache,
                )
            })
            .collect();
        let mut faces = Vec::new();
        let mut index_of = vec![None; model.faces.len()];
        let mut skipped = Vec::new();
        for (i, face) in prepared.into_iter().enumerate() {
            match face {
                Some(face) => {
                    index_of[i] = Some(faces.len());
                    faces.push(face);
                }
                None => skipped.push(model.faces[i].step_id),
            }
        }
        let mut instances = Vec::new();
        let mut tessellated = Vec::new();
        model.visit_instances(|visit| {
            let mut ids = Vec::new();
            for body in &model.part(visit.part).bodies {
                let mut push = |f: FaceId| {
                    if let Some(k) = index_of[f.index()] {
                        ids.push(k);
                    }
                };
                match body {
                    Body::Solid(s) => {
                        for shell in model.solids[s.index()].shells() {
                            for &(f, _) in &model.shells[shell.index()].faces {
                                push(f);
                            }
                        }
                    }
                    Body::Shell(shell) => {
                        for &(f, _) in &model.shells[shell.index()].faces {
                            push(f);
                        }
                    }
                    Body::Face(f) => push(*f),
                    // A tessellated item (AP242) is not cast: its faces are reported as
                    // skipped, so the pixels showing them count as unverified, not wrong.
                    Body::Mesh(m) => tessellated.push(model.meshes[m.index()].step_id),
                    _ => {}
                }
            }
            if !ids.is_empty() {
                instances.push((visit.transform.inverse(), ids));
            }
        });
        tessellated.sort_unstable();
        tessellated.dedup();
        skipped.extend(tessellated);
        RayCaster {
            faces,
            instances,
            skipped,
            cache,
            quadrics: Vec::new(),
        }
    }

    /// Adds an analytic primitive, cast like a face with the primitive's face id: a sphere
    /// is its whole spherical surface, a rectangle its plane trimmed to it.
    pub fn add_primitive(&mut self, primitive: &crate::AnalyticPrimitive) {
        use crate::AnalyticShape;
        use std::f64::consts::{FRAC_PI_2, TAU};
        let frame = primitive.frame;
        // The trim: a rectangle of (u, v); a sphere's covers its whole domain.
        let (surface, (u0, u1), (v0, v1)) = match &primitive.shape {
            AnalyticShape::Quadric(q) => {
                let corners = q.bounds().corners();
                let bounds = corners
                    .iter()
                    .fold((corners[0], corners[0]), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    });
                self.quadrics.push(CastQuadric {
                    id: u64::from(primitive.face_id),
                    to_frame: primitive.placement().inverse(),
                    cut: q.cut().clone(),
                    bounds,
                });
                return;
            }
            AnalyticShape::Sphere { radius } => (
                Surface::Sphere {
                    frame,
                    radius: *radius,
                },
                (-0.1, TAU + 0.1),
                (-FRAC_PI_2 - 0.1, FRAC_PI_2 + 0.1),
            ),
            AnalyticShape::Rectangle {
                half_width: a,
                half_height: b,
            } => (Surface::Plane { frame }, (-*a, *a), (-*b, *b)),
        };
        let rectangle = vec![
            DVec2::new(u0, v0),
            DVec2::new(u1, v0),
            DVec2::new(u1, v1),
            DVec2::new(u0, v1),
        ];
        let id = u64::from(primitive.face_id);
        let Some(face) = CastFace::new(id, surface, vec![rectangle], &self.cache) else {
            self.skipped.push(u64::from(primitive.face_id));
            return;
        };
        self.faces.push(face);
        self.instances
            .push((Transform::IDENTITY, vec![self.faces.len() - 1]));
    }

    /// The STEP id of the face seen at the centre of every pixel of a `width` × `height`
    /// image from `camera` (0 for background), row by row.
    pub fn face_ids(&self, camera: &Camera, width: u32, height: u32) -> Vec<u64> {
        self.hits(camera, width, height)
            .into_iter()
            .map(|h| h.map_or(0, |(id, _)| id))
            .collect()
    }

    /// The face (STEP id) and world point seen at the centre of every pixel, row by row.
    pub fn hits(&self, camera: &Camera, width: u32, height: u32) -> Vec<Option<(u64, DVec3)>> {
        self.hits_at(camera, width, height, DVec2::ZERO)
    }

    /// Per pixel, whether a true boundary (between two faces, or a face and the background)
    /// passes within `radius` pixels of its centre: whether the face seen at any of eight
    /// points on the circle of that radius about the centre differs from the one seen at the
    /// centre (a boundary crossing the disc between two of them unseen: a detail thinner than
    /// the sampling, is missed). A pixel whose centre sees two faces at the same depth
    /// (coincident faces, within [`TIE`] of the distance: which one shows is undefined, on
    /// the GPU as here) counts as on a boundary too.
    pub fn near_boundary(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        radius: f64,
    ) -> Vec<bool> {
        let centre = self.samples_at(camera, width, height, DVec2::ZERO);
        let mut near: Vec<bool> = centre.iter().map(|s| s.tied).collect();
        for k in 0..8 {
            let angle = f64::from(k) * std::f64::consts::FRAC_PI_4;
            let offset = DVec2::new(angle.cos(), angle.sin()) * radius;
            let ids = self.face_ids_at(camera, width, height, offset);
            for ((n, a), b) in near.iter_mut().zip(&centre).zip(&ids) {
                *n |= a.id() != *b;
            }
        }
        near
    }

    /// [`RayCaster::near_boundary`] looked at again, more closely, at the pixels `pixels`
    /// (indices row by row): the disc of `radius` pixels about each centre sampled on
    /// [`DENSE_RINGS`] circles of [`DENSE_SAMPLES`] points each. Eight points on one
    /// circle miss a boundary thinner than their spacing (0.39 pixel at half a pixel) —
    /// a sliver of a surface seen nearly edge-on, sub-pixel wide, was called far from any
    /// boundary (bug29478's ruled face from the front); 32 points 0.1 pixel apart on it, and
    /// two circles inside it, do not. Meant for the few pixels where two images disagree.
    pub fn near_boundary_at(
        &self,
        camera: &Camera,
        (width, height): (u32, u32),
        radius: f64,
        pixels: &[usize],
    ) -> Vec<bool> {
        let rays = PixelRays::new(camera, width, height);
        let id_at = |pixel: DVec2| {
            let (origin, dir) = rays.through(pixel);
            self.cast(origin, dir)
                .map_or((0, false), |(_, id, tied)| (id, tied))
        };
        pixels
            .par_iter()
            .map(|&i| {
                let i = i as u32;
                let centre = DVec2::new(f64::from(i % width), f64::from(i / width));
                let (id, tied) = id_at(centre);
                tied || (1..=DENSE_RINGS).any(|ring| {
                    let r = radius * f64::from(ring) / f64::from(DENSE_RINGS);
                    (0..DENSE_SAMPLES).any(|k| {
                        let angle = std::f64::consts::TAU * f64::from(k) / f64::from(DENSE_SAMPLES);
                        id_at(centre + DVec2::new(angle.cos(), angle.sin()) * r).0 != id
                    })
                })
            })
            .collect()
    }

    /// Whether each of the pixels `pixels` (index row by row, and the face's STEP id an
    /// image shows there, 0 for nothing) is a crack of that image, given that the image
    /// shows something farther there than the exact surface: the pixel's centre sees a
    /// face, and none of [`DENSE_SAMPLES`] points on the circle of `radius` pixels about it
    /// sees what the image shows (nothing included). Where one does, the image's choice
    /// is a boundary's (a silhouette over what is behind, or the edge between two faces),
    /// not a crack. Meant for the pixels where an image shows something farther than the
    /// exact surface (the crack pass's verification).
    pub fn cracks_at(
        &self,
        camera: &Camera,
        (width, height): (u32, u32),
        radius: f64,
        pixels: &[(usize, u64)],
    ) -> Vec<bool> {
        let rays = PixelRays::new(camera, width, height);
        let seen_at = |pixel: DVec2| {
            let (origin, dir) = rays.through(pixel);
            self.cast(origin, dir).map_or(0, |(_, id, _)| id)
        };
        pixels
            .par_iter()
            .map(|&(i, shown)| {
                let i = i as u32;
                let centre = DVec2::new(f64::from(i % width), f64::from(i / width));
                let id = seen_at(centre);
                id != 0
                    && id != shown
                    && (0..DENSE_SAMPLES).all(|k| {
                        let angle = std::f64::consts::TAU * f64::from(k) / f64::from(DENSE_SAMPLES);
                        seen_at(centre + DVec2::new(angle.cos(), angle.sin()) * radius) != shown
                    })
            })
            .collect()
    }

    /// The crack pixels (indices row by row) of a GPU image (`ids`, as
    /// `Renderer::render_ids` gives them; `step_ids`, its faces' STEP ids) against the ray
    /// caster's `hits` of the same view: pixels where the GPU shows nothing, or a point
    /// farther from the eye plane than the exact one by more than `d_min`, and the exact
    /// image shows neither within half a pixel ([`RayCaster::cracks_at`]).
    pub fn crack_pixels(
        &self,
        camera: &Camera,
        (w, h): (u32, u32),
        (ids, step_ids, hits): (&[[u32; 4]], &[u64], &[PixelHit]),
        d_min: f64,
    ) -> Vec<usize> {
        let aspect = f64::from(w) / f64::from(h);
        let unproject = (camera.projection_matrix(aspect) * camera.view_rotation()).inverse();
        let forward = (camera.target - camera.eye).normalize_or_zero();
        let gpu_depth = |i: usize, depth: f32| -> f64 {
            if depth <= 0.0 {
                return f64::INFINITY;
            }
            let (x, y) = ((i as u32 % w) as f64, (i as u32 / w) as f64);
            let ndc = DVec4::new(
                (x + 0.5) / f64::from(w) * 2.0 - 1.0,
                1.0 - (y + 0.5) / f64::from(h) * 2.0,
                f64::from(depth),
                1.0,
            );
            let p = unproject * ndc;
            (p.truncate() / p.w).dot(forward)
        };
        let suspects: Vec<usize> = (0..ids.len())
            .filter(|&i| {
                hits[i].is_some_and(|(_, point)| {
                    let exact = (point - camera.eye).dot(forward);
                    // Background: no depth (its ids may be an earlier frame's, `render_ids`).
                    let depth = if ids[i][1] == 0 {
                        0.0
                    } else {
                        f32::from_bits(ids[i][3])
                    };
                    gpu_depth(i, depth) > exact + d_min
                })
            })
            .collect();
        let shown: Vec<(usize, u64)> = suspects.iter().map(|&i| (i, step_ids[i])).collect();
        let cracks = self.cracks_at(camera, (w, h), 0.5, &shown);
        suspects
            .into_iter()
            .zip(cracks)
            .filter_map(|(i, c)| c.then_some(i))
            .collect()
    }

    /// [`RayCaster::face_ids`] at `offset` pixels from each pixel's centre.
    fn face_ids_at(&self, camera: &Camera, width: u32, height: u32, offset: DVec2) -> Vec<u64> {
        self.samples_at(camera, width, height, offset)
            .into_iter()
            .map(|s| s.id())
            .collect()
    }

    /// [`RayCaster::hits`] at `offset` pixels from each pixel's centre (x right, y down).
    fn hits_at(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        offset: DVec2,
    ) -> Vec<Option<(u64, DVec3)>> {
        self.samples_at(camera, width, height, offset)
            .into_iter()
            .map(|s| s.hit)
            .collect()
    }

    /// Each pixel's [`PixelSample`] at `offset` pixels from its centre, row by row.
    fn samples_at(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        offset: DVec2,
    ) -> Vec<PixelSample> {
        let rays = PixelRays::new(camera, width, height);
        (0..width * height)
            .into_par_iter()
            .map(|i| {
                let pixel = DVec2::new(f64::from(i % width), f64::from(i / width)) + offset;
                let (origin, dir) = rays.through(pixel);
                match self.cast(origin, dir) {
                    Some((t, id, tied)) => PixelSample {
                        hit: Some((id, origin + dir * t)),
                        tied,
                    },
                    None => PixelSample {
                        hit: None,
                        tied: false,
                    },
                }
            })
            .collect()
    }

    /// The ray parameter and STEP id of the nearest face hit by the ray, and whether
    /// another face is hit at the same distance (within [`TIE`] of it).
    fn cast(&self, origin: DVec3, dir: DVec3) -> Option<(f64, u64, bool)> {
        let mut best = (f64::INFINITY, 0, false);
        // Faces are searched a tie's width beyond the nearest hit so far, so that a
        // coincident face is seen whichever comes first.
        let reach = |t: f64| t + TIE * t;
        let consider = |best: &mut (f64, u64, bool), t: f64, id: u64| {
            if reach(t) < best.0 {
                *best = (t, id, false);
            } else {
                // Within a tie of the nearest: the nearer stays, marked as tied unless both
                // are the same face (another instance of it).
                let tied = best.2 || id != best.1;
                *best = if t < best.0 {
                    (t, id, tied)
                } else {
                    (best.0, best.1, tied)
                };
            }
        };
        for (to_part, ids) in &self.instances {
            let o = to_part.transform_point3(origin);
            let d = to_part.transform_vector3(dir);
            let inv = d.recip();
            for &k in ids {
                let face = &self.faces[k];
                let t_max = reach(best.0);
                if slab(face.bounds.0, face.bounds.1, o, inv, t_max).is_none() {
                    continue;
                }
                if let Some(t) = face.nearest_hit(o, d, t_max) {
                    consider(&mut best, t, face.step_id);
                }
            }
        }
        for q in &self.quadrics {
            // The frame is rigid: the ray parameter is the world's.
            let o = q.to_frame.transform_point3(origin);
            let d = q.to_frame.transform_vector3(dir);
            if slab(q.bounds.0, q.bounds.1, o, d.recip(), reach(best.0)).is_none() {
                continue;
            }
            if let Some(hit) = q.cut.hit(o, d, 0.0) {
                consider(&mut best, hit.t, q.id);
            }
        }
        best.0.is_finite().then_some(best)
    }
}

/// What a pixel's centre sees: the face's STEP id and the world point, or nothing
/// ([`RayCaster::hits`]).
pub type PixelHit = Option<(u64, DVec3)>;

/// Circles of [`RayCaster::near_boundary_at`]'s samples (radii a third, two thirds and all
/// of the disc's).
pub const DENSE_RINGS: u32 = 3;

/// Samples on each of [`RayCaster::near_boundary_at`]'s circles.
pub const DENSE_SAMPLES: u32 = 32;

/// Two faces hit by one ray closer than this share of its distance are at the same depth:
/// below f32 depth's resolution, so which one a GPU shows is undefined.
pub const TIE: f64 = 1e-6;

/// What one ray sees: the face and point, and whether another face ties with it.
struct PixelSample {
    hit: Option<(u64, DVec3)>,
    tied: bool,
}

impl PixelSample {
    /// The STEP id of the face seen (0 for background).
    fn id(&self) -> u64 {
        self.hit.map_or(0, |(id, _)| id)
    }
}

/// The rays of a camera's image: from the near plane through each pixel.
pub struct PixelRays {
    eye: DVec3,
    unproject: glam::DMat4,
    size: DVec2,
}

impl PixelRays {
    /// The rays of a `width` × `height` image seen by `camera`.
    pub fn new(camera: &Camera, width: u32, height: u32) -> PixelRays {
        let aspect = f64::from(width) / f64::from(height);
        PixelRays {
            eye: camera.eye,
            unproject: (camera.projection_matrix(aspect) * camera.view_rotation()).inverse(),
            size: DVec2::new(f64::from(width), f64::from(height)),
        }
    }

    /// Origin (on the near plane) and unit direction of the ray through the image point
    /// `pixel` + ½ (pixel (x, y) has its centre at (x + ½, y + ½); y down).
    pub fn through(&self, pixel: DVec2) -> (DVec3, DVec3) {
        let ndc = DVec2::new(
            (pixel.x + 0.5) / self.size.x * 2.0 - 1.0,
            1.0 - (pixel.y + 0.5) / self.size.y * 2.0,
        );
        // Reverse Z: depth 1 is the near plane, 0 the far one.
        let near = self.unproject * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let far = self.unproject * DVec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let (near, far) = (near.truncate() / near.w, far.truncate() / far.w);
        (self.eye + near, (far - near).normalize())
    }
}

impl CastFace {
    /// The face of `surface` trimmed by `loops` (even-odd, in (u, v)); `None` when it has
    /// no loop or its surface gives no finite box over them.
    fn new(
        step_id: u64,
        surface: Surface,
        loops: Vec<Vec<DVec2>>,
        cache: &RefineCache,
    ) -> Option<CastFace> {
        // A rectangular trim of a quadric is the quadric, trimmed by the loops anyway.
        let surface = match surface {
            Surface::Trimmed { basis, .. } if closed_form::handles(&basis) => *basis,
            other => other,
        };
        let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        for p in loops.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if !(lo.x < hi.x && lo.y < hi.y && lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let (intersect, bounds) = if closed_form::handles(&surface) {
            let b = surface.bbox_over(lo.x, hi.x, lo.y, hi.y);
            if b.is_empty() || !(b.min.is_finite() && b.max.is_finite()) {
                return None;
            }
            let pad = DVec3::splat(1e-9 * (b.max - b.min).length().max(1e-300));
            (Intersect::ClosedForm, (b.min - pad, b.max + pad))
        } else {
            let tree = PatchTree::build(&surface, (lo.x, hi.x), (lo.y, hi.y), cache.clone())?;
            let bounds = tree.bounds();
            (Intersect::Tree(tree), bounds)
        };
        Some(CastFace {
            step_id,
            period_u: surface.u_period(),
            period_v: surface.v_period(),
            surface,
            intersect,
            loops,
            uv_box: [lo.x, hi.x, lo.y, hi.y],
            bounds,
        })
    }

    /// The nearest `t` in `(0, t_max)` where the ray `o + t·d` (part space) meets the face.
    fn nearest_hit(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<f64> {
        match &self.intersect {
            Intersect::ClosedForm => closed_form::hits(&self.surface, o, d)
                .into_iter()
                .filter(|&t| t > 0.0 && t < t_max)
                .filter(|&t| {
                    closed_form::uv_of(&self.surface, o + d * t).is_some_and(|q| self.contains(q))
                })
                .min_by(f64::total_cmp),
            Intersect::Tree(tree) => tree
                .nearest(&self.surface, (o, d), t_max, |u, v| {
                    self.contains(DVec2::new(u, v))
                })
                .map(|h| h.t),
        }
    }

    /// Whether the surface point of parameters `q` lies inside the trim (even-odd over the
    /// loops), `q` taken into the loops' box by whole periods on closed surfaces.
    fn contains(&self, q: DVec2) -> bool {
        let [u0, _, v0, _] = self.uv_box;
        // The loops may span a little more than one period: try the point and its image a
        // period on.
        let candidates = |x: f64, start: f64, period: Option<f64>| match period {
            Some(t) if t > 0.0 => {
                let x = start + (x - start).rem_euclid(t);
                [x, x + t]
            }
            _ => [x, f64::NAN],
        };
        for u in candidates(q.x, u0, self.period_u) {
            for v in candidates(q.y, v0, self.period_v) {
                if !u.is_nan() && !v.is_nan() && self.even_odd(DVec2::new(u, v)) {
                    return true;
                }
            }
        }
        false
    }

    fn even_odd(&self, q: DVec2) -> bool {
        let mut inside = false;
        for poly in &self.loops {
            let n = poly.len();
            for i in 0..n {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x)
                {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::ViewPreset;
    use crate::{AnalyticPrimitive, AnalyticShape};
    use cadre_geom::Frame;

    /// A caster of two 2 × 2 squares facing +Z, the second `lift` above the first.
    fn two_squares(lift: f64) -> RayCaster {
        let mut caster = RayCaster::new(&Model::default(), 1e-3);
        for (face_id, z) in [(7, 0.0), (9, lift)] {
            let mut frame = Frame::WORLD;
            frame.origin.z = z;
            caster.add_primitive(&AnalyticPrimitive {
                shape: AnalyticShape::Rectangle {
                    half_width: 1.0,
                    half_height: 1.0,
                },
                frame,
                face_id,
                colour: [1.0; 4],
            });
        }
        caster
    }

    #[test]
    fn coincident_faces_count_as_a_boundary_and_separate_ones_do_not() {
        let camera = Camera::fit(
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            ViewPreset::Top,
            true,
            1.0,
        );
        // The centre pixel of a 9 × 9 image, far from the squares' edges.
        let centre = 4 * 9 + 4;
        let tied = two_squares(0.0);
        assert!(tied.near_boundary(&camera, 9, 9, 0.5)[centre]);
        // Negative control: a thousandth apart, the upper square is seen and nothing ties.
        let apart = two_squares(1e-3);
        assert_eq!(apart.face_ids(&camera, 9, 9)[centre], 9);
        assert!(!apart.near_boundary(&camera, 9, 9, 0.5)[centre]);
    }
}
