//! Analytic primitives: spheres and rectangles drawn by ray casting each pixel (the analytic
//! surface back-end, `passes/visibility/analytic`), in the same visibility buffer as the
//! meshes. They are the second back-end, proving that several share the buffer; exact quadrics cut
//! by planes (seed 001, [`QuadricShape`]) are the third kind; the analytic faces of a B-Rep
//! grow from them.

mod quadric;

use std::sync::Arc;

use cadre_geom::{CutKind, Frame};
use glam::{DAffine3, DMat3, DMat4, DVec3, DVec4};

pub use quadric::QuadricShape;

use crate::Camera;
use crate::layout::{DRAW_CLOSED, Primitive};
use crate::placements::{normal_columns, normal_matrix};

/// [`Primitive::kind`]: a sphere of radius `size.x`.
pub const PRIMITIVE_SPHERE: u32 = 0;
/// [`Primitive::kind`]: the rectangle `|x| ≤ size.x`, `|y| ≤ size.y` of the plane z = 0.
pub const PRIMITIVE_RECTANGLE: u32 = 1;
/// [`Primitive::kind`]: a quadric surface cut by planes ([`CutKind::Patch`]).
pub const PRIMITIVE_QUADRIC_PATCH: u32 = 2;
/// [`Primitive::kind`]: the volume of a quadric cut by planes ([`CutKind::Volume`]).
pub const PRIMITIVE_QUADRIC_VOLUME: u32 = 3;

/// The shape of an analytic primitive, in its own frame.
#[derive(Clone, Debug, PartialEq)]
pub enum AnalyticShape {
    /// The sphere of `radius` about the frame's origin; (u, v) are longitude about the
    /// frame's z axis from its x axis, in [0, 2π), and latitude, in [−π/2, π/2] (ISO
    /// 10303-42's spherical surface).
    Sphere {
        /// Radius, model units.
        radius: f64,
    },
    /// The rectangle `|x| ≤ half_width`, `|y| ≤ half_height` of the frame's xy plane, seen
    /// from both sides; (u, v) are its x and y.
    Rectangle {
        /// Half its extent along the frame's x axis.
        half_width: f64,
        /// Half its extent along the frame's y axis.
        half_height: f64,
    },
    /// A quadric cut by planes, as a surface patch or a volume (seed 001); (u, v) are the
    /// hit's coordinates along the first two axes of the quadric's canonical frame, from the
    /// centre of its box.
    Quadric(Arc<QuadricShape>),
}

/// A sphere or rectangle drawn exactly, by ray casting, with the meshes of a scene
/// ([`crate::RenderScene::primitives`]). It is an instance of its own: the
/// visibility buffer gives it `face_id` and its instance number
/// ([`crate::PreparedScene::primitive_instance`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AnalyticPrimitive {
    /// Its shape.
    pub shape: AnalyticShape,
    /// Where it lies: the shape's frame in world coordinates.
    pub frame: Frame,
    /// The face id it writes into the visibility buffer.
    pub face_id: u32,
    /// Base colour, linear RGBA (an opacity below 1 draws it see-through, as a view's
    /// colour does).
    pub colour: [f32; 4],
}

impl AnalyticPrimitive {
    /// Its frame as an affine map, shape-local → world.
    pub fn placement(&self) -> DAffine3 {
        let f = &self.frame;
        DAffine3::from_mat3_translation(DMat3::from_cols(f.x, f.y, f.z), f.origin)
    }

    /// Its bounding sphere in world coordinates (centre, radius).
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        let r = match &self.shape {
            AnalyticShape::Sphere { radius } => *radius,
            AnalyticShape::Rectangle {
                half_width,
                half_height,
            } => half_width.hypot(*half_height),
            AnalyticShape::Quadric(q) => {
                let (centre, radius) = q.sphere();
                return (self.frame.to_world(centre), radius);
            }
        };
        (self.frame.origin, r.abs())
    }

    /// The world box of the primitive (low, high).
    pub fn world_box(&self) -> (DVec3, DVec3) {
        let f = &self.frame;
        let half = match &self.shape {
            AnalyticShape::Sphere { radius } => DVec3::splat(radius.abs()),
            AnalyticShape::Rectangle {
                half_width,
                half_height,
            } => (f.x * *half_width).abs() + (f.y * *half_height).abs(),
            AnalyticShape::Quadric(q) => {
                let corners = q.bounds().corners().map(|c| f.to_world(c));
                return corners
                    .iter()
                    .fold((corners[0], corners[0]), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    });
            }
        };
        (f.origin - half, f.origin + half)
    }

    /// Its record for a frame seen through `view`: placed relative to the eye (in `f64`, so primitives far from the origin keep their
    /// precision), with its `instance` and `material`; a quadric's planes go into `planes`
    /// (the frame's plane buffer, which the record indexes) once per shape.
    pub(crate) fn record(
        &self,
        view: &FrameView,
        (instance, material): (u32, u32),
        planes: &mut FramePlanes,
    ) -> Primitive {
        let camera = &view.camera;
        let rotation = DMat3::from_mat4(view.rotation);
        // The shape's own frame: a quadric's is its box's.
        let world = match &self.shape {
            AnalyticShape::Quadric(q) => self.placement() * q.local().placement,
            _ => self.placement(),
        };
        let relative = DAffine3 {
            matrix3: world.matrix3,
            translation: world.translation - camera.eye,
        };
        let model = glam::DMat4::from(relative);
        let mut record = Primitive {
            model: model.as_mat4().to_cols_array_2d(),
            to_local: model.inverse().as_mat4().to_cols_array_2d(),
            normal: normal_columns(rotation * normal_matrix(world.matrix3)),
            instance,
            material,
            ..Primitive::default()
        };
        (record.ray, record.depth) = pixel_ray(view, relative);
        match &self.shape {
            AnalyticShape::Sphere { radius } => {
                record.kind = PRIMITIVE_SPHERE;
                record.size = [*radius as f32, 0.0, 0.0, 0.0];
                record.flags = DRAW_CLOSED;
            }
            AnalyticShape::Rectangle {
                half_width,
                half_height,
            } => {
                record.kind = PRIMITIVE_RECTANGLE;
                record.size = [*half_width as f32, *half_height as f32, 0.0, 0.0];
            }
            AnalyticShape::Quadric(q) => {
                let local = q.local();
                let volume = q.kind() == CutKind::Volume;
                record.kind = if volume {
                    PRIMITIVE_QUADRIC_VOLUME
                } else {
                    PRIMITIVE_QUADRIC_PATCH
                };
                // A bounded volume is a closed solid: section planes cap it.
                record.flags = if volume { DRAW_CLOSED } else { 0 };
                record.size = local.lambda.extend(local.constant).as_vec4().to_array();
                let smooth = if local.smooth { 1.0 } else { 0.0 };
                record.linear = local.linear.extend(smooth).as_vec4().to_array();
                record.planes = [planes.of(q), local.planes.len() as u32];
                record.screen = quadric_screen(view, relative, local);
            }
        }
        record.face = self.face_id;
        record
    }
}

/// What every primitive's record of a frame reads of its camera, worked out once a frame
/// (10⁶ records would build the same matrices 10⁶ times).
pub(crate) struct FrameView {
    /// The camera.
    pub camera: Camera,
    /// Its rotation-only view matrix.
    pub rotation: DMat4,
    /// Its projection for the frame's aspect.
    pub projection: DMat4,
}

impl FrameView {
    /// `camera` seen in an image of `aspect` (width / height).
    pub fn new(camera: &Camera, aspect: f64) -> FrameView {
        FrameView {
            camera: *camera,
            rotation: camera.view_rotation(),
            projection: camera.projection_matrix(aspect),
        }
    }
}

/// A frame's cutting planes of its quadrics, each shape's once (the primitives of a crowd
/// share a few shapes).
#[derive(Default)]
pub(crate) struct FramePlanes {
    /// The planes (n, d) in their shapes' box frames.
    pub planes: Vec<[f32; 4]>,
    /// Where each shape's planes start, by the shape's address.
    first: std::collections::HashMap<*const QuadricShape, u32>,
}

impl FramePlanes {
    /// Where `shape`'s planes start, adding them the first time.
    fn of(&mut self, shape: &Arc<QuadricShape>) -> u32 {
        *self.first.entry(Arc::as_ptr(shape)).or_insert_with(|| {
            let at = self.planes.len() as u32;
            self.planes
                .extend(shape.local().planes.iter().map(|p| p.as_vec4().to_array()));
            at
        })
    }
}

/// The screen rectangle (normalised device coordinates: low x, low y, high x, high y)
/// holding a quadric whose box frame maps to camera-relative world by `relative`: its box's
/// corners projected (the whole screen when the box reaches behind the eye), narrowed for an
/// ellipsoid to the planes x = X w and y = Y w tangent to it, which its dual quadric
/// C = T Q⁻¹ Tᵀ gives (T: box frame → clip; Sigg et al. 2006): C_ii − 2X C_i3 + X² C_33 = 0.
fn quadric_screen(view: &FrameView, relative: DAffine3, local: &quadric::LocalQuadric) -> [f32; 4] {
    let to_clip = view.projection * view.rotation * DMat4::from(relative);
    let whole = [-1.0, -1.0, 1.0, 1.0];
    let (mut lo, mut hi) = (
        glam::DVec2::splat(f64::INFINITY),
        glam::DVec2::splat(f64::NEG_INFINITY),
    );
    for i in 0..8 {
        let sign = |bit: u32| if i & bit == 0 { -1.0 } else { 1.0 };
        let corner = DVec3::new(sign(1), sign(2), sign(4)) * local.half;
        let clip = to_clip * corner.extend(1.0);
        if clip.w <= 0.0 {
            return whole;
        }
        let ndc = clip.truncate().truncate() / clip.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    if local.ellipsoid {
        let q = DMat4::from_cols(
            DVec4::new(local.lambda.x, 0.0, 0.0, local.linear.x),
            DVec4::new(0.0, local.lambda.y, 0.0, local.linear.y),
            DVec4::new(0.0, 0.0, local.lambda.z, local.linear.z),
            local.linear.extend(local.constant),
        );
        let dual = to_clip * q.inverse() * to_clip.transpose();
        let c = |i: usize, j: usize| dual.col(j)[i];
        for i in 0..2 {
            let (a, h, c0) = (c(3, 3), c(i, 3), c(i, i));
            let disc = h * h - c0 * a;
            if disc >= 0.0 && a != 0.0 {
                let (x0, x1) = ((h - disc.sqrt()) / a, (h + disc.sqrt()) / a);
                lo[i] = lo[i].max(x0.min(x1));
                hi[i] = hi[i].min(x0.max(x1));
            }
        }
    }
    [lo.x as f32, lo.y as f32, hi.x as f32, hi.y as f32]
}

/// The pixel rays of a frame in a shape's frame (`relative`: shape → camera-relative
/// world), as [`Primitive::ray`] and [`Primitive::depth`] give them: for the pixel at
/// normalised device coordinates (x, y), the ray o + s d with o = o₀ + x oₓ + y o_y (the
/// point of the ray at the view depth Z of the shape's origin) and d = d₀ + x dₓ + y d_y
/// (scaled so the view depth grows by 1 per unit of s), and its depth (reverse Z)
/// (N − P₂₂ s) / (Z + s) in perspective, N − P₂₂ s in orthographic projection.
///
/// All of it is computed in `f64` and is of the shape's size near the shape, so the `f32`
/// rays stay exact to a fraction of a pixel at any magnification: a ray from the eye in
/// `f32` would carry the eye's rounding (10⁻⁷ of its distance, a pixel at 10⁴×).
fn pixel_ray(frame: &FrameView, relative: DAffine3) -> ([[f32; 4]; 6], [f32; 4]) {
    let camera = &frame.camera;
    let view = DMat3::from_mat4(frame.rotation);
    // Shape frame → view space, and back.
    let to_view = DAffine3 {
        matrix3: view * relative.matrix3,
        translation: view * relative.translation,
    };
    let to_shape = to_view.inverse();
    let projection = frame.projection;
    let (p00, p11) = (projection.x_axis.x, projection.y_axis.y);
    let (p22, p32) = (projection.z_axis.z, projection.w_axis.z);
    // The view depth of the shape's origin, or just past the near plane when it is behind.
    let depth = (-to_view.translation.z).max(camera.near.max(f64::MIN_POSITIVE));
    let ortho = camera.is_orthographic();
    let (ox, oy, o0, dx, dy) = if ortho {
        let (cx, cy) = (-projection.w_axis.x / p00, -projection.w_axis.y / p11);
        (
            DVec3::new(1.0 / p00, 0.0, 0.0),
            DVec3::new(0.0, 1.0 / p11, 0.0),
            DVec3::new(cx, cy, -depth),
            DVec3::ZERO,
            DVec3::ZERO,
        )
    } else {
        let (tx, ty) = (1.0 / p00, 1.0 / p11);
        (
            DVec3::new(tx * depth, 0.0, 0.0),
            DVec3::new(0.0, ty * depth, 0.0),
            DVec3::new(0.0, 0.0, -depth),
            DVec3::new(tx, 0.0, 0.0),
            DVec3::new(0.0, ty, 0.0),
        )
    };
    let point = |v: DVec3| to_shape.transform_point3(v);
    let vector = |v: DVec3| to_shape.transform_vector3(v);
    let column = |v: DVec3| v.as_vec3().extend(0.0).to_array();
    let ray = [
        column(point(o0)),
        column(vector(ox)),
        column(vector(oy)),
        column(vector(DVec3::NEG_Z)),
        column(vector(dx)),
        column(vector(dy)),
    ];
    // Reverse Z: depth = (P₂₂ z + P₃₂) / w with z = −(Z + s), w = Z + s (perspective) or 1.
    let numerator = p32 - p22 * depth;
    let terms = DVec4::new(depth, numerator, p22, 0.0);
    (ray, terms.as_vec4().to_array())
}
