//! Labels: text drawn from multi-channel signed distance fields (seed 003), every glyph of
//! every label of a frame in one instanced draw (`passes/text`).
//!
//! A [`Label`] is laid out once (`cadre_text`: the bundled Noto fonts with their fallback
//! chain for GD&T symbols, HarfRust shaping with kerning) into glyph quads in em; the
//! camera only moves the anchors, in the vertex shader. A label is fixed to the screen,
//! stands at a point of the scene facing the viewer (sized in pixels), or lies in a plane of
//! the scene (an annotation plane; sized in model units). It is tested against the
//! visibility buffer's depth or drawn on top, over an optional box.

pub mod leaders;

/// Margin of a label's box around its text, em.
pub const BOX_MARGIN: f32 = 0.2;

use cadre_text::{Align, Baseline};
use glam::{DVec3, Vec2};

/// Where a label is and how it turns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextAnchor {
    /// Fixed to the screen at this position (output pixels from the top-left corner).
    Screen(Vec2),
    /// At this point of the scene, facing the viewer, moved by `offset` output pixels
    /// (x right, y down).
    Billboard {
        /// The point (model units).
        point: DVec3,
        /// Screen offset, pixels.
        offset: Vec2,
    },
    /// Lying in a plane of the scene: the text's baseline along `x_axis`, its up along
    /// `y_axis` (both unit vectors).
    Plane {
        /// The anchor (model units).
        origin: DVec3,
        /// Reading direction.
        x_axis: DVec3,
        /// Up direction.
        y_axis: DVec3,
    },
}

/// How tall a label's capital letters are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextHeight {
    /// Output pixels (screen and billboard labels).
    Pixels(f32),
    /// Model units (labels in a plane; the drawing's lettering height).
    Model(f64),
}

/// Whether surfaces in front hide a label.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextDepth {
    /// Hidden where the visibility buffer has a surface in front.
    Tested,
    /// Always drawn.
    #[default]
    OnTop,
}

/// One label.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// The text (lines split at `\n`).
    pub text: String,
    /// Where it is.
    pub anchor: TextAnchor,
    /// Cap height.
    pub height: TextHeight,
    /// sRGB colour and alpha.
    pub colour: [f32; 4],
    /// A box behind the text (sRGB colour and alpha), if any.
    pub background: Option<[f32; 4]>,
    /// Horizontal alignment on the anchor.
    pub align: Align,
    /// Which height of the block is on the anchor.
    pub baseline: Baseline,
    /// Depth test.
    pub depth: TextDepth,
    /// A leader line from this point of the scene to the label (billboard labels), drawn
    /// one pixel wide in the text's colour under the label's box.
    pub leader: Option<DVec3>,
}

impl Label {
    /// Black text `height` pixels tall facing the viewer at `point`, left-aligned, its
    /// middle on the point, on top.
    pub fn billboard(text: impl Into<String>, point: DVec3, height: f32) -> Label {
        Label {
            text: text.into(),
            anchor: TextAnchor::Billboard {
                point,
                offset: Vec2::ZERO,
            },
            height: TextHeight::Pixels(height),
            colour: [0.0, 0.0, 0.0, 1.0],
            background: None,
            align: Align::Left,
            baseline: Baseline::Middle,
            depth: TextDepth::OnTop,
            leader: None,
        }
    }

    /// Black text `height` pixels tall at `position` on the screen (pixels from the
    /// top-left), its first baseline there.
    pub fn screen(text: impl Into<String>, position: Vec2, height: f32) -> Label {
        Label {
            anchor: TextAnchor::Screen(position),
            baseline: Baseline::Alphabetic,
            ..Label::billboard(text, DVec3::ZERO, height)
        }
    }

    /// Black text `height` model units tall lying in the plane through `origin` spanned by
    /// `x_axis` (reading direction) and `y_axis` (up), depth-tested.
    pub fn in_plane(
        text: impl Into<String>,
        origin: DVec3,
        (x_axis, y_axis): (DVec3, DVec3),
        height: f64,
    ) -> Label {
        Label {
            anchor: TextAnchor::Plane {
                origin,
                x_axis: x_axis.normalize_or(DVec3::X),
                y_axis: y_axis.normalize_or(DVec3::Y),
            },
            height: TextHeight::Model(height),
            baseline: Baseline::Alphabetic,
            depth: TextDepth::Tested,
            ..Label::billboard(text, origin, 1.0)
        }
    }

    /// This label with a leader line from `point`.
    pub fn with_leader(mut self, point: DVec3) -> Label {
        self.leader = Some(point);
        self
    }

    /// The point of the scene the label hangs on (`None` for a screen label).
    pub fn point(&self) -> Option<DVec3> {
        match self.anchor {
            TextAnchor::Screen(_) => None,
            TextAnchor::Billboard { point, .. } => Some(point),
            TextAnchor::Plane { origin, .. } => Some(origin),
        }
    }
}

/// A filled triangle drawn with the labels (an annotation's arrowhead or filled lettering),
/// flat in its colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fill {
    /// Its corners (model units).
    pub corners: [DVec3; 3],
    /// sRGB colour and alpha.
    pub colour: [f32; 4],
    /// Depth test.
    pub depth: TextDepth,
}

/// Labels drawn over the scene, in order (later ones over earlier ones), and filled
/// triangles under them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LabelSet {
    /// The labels.
    pub labels: Vec<Label>,
    /// Filled triangles, drawn before the labels.
    pub fills: Vec<Fill>,
}

impl LabelSet {
    /// Appends `other`'s labels and fills after these.
    pub fn extend(&mut self, other: LabelSet) {
        self.labels.extend(other.labels);
        self.fills.extend(other.fills);
    }

    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.fills.is_empty() && self.labels.iter().all(|l| l.text.trim().is_empty())
    }

    /// The box of the labels' scene points and leader ends (screen labels have none).
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.labels
            .iter()
            .flat_map(|l| l.point().into_iter().chain(l.leader))
            .chain(self.fills.iter().flat_map(|f| f.corners))
            .fold(None, |b, p| match b {
                None => Some((p, p)),
                Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
            })
    }
}
