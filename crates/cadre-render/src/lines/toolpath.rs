//! A CAM program's moves ([`cadre_gcode::Program`]) as a [`LineSet`]: rapids thin and dashed
//! in their own colour, cutting moves (feeds, arcs) solid and coloured by feed rate or by
//! tool, arcs sampled within a chord tolerance (what a pixel is worth at the view's zoom:
//! [`pixel_tolerance`]), hidden parts drawn faded behind the part; and the tool at a point
//! of the path as an exact ray-cast cylinder.

use super::{Cap, Hidden, Join, LineSet, LineStyle, LineWidth, Polyline, Stipple};
use crate::{AnalyticPrimitive, AnalyticShape, QuadricShape};
use cadre_gcode::{Program, sample_moves};
use glam::DVec3;

/// What colours the cutting moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColourBy {
    /// A blue → green → yellow → red ramp from the slowest to the fastest feed.
    #[default]
    Feed,
    /// A colour per tool number.
    Tool,
    /// One colour for every cutting move.
    Kind,
}

/// How a toolpath is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolpathStyle {
    /// The rapids' style.
    pub rapid: LineStyle,
    /// The cutting moves' style (its colour where [`ColourBy::Kind`]).
    pub cut: LineStyle,
    /// What colours the cutting moves.
    pub colour_by: ColourBy,
}

impl Default for ToolpathStyle {
    /// Rapids 1 pixel, dashed, orange-red; cuts 2 pixels, round joins, coloured by feed;
    /// both faded behind surfaces.
    fn default() -> Self {
        let faded = |colour: [f32; 3]| Hidden::Styled {
            colour: [colour[0], colour[1], colour[2], 0.35],
            stipple: Stipple::SOLID,
        };
        ToolpathStyle {
            rapid: LineStyle {
                colour: [0.95, 0.35, 0.1, 1.0],
                width: LineWidth::Pixels(1.0),
                stipple: Stipple {
                    pattern: 0x0F0F,
                    factor: 2,
                },
                join: Join::Bevel,
                cap: Cap::Butt,
                hidden: faded([0.95, 0.35, 0.1]),
                follows_view: true,
            },
            cut: LineStyle {
                colour: [0.1, 0.35, 0.85, 1.0],
                width: LineWidth::Pixels(2.0),
                stipple: Stipple::SOLID,
                join: Join::Round,
                cap: Cap::Round,
                hidden: faded([0.3, 0.4, 0.6]),
                follows_view: true,
            },
            colour_by: ColourBy::Feed,
        }
    }
}

/// The chord tolerance (model units) that keeps a sampled arc within a quarter pixel of the
/// exact one in a view `view_height` model units high on `pixels` rows.
pub fn pixel_tolerance(view_height: f64, pixels: u32) -> f64 {
    0.25 * view_height / f64::from(pixels.max(1))
}

/// The program's path as polylines in `style`, arcs sampled within `tolerance` model units.
pub fn toolpath_lines(program: &Program, style: &ToolpathStyle, tolerance: f64) -> LineSet {
    let runs = sample_moves(&program.moves, tolerance);
    let (slow, fast) = program
        .moves
        .iter()
        .filter(|m| m.kind != cadre_gcode::MoveKind::Rapid)
        .map(|m| m.feed)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), f| {
            (lo.min(f), hi.max(f))
        });
    let polylines = runs
        .into_iter()
        .map(|run| {
            let colours = if run.rapid || style.colour_by == ColourBy::Kind {
                Vec::new()
            } else {
                run.moves
                    .iter()
                    .map(|&k| {
                        let m = &program.moves[k as usize];
                        match style.colour_by {
                            ColourBy::Tool => tool_colour(m.tool),
                            _ => feed_colour(m.feed, (slow, fast)),
                        }
                    })
                    .collect()
            };
            Polyline {
                points: run.points,
                style: u32::from(!run.rapid),
                colours,
            }
        })
        .collect();
    LineSet {
        polylines,
        styles: vec![style.rapid, style.cut],
    }
}

/// The feed ramp: blue (slowest) → cyan → green → yellow → red (fastest).
fn feed_colour(feed: f64, (slow, fast): (f64, f64)) -> [u8; 4] {
    let f = if fast > slow {
        ((feed - slow) / (fast - slow)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    const RAMP: [[f64; 3]; 5] = [
        [0.1, 0.2, 0.9],
        [0.0, 0.7, 0.8],
        [0.1, 0.75, 0.2],
        [0.95, 0.8, 0.1],
        [0.9, 0.15, 0.1],
    ];
    let x = f * 4.0;
    let i = (x.floor() as usize).min(3);
    let t = x - i as f64;
    let c: Vec<u8> = (0..3)
        .map(|k| ((RAMP[i][k] + (RAMP[i + 1][k] - RAMP[i][k]) * t) * 255.0).round() as u8)
        .collect();
    [c[0], c[1], c[2], 255]
}

/// A distinct colour per tool (a golden-angle walk round the hue circle).
fn tool_colour(tool: u32) -> [u8; 4] {
    let hue = (f64::from(tool) * 0.618_034).fract();
    let (r, g, b) = hsv(hue, 0.75, 0.85);
    [(r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8, 255]
}

fn hsv(h: f64, s: f64, v: f64) -> (f64, f64, f64) {
    let i = (h * 6.0).floor();
    let f = h * 6.0 - i;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - f * s), v * (1.0 - (1.0 - f) * s));
    match i as i32 % 6 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    }
}

/// The face id the tool marker's pixels carry (none of a model's).
pub const TOOL_FACE_ID: u32 = u32::MAX - 1;

/// The tool at `tip` as an exact cylinder of `diameter` (at least 1 µm), four diameters long
/// (at least 1 mm), standing on its tip along +Z (the spindle's axis on a 3-axis mill),
/// capped, ray cast like any quadric; its pixels carry [`TOOL_FACE_ID`].
pub fn tool_marker(tip: DVec3, diameter: f64) -> Option<AnalyticPrimitive> {
    use cadre_geom::{CutKind, CutQuadric, Frame, HalfSpace, Quadric};
    let diameter = diameter.max(1e-3);
    let length = (4.0 * diameter).max(1.0);
    let face_id = TOOL_FACE_ID;
    let cut = CutQuadric {
        quadric: Quadric::cylinder(0.5 * diameter),
        planes: vec![
            HalfSpace::through(DVec3::new(0.0, 0.0, length), DVec3::Z),
            HalfSpace::through(DVec3::ZERO, DVec3::NEG_Z),
        ],
        kind: CutKind::Volume,
    };
    let shape = QuadricShape::new(cut).ok()?;
    Some(AnalyticPrimitive {
        shape: AnalyticShape::Quadric(shape),
        frame: cadre_geom::Frame {
            origin: tip,
            ..Frame::WORLD
        },
        face_id,
        colour: [0.75, 0.75, 0.78, 1.0],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rapids_and_cuts_become_styled_polylines_with_feed_colours() {
        let program = cadre_gcode::interpret(
            "G0 X0 Y0 Z5\nG1 Z0 F100\nG1 X10 F1000\nG3 X-10 I-10 J0\nG0 Z5\n",
        );
        let set = toolpath_lines(&program, &ToolpathStyle::default(), 0.01);
        let kinds: Vec<u32> = set.polylines.iter().map(|p| p.style).collect();
        assert_eq!(kinds, [0, 1, 0]);
        let cut = &set.polylines[1];
        assert_eq!(cut.colours.len(), cut.points.len() - 1);
        // The slow plunge blue, the fast moves red.
        assert_eq!(cut.colours[0], [26, 51, 230, 255]);
        assert_eq!(cut.colours[1], [230, 38, 26, 255]);
        // The half circle of radius 10 within 0.01: ≈ 36 chords.
        assert!(
            (30..45).contains(&(cut.points.len() - 3)),
            "{}",
            cut.points.len()
        );
        assert!(tool_marker(DVec3::ZERO, 6.0).is_some());
        assert_eq!(pixel_tolerance(100.0, 400), 0.0625);
    }
}
