//! What is drawn behind the model (the seed's list: solid, gradient, image) and the ground
//! grid, an anti-aliased grid on a horizontal plane whose spacing follows the zoom (powers
//! of ten, the finer level fading in as it opens up), found per pixel by the exact ray–plane
//! hit and depth-tested against the model (`passes/backdrop`).

use std::sync::Arc;

use image::RgbaImage;

/// The background behind the model.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Background {
    /// [`crate::FrameOptions::background`]'s colour.
    #[default]
    Solid,
    /// A vertical gradient, sRGB colours and alpha.
    Gradient {
        /// At the image's top.
        top: [f32; 4],
        /// At its bottom.
        bottom: [f32; 4],
    },
    /// An image stretched over the view (bilinear), sRGB.
    Image(Arc<RgbaImage>),
}

impl Background {
    /// The CAD viewers' usual grey-blue gradient.
    pub fn cad_gradient() -> Background {
        Background::Gradient {
            top: [0.55, 0.63, 0.75, 1.0],
            bottom: [0.93, 0.94, 0.96, 1.0],
        }
    }
}

/// A grid on the ground: the horizontal plane (world Z up) under the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundGrid {
    /// The plane's height (world Z); `None`: the scene's lowest point.
    pub height: Option<f64>,
    /// The spacing of its finest lines (model units); `None`: powers of ten that follow
    /// the zoom (lines at least a few pixels apart, every tenth one stronger).
    pub spacing: Option<f64>,
    /// sRGB colour and opacity of its lines.
    pub colour: [f32; 4],
    /// The X (red) and Y (green) axes drawn through the origin.
    pub axes: bool,
}

impl Default for GroundGrid {
    /// Under the scene, adaptive, dark grey at 60 %, with axes.
    fn default() -> Self {
        GroundGrid {
            height: None,
            spacing: None,
            colour: [0.25, 0.27, 0.3, 0.6],
            axes: true,
        }
    }
}
