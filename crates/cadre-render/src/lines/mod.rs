//! Polylines as a CAD/CAM engine draws them (seed 003): B-Rep edges, wires, sketches, PMI
//! curves and toolpaths, each a [`Polyline`] of a [`LineSet`] drawn in a [`LineStyle`] —
//! a width in pixels (0.5–16, anti-aliased) or in model units (at least one pixel), miter,
//! round or bevel joins, butt, square or round caps, and an exact stipple: `glLineStipple`'s
//! 16-bit pattern repeated with a factor, counted on the cumulative **screen-space** arc
//! length of each polyline, continuous across its joints, recomputed every frame by a GPU
//! segmented scan (`passes/lines`). Lines are clipped at the near plane, tested against the
//! visibility buffer's depth, and their hidden parts hidden, shown, or drawn in another
//! style ([`Hidden`]).
//!
//! A [`LineView`] in the frame's [`crate::ViewState`] shows a set only up to a distance
//! along it (a toolpath's simulation) and clips it to a box.
//!
//! [`reference`] computes the same arc lengths and dashes on the CPU in `f64`: the oracle of
//! the GPU scan, and its fallback where the adapter has no compute shaders.

pub mod reference;
pub mod toolpath;

use glam::DVec3;

/// `glLineStipple`'s pattern: bit `⌊s / factor⌋ mod 16` of `pattern` (bit 0 first; 1 =
/// drawn) at screen arc length `s` (output pixels) from the polyline's start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stipple {
    /// The 16-bit pattern, bit 0 first.
    pub pattern: u16,
    /// How many pixels each bit lasts (≥ 1).
    pub factor: u32,
}

impl Default for Stipple {
    /// Solid.
    fn default() -> Self {
        Stipple::SOLID
    }
}

impl Stipple {
    /// Every bit drawn.
    pub const SOLID: Stipple = Stipple {
        pattern: 0xFFFF,
        factor: 1,
    };

    /// The standard patterns by name (the OpenGL red book's and CAD's usual set).
    pub const PRESETS: [(&'static str, u16); 7] = [
        ("solid", 0xFFFF),
        ("dashed", 0x00FF),
        ("dash-dot", 0x0C0F),
        ("dotted", 0xAAAA),
        ("long-dash", 0xFFC0),
        ("short-dash", 0xCCCC),
        ("dash-dot-dot", 0xFF18),
    ];

    /// A named preset ([`Stipple::PRESETS`]) or a pattern written as hexadecimal (`0x00FF`),
    /// with `factor`; `None` for anything else.
    pub fn parse(name: &str, factor: u32) -> Option<Stipple> {
        let pattern = Stipple::PRESETS
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, p)| *p)
            .or_else(|| {
                let hex = name
                    .strip_prefix("0x")
                    .or_else(|| name.strip_prefix("0X"))?;
                u16::from_str_radix(hex, 16).ok()
            })?;
        Some(Stipple {
            pattern,
            factor: factor.max(1),
        })
    }

    /// Whether the pattern draws at arc length `s` (pixels).
    pub fn drawn_at(self, s: f64) -> bool {
        let bit = (s / f64::from(self.factor.max(1))).floor().rem_euclid(16.0) as u32;
        self.pattern >> bit & 1 == 1
    }

    /// Whether every bit is drawn.
    pub fn is_solid(self) -> bool {
        self.pattern == 0xFFFF
    }
}

/// How two segments of a polyline meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Join {
    /// The outer edges extended to their intersection, beveled where that point lies more
    /// than `limit` half widths from the joint (SVG's `stroke-miterlimit`, 4 by default).
    Miter {
        /// The longest miter, in half widths (≥ 1).
        limit: f32,
    },
    /// A disc of the line's width.
    Round,
    /// The outer corners joined by a straight cut.
    Bevel,
}

/// How a polyline ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cap {
    /// At the end point.
    Butt,
    /// Half a width past it.
    Square,
    /// A half disc past it.
    Round,
}

/// A line's width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LineWidth {
    /// In output pixels (0.5–16 is the useful range; clamped to [0.25, 64]).
    Pixels(f32),
    /// In model units (a tool's diameter), at least one pixel wide on screen.
    World(f64),
}

/// What is drawn where a line lies behind the visibility buffer's surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hidden {
    /// Nothing.
    Hide,
    /// The line as where it is seen (on top of everything).
    Show,
    /// The line in this colour (sRGB, straight alpha) and stipple: hidden-line mode.
    Styled {
        /// sRGB colour and alpha.
        colour: [f32; 4],
        /// The hidden part's pattern, counted on the same arc length as the visible part's.
        stipple: Stipple,
    },
}

/// How a polyline is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineStyle {
    /// sRGB colour and alpha (where the polyline has no colours of its own).
    pub colour: [f32; 4],
    /// Width.
    pub width: LineWidth,
    /// Dash pattern.
    pub stipple: Stipple,
    /// Joins between segments.
    pub join: Join,
    /// Caps at the polyline's two ends.
    pub cap: Cap,
    /// What is drawn behind surfaces.
    pub hidden: Hidden,
    /// Whether a [`LineView`] cuts this style's polylines (its travel and clip box: a
    /// toolpath's); `false` draws them whole and leaves them out of [`LineSet::travel`] (an
    /// annotation's, a leader's).
    pub follows_view: bool,
}

impl Default for LineStyle {
    /// A solid black 1.5-pixel line, miter joins (limit 4), butt caps, hidden parts dashed
    /// in grey.
    fn default() -> Self {
        LineStyle {
            colour: [0.0, 0.0, 0.0, 1.0],
            width: LineWidth::Pixels(1.5),
            stipple: Stipple::SOLID,
            join: Join::Miter { limit: 4.0 },
            cap: Cap::Butt,
            hidden: Hidden::Styled {
                colour: [0.45, 0.45, 0.5, 1.0],
                stipple: Stipple {
                    pattern: 0x00FF,
                    factor: 1,
                },
            },
            follows_view: true,
        }
    }
}

/// One polyline: points joined in order, drawn like a GL line strip.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polyline {
    /// The points, model units (world coordinates).
    pub points: Vec<DVec3>,
    /// Index into [`LineSet::styles`] (past the end: the first style).
    pub style: u32,
    /// Optional sRGB colour of each segment, `colours[k]` for the one from point `k` to
    /// `k + 1` (a toolpath coloured by feed rate); missing entries take the style's colour.
    pub colours: Vec<[u8; 4]>,
}

/// Polylines and their styles, drawn over the scene by the lines pass.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineSet {
    /// The polylines, in order (a toolpath's in program order: [`LineView::up_to`] counts
    /// along them in this order).
    pub polylines: Vec<Polyline>,
    /// Their styles (none: [`LineStyle::default`]).
    pub styles: Vec<LineStyle>,
}

impl LineSet {
    /// Appends `other`'s polylines after this set's, with their styles.
    pub fn extend(&mut self, other: LineSet) {
        let offset = self.styles.len() as u32;
        // A polyline naming a style past the end takes the first style: keep that meaning.
        let first = other.styles.first().copied().unwrap_or_default();
        let count = other.styles.len() as u32;
        self.styles.extend(other.styles);
        if count == 0 {
            self.styles.push(first);
        }
        let count = count.max(1);
        self.polylines
            .extend(other.polylines.into_iter().map(|mut p| {
                p.style = offset + if p.style < count { p.style } else { 0 };
                p
            }));
    }

    /// Whether it has no segment to draw.
    pub fn is_empty(&self) -> bool {
        self.polylines.iter().all(|p| p.points.len() < 2)
    }

    /// The number of points.
    pub fn point_count(&self) -> usize {
        self.polylines.iter().map(|p| p.points.len()).sum()
    }

    /// The number of segments.
    pub fn segment_count(&self) -> usize {
        self.polylines
            .iter()
            .map(|p| p.points.len().saturating_sub(1))
            .sum()
    }

    /// Its bounding box, `None` when it has no finite point.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut points = self
            .polylines
            .iter()
            .flat_map(|p| &p.points)
            .filter(|p| p.is_finite());
        let first = *points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))))
    }

    /// The style of polyline `polyline` ([`LineStyle::default`] without styles).
    pub fn style_of(&self, polyline: &Polyline) -> LineStyle {
        self.styles
            .get(polyline.style as usize)
            .or(self.styles.first())
            .copied()
            .unwrap_or_default()
    }

    /// The model-space length of every polyline that follows the view, in order: where
    /// [`LineView::up_to`] counts.
    pub fn travel(&self) -> f64 {
        self.polylines
            .iter()
            .filter(|p| self.style_of(p).follows_view)
            .map(|p| {
                p.points
                    .windows(2)
                    .map(|w| w[0].distance(w[1]))
                    .sum::<f64>()
            })
            .sum()
    }

    /// The point at `distance` model units along the set (clamped to its ends): where a
    /// toolpath's tool is when the path is shown up to there.
    pub fn point_at_travel(&self, distance: f64) -> Option<DVec3> {
        let mut left = distance.max(0.0);
        let mut last = None;
        for polyline in self
            .polylines
            .iter()
            .filter(|p| self.style_of(p).follows_view)
        {
            for w in polyline.points.windows(2) {
                let length = w[0].distance(w[1]);
                if left <= length && length > 0.0 {
                    return Some(w[0].lerp(w[1], left / length));
                }
                left -= length;
                last = Some(w[1]);
            }
            if polyline.points.len() == 1 && last.is_none() {
                last = polyline.points.first().copied();
            }
        }
        last
    }
}

/// What of the line sets a frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineView {
    /// Only the first this many model units along the set ([`LineSet::travel`]), the last
    /// segment cut where the distance ends; `None`: all.
    pub up_to: Option<f64>,
    /// Only what lies in this box (world, model units; min and max corners): the CAM
    /// clipping volume. `None`: no box.
    pub clip_box: Option<(DVec3, DVec3)>,
}
