//! Analytic primitives: spheres and rectangles drawn by ray casting each pixel (the analytic
//! surface back-end, `passes/visibility/analytic`), in the same visibility buffer as the
//! meshes. They are the second back-end, proving that several share the buffer; exact quadrics cut
//! by planes (seed 001) and the analytic faces of a B-Rep grow from them.

use cadre_geom::Frame;
use glam::{DAffine3, DMat3, DVec3};

use crate::Camera;
use crate::layout::{DRAW_CLOSED, Primitive};
use crate::placements::{normal_columns, normal_matrix};

/// [`Primitive::kind`]: a sphere of radius `size.x`.
pub const PRIMITIVE_SPHERE: u32 = 0;
/// [`Primitive::kind`]: the rectangle `|x| ≤ size.x`, `|y| ≤ size.y` of the plane z = 0.
pub const PRIMITIVE_RECTANGLE: u32 = 1;

/// The shape of an analytic primitive, in its own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
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
}

/// A sphere or rectangle drawn exactly, by ray casting, with the meshes of a scene
/// ([`crate::RenderScene::primitives`]). It is an instance of its own: the
/// visibility buffer gives it `face_id` and its instance number
/// ([`crate::PreparedScene::primitive_instance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
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
        let r = match self.shape {
            AnalyticShape::Sphere { radius } => radius,
            AnalyticShape::Rectangle {
                half_width,
                half_height,
            } => half_width.hypot(half_height),
        };
        (self.frame.origin, r.abs())
    }

    /// Its record for a frame seen by `camera`: placed relative to the eye (in `f64`, so
    /// primitives far from the origin keep their precision), with its `instance` and
    /// `material`.
    pub(crate) fn record(&self, camera: &Camera, (instance, material): (u32, u32)) -> Primitive {
        let rotation = DMat3::from_mat4(camera.view_rotation());
        let world = self.placement();
        let relative = DAffine3 {
            matrix3: world.matrix3,
            translation: world.translation - camera.eye,
        };
        let model = glam::DMat4::from(relative);
        let (kind, size, flags) = match self.shape {
            AnalyticShape::Sphere { radius } => {
                (PRIMITIVE_SPHERE, [radius as f32, 0.0], DRAW_CLOSED)
            }
            AnalyticShape::Rectangle {
                half_width,
                half_height,
            } => (
                PRIMITIVE_RECTANGLE,
                [half_width as f32, half_height as f32],
                0,
            ),
        };
        Primitive {
            model: model.as_mat4().to_cols_array_2d(),
            to_local: model.inverse().as_mat4().to_cols_array_2d(),
            normal: normal_columns(rotation * normal_matrix(world.matrix3)),
            size: [size[0], size[1], 0.0, 0.0],
            kind,
            face: self.face_id,
            instance,
            material,
            flags,
            pad: [0; 3],
        }
    }
}
