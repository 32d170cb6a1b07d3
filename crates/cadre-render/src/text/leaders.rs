//! Part names as leader labels (`cadre render --labels`, the viewer's Display → Part
//! labels), laid out as CAD callouts for one view: each placed part's name in a box in a
//! column beside the assembly's image (left for parts left of its middle, right for the
//! others), ordered by height and spread so that no two boxes overlap, with a leader line
//! from a point of the part's surface. The layout follows the camera: a new view lays the
//! labels out again ([`part_labels`] is cheap: a projection and a sort).

use super::{Label, LabelSet, TextAnchor, TextDepth};
use crate::Camera;
use cadre_mesh::scene::Scene;
use cadre_text::{Align, Baseline};
use glam::{DMat4, DVec3, DVec4, Vec2};

/// A callout to lay out: its text and the point of a surface its leader starts from (a part's
/// name, or a generated PMI callout's text at its faces).
#[derive(Clone, Debug, PartialEq)]
pub struct PartAnchor {
    /// The text (the part's name).
    pub name: String,
    /// A point of its surface (world, model units).
    pub point: DVec3,
    /// How it is drawn.
    pub style: CalloutStyle,
}

/// The colours of a callout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalloutStyle {
    /// Text and leader colour (linear RGBA).
    pub colour: [f32; 4],
    /// Its box's colour.
    pub background: [f32; 4],
}

impl CalloutStyle {
    /// A part name: near-black on pale yellow.
    pub const PART: CalloutStyle = CalloutStyle {
        colour: [0.1, 0.1, 0.1, 1.0],
        background: [1.0, 1.0, 0.88, 0.92],
    };
    /// Generated PMI: the PMI colour on white.
    pub const PMI: CalloutStyle = CalloutStyle {
        colour: crate::pmi::PMI_COLOUR,
        background: [1.0, 1.0, 1.0, 0.9],
    };
}

/// The named parts of `scene`, each named by its node, else its nearest named ancestor
/// (STEP files name the product and leave its shape representation unnamed), else its mesh;
/// parts without any name are left out.
pub fn part_anchors(scene: &Scene) -> Vec<PartAnchor> {
    // Each node's first parent, for the names of unnamed nodes.
    let mut parent = vec![None; scene.nodes.len()];
    for (n, node) in scene.nodes.iter().enumerate() {
        for &child in &node.children {
            if let Some(p) = parent.get_mut(child) {
                p.get_or_insert(n);
            }
        }
    }
    let named = |mut node: usize| {
        // At most as many steps as nodes: a cycle of parents ends the search.
        for _ in 0..scene.nodes.len() {
            let name = scene.nodes[node].name.trim();
            if !name.is_empty() {
                return Some(name);
            }
            node = parent[node]?;
        }
        None
    };
    let mut out = Vec::new();
    for (node, world) in scene.instances() {
        let Some(mesh) = scene.nodes[node].mesh.and_then(|m| scene.meshes.get(m)) else {
            continue;
        };
        let name = named(node).or_else(|| Some(mesh.name.trim()).filter(|n| !n.is_empty()));
        let (Some(name), Some(point)) = (name, surface_anchor(&mesh.positions, world)) else {
            continue;
        };
        out.push(PartAnchor {
            name: name.to_string(),
            point,
            style: CalloutStyle::PART,
        });
    }
    out
}

/// The vertex of a mesh (placed by `world`) nearest its box's centre: a point on the part's
/// surface for the leader to start from; `None` for a mesh without finite vertices.
fn surface_anchor(positions: &[[f32; 3]], world: glam::DAffine3) -> Option<DVec3> {
    let points = positions
        .iter()
        .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
        .filter(|p| p.is_finite());
    let (lo, hi) = points.clone().fold(None, |b: Option<(DVec3, DVec3)>, p| {
        Some(b.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))))
    })?;
    let middle = 0.5 * (lo + hi);
    let nearest = points.min_by(|a, b| {
        a.distance_squared(middle)
            .total_cmp(&b.distance_squared(middle))
    })?;
    Some(world.transform_point3(nearest))
}

/// Where world points fall on a `w` × `h` image seen by a camera (output pixels, y down);
/// `None` behind the eye.
struct Projector {
    to_clip: DMat4,
    size: (f64, f64),
}

impl Projector {
    fn new(camera: &Camera, (w, h): (u32, u32)) -> Projector {
        let size = (f64::from(w.max(1)), f64::from(h.max(1)));
        let to_clip = camera.projection_matrix(size.0 / size.1)
            * camera.view_rotation()
            * DMat4::from_translation(-camera.eye);
        Projector { to_clip, size }
    }

    fn pixel(&self, p: DVec3) -> Option<(f64, f64)> {
        let c: DVec4 = self.to_clip * p.extend(1.0);
        (c.w > 0.0).then(|| {
            (
                (0.5 * c.x / c.w + 0.5) * self.size.0,
                (0.5 - 0.5 * c.y / c.w) * self.size.1,
            )
        })
    }
}

/// Labels for `anchors` seen by `camera` on a `size` image: text `height` pixels tall in
/// boxes stacked in two columns beside the image of `bounds` (the assembly's box; the
/// anchors' own when `None`), leaders to the parts.
pub fn callout_labels(
    anchors: &[PartAnchor],
    bounds: Option<(DVec3, DVec3)>,
    camera: &Camera,
    size: (u32, u32),
    height: f32,
) -> LabelSet {
    lay_out_callouts(anchors, bounds, camera, size, height).labels
}

/// Callouts laid out for a view, and how many did not fit.
#[derive(Clone, Debug, Default)]
pub struct Callouts {
    /// The boxes, texts and leaders.
    pub labels: LabelSet,
    /// Anchors left out: a column holds as many boxes as the image is tall.
    pub omitted: usize,
}

/// [`callout_labels`], telling how many anchors were left out for want of room (a column
/// keeps an even choice of its anchors, top to bottom).
pub fn lay_out_callouts(
    anchors: &[PartAnchor],
    bounds: Option<(DVec3, DVec3)>,
    camera: &Camera,
    size: (u32, u32),
    height: f32,
) -> Callouts {
    let projector = Projector::new(camera, size);
    let seen: Vec<(&PartAnchor, (f64, f64))> = anchors
        .iter()
        .filter_map(|a| Some((a, projector.pixel(a.point)?)))
        .collect();
    if seen.is_empty() {
        return Callouts::default();
    }
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    let corners = bounds.into_iter().flat_map(|(lo, hi)| {
        (0..8).map(move |i| {
            DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
    });
    let outline = corners.filter_map(|c| projector.pixel(c));
    for (x, _) in seen.iter().map(|s| s.1).chain(outline) {
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    let middle = 0.5 * (x0 + x1);
    // Boxes one box apart (a line of the first font and its margins, and a pixel); columns
    // a gap outside the assembly, kept on the image.
    let font = cadre_text::FontChain::bundled().primary();
    let em = f64::from(height / font.cap_height);
    let pitch = f64::from(font.ascender - font.descender + 2.0 * super::BOX_MARGIN) * em + 1.0;
    let gap = 2.0 * f64::from(height);
    let (w, h) = projector.size;
    let columns = [
        ((x0 - gap).max(0.3 * w.min(x0)), Align::Right),
        ((x1 + gap).min(w - 0.3 * (w - x1).max(0.0)), Align::Left),
    ];
    let mut labels = Vec::new();
    let mut omitted = 0;
    for (side, &(column, align)) in columns.iter().enumerate() {
        let mut group: Vec<&(&PartAnchor, (f64, f64))> = seen
            .iter()
            .filter(|(_, (x, _))| (*x >= middle) == (side == 1))
            .collect();
        group.sort_by(|a, b| a.1.1.total_cmp(&b.1.1));
        // A column holds as many boxes as the image is tall: past that, an even choice
        // across the column (top to bottom) is kept and the rest counted as omitted.
        let capacity = ((h / pitch).floor() as usize).max(1);
        if group.len() > capacity {
            let n = group.len();
            omitted += n - capacity;
            group = (0..capacity).map(|k| group[k * n / capacity]).collect();
        }
        // The column stays where its widest box is whole on the image (a long feature
        // control frame beside a wide model moves in over the model rather than off the
        // image).
        let chain = cadre_text::FontChain::bundled();
        let shaper = cadre_text::Shaper::bundled();
        let widest = group
            .iter()
            .map(|g| {
                let l = cadre_text::layout(
                    chain,
                    shaper,
                    &g.0.name,
                    (Align::Left, Baseline::Middle),
                    1.0,
                );
                f64::from(l.max.x - l.min.x + 2.0 * super::BOX_MARGIN) * em
            })
            .fold(0.0, f64::max);
        let margin = 2.0;
        let column = match align {
            Align::Right => column.max(widest + margin),
            _ => column.min(w - widest - margin),
        };
        let slots = spread(&group.iter().map(|g| g.1.1).collect::<Vec<_>>(), pitch, h);
        for ((anchor, (ax, ay)), y) in group.iter().map(|g| (g.0, g.1)).zip(slots) {
            labels.push(Label {
                text: anchor.name.clone(),
                anchor: TextAnchor::Billboard {
                    point: anchor.point,
                    offset: Vec2::new((column - ax) as f32, (y - ay) as f32),
                },
                height: super::TextHeight::Pixels(height),
                colour: anchor.style.colour,
                background: Some(anchor.style.background),
                align,
                baseline: Baseline::Middle,
                depth: TextDepth::OnTop,
                leader: Some(anchor.point),
            });
        }
    }
    Callouts {
        labels: LabelSet {
            labels,
            fills: Vec::new(),
        },
        omitted,
    }
}

/// Heights for boxes wanted at `wanted` (sorted), at least `pitch` apart, as near their
/// wish as that allows and inside `0..height` where they fit.
fn spread(wanted: &[f64], pitch: f64, height: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(wanted.len());
    for &y in wanted {
        let y = match out.last() {
            Some(&above) => y.max(above + pitch),
            None => y,
        };
        out.push(y);
    }
    // Pushed past the bottom: the stack moves up (not past the top).
    if let Some(&last) = out.last() {
        let over = last - (height - pitch);
        if over > 0.0 {
            let room = out
                .first()
                .map_or(0.0, |&first| (first - 0.5 * pitch).max(0.0));
            let shift = over.min(room);
            for y in &mut out {
                *y -= shift;
            }
            // Keep the pitch where the shift squeezed the top.
            for i in 1..out.len() {
                out[i] = out[i].max(out[i - 1] + pitch);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Projection;
    use cadre_mesh::scene::{SceneMesh, SceneNode};

    fn cube(name: &str) -> SceneMesh {
        SceneMesh {
            name: name.to_string(),
            positions: vec![[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.4, 0.5, 0.5]],
            ..SceneMesh::default()
        }
    }

    #[test]
    fn every_named_part_gets_an_anchor_on_its_surface() {
        let mut scene = Scene::new("mm");
        scene.meshes = vec![cube("Bolt"), cube(""), cube("")];
        scene.nodes = vec![
            SceneNode {
                name: "Base plate".into(),
                mesh: Some(0),
                ..SceneNode::default()
            },
            SceneNode {
                mesh: Some(0),
                transform: glam::DAffine3::from_translation(DVec3::new(10.0, 0.0, 0.0)),
                ..SceneNode::default()
            },
            // Unnamed node, unnamed mesh: no label.
            SceneNode {
                mesh: Some(1),
                transform: glam::DAffine3::from_translation(DVec3::new(0.0, 10.0, 0.0)),
                ..SceneNode::default()
            },
            // A named product whose unnamed representation holds the mesh.
            SceneNode {
                name: "Nut".into(),
                children: vec![4],
                ..SceneNode::default()
            },
            SceneNode {
                mesh: Some(2),
                ..SceneNode::default()
            },
        ];
        scene.roots = vec![0, 1, 2, 3];
        let anchors = part_anchors(&scene);
        let names: Vec<&str> = anchors.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(names, ["Base plate", "Bolt", "Nut"]);
        // The vertex nearest the part's middle, placed.
        assert!(anchors[1].point.distance(DVec3::new(10.4, 0.5, 0.5)) < 1e-6);
    }

    /// Looking down −z at the origin, 150 units of the scene high.
    fn looking_down() -> Camera {
        Camera {
            eye: DVec3::new(0.0, 0.0, 100.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            projection: Projection::Orthographic { height: 150.0 },
            near: 1.0,
            far: 200.0,
        }
    }

    #[test]
    fn callouts_stack_in_two_columns_without_overlap() {
        // Twenty parts in a row along x, seen from above: ten left, ten right of the middle.
        let anchors: Vec<PartAnchor> = (0..20)
            .map(|i| PartAnchor {
                name: format!("part {i}"),
                point: DVec3::new(f64::from(i) * 5.0 - 47.5, 0.0, 0.0),
                style: CalloutStyle::PART,
            })
            .collect();
        let camera = looking_down();
        let set = callout_labels(&anchors, None, &camera, (400, 300), 10.0);
        assert_eq!(set.labels.len(), 20);
        let projector = Projector::new(&camera, (400, 300));
        let mut boxes = Vec::new();
        for label in &set.labels {
            let TextAnchor::Billboard { point, offset } = label.anchor else {
                panic!("billboard expected");
            };
            let (x, y) = projector.pixel(point).expect("in front");
            let at = (x + f64::from(offset.x), y + f64::from(offset.y));
            // Left column right-aligned left of the parts, right column the other way.
            match label.align {
                Align::Right => assert!(at.0 < x),
                _ => assert!(at.0 > x),
            }
            assert!(at.1 >= 0.0 && at.1 <= 300.0, "on the image: {at:?}");
            boxes.push((label.align, at.1));
        }
        for side in [Align::Left, Align::Right] {
            let mut ys: Vec<f64> = boxes.iter().filter(|b| b.0 == side).map(|b| b.1).collect();
            ys.sort_by(f64::total_cmp);
            assert_eq!(ys.len(), 10);
            // Boxes 10 / 0.714 × (1.069 + 0.293 + 0.4) + 1 ≈ 25.7 px tall.
            assert!(ys.windows(2).all(|w| w[1] - w[0] >= 25.0), "{ys:?}");
        }
    }

    #[test]
    fn long_callouts_stay_whole_on_the_image() {
        // Two long frames for parts near the image's sides.
        let text = "⌖ | ⌀0.1 Ⓜ | A | B | C — a long feature control frame";
        let anchors: Vec<PartAnchor> = [-90.0, 90.0]
            .iter()
            .map(|&x| PartAnchor {
                name: text.to_string(),
                point: DVec3::new(x, 0.0, 0.0),
                style: CalloutStyle::PMI,
            })
            .collect();
        let camera = looking_down();
        let set = callout_labels(&anchors, None, &camera, (400, 300), 10.0);
        let l = cadre_text::layout(
            cadre_text::FontChain::bundled(),
            cadre_text::Shaper::bundled(),
            text,
            (Align::Left, Baseline::Middle),
            1.0,
        );
        let em = f64::from(10.0 / cadre_text::FontChain::bundled().primary().cap_height);
        let width = f64::from(l.max.x - l.min.x + 2.0 * super::super::BOX_MARGIN) * em;
        assert!(width > 200.0, "{width}: longer than half the image");
        let projector = Projector::new(&camera, (400, 300));
        for label in &set.labels {
            let TextAnchor::Billboard { point, offset } = label.anchor else {
                panic!("billboard expected");
            };
            let x = projector.pixel(point).expect("in front").0 + f64::from(offset.x);
            let (left, right) = match label.align {
                Align::Right => (x - width, x),
                _ => (x, x + width),
            };
            assert!(left >= 0.0 && right <= 400.0, "{left}..{right}");
        }
        assert_eq!(set.labels.len(), 2);
    }

    #[test]
    fn a_column_keeps_what_fits_and_counts_the_rest() {
        // Two hundred parts: a 300 px column holds 11 boxes of 25.7 px.
        let anchors: Vec<PartAnchor> = (0..200)
            .map(|i| PartAnchor {
                name: format!("part {i}"),
                point: DVec3::new(f64::from(i) * 0.5 - 49.75, f64::from(i % 7), 0.0),
                style: CalloutStyle::PART,
            })
            .collect();
        let camera = looking_down();
        let out = lay_out_callouts(&anchors, None, &camera, (400, 300), 10.0);
        assert_eq!(out.labels.labels.len(), 22);
        assert_eq!(out.omitted, 200 - 22);
        let projector = Projector::new(&camera, (400, 300));
        for side in [Align::Left, Align::Right] {
            let mut ys: Vec<f64> = out
                .labels
                .labels
                .iter()
                .filter(|l| l.align == side)
                .map(|l| {
                    let TextAnchor::Billboard { point, offset } = l.anchor else {
                        panic!("billboard expected");
                    };
                    projector.pixel(point).expect("in front").1 + f64::from(offset.y)
                })
                .collect();
            ys.sort_by(f64::total_cmp);
            assert!(ys.windows(2).all(|w| w[1] - w[0] >= 25.0), "{ys:?}");
            assert!(ys.iter().all(|&y| (0.0..=300.0).contains(&y)), "{ys:?}");
        }
        // Negative control: twenty fit whole.
        let few = lay_out_callouts(&anchors[..20], None, &camera, (400, 300), 10.0);
        assert_eq!((few.labels.labels.len(), few.omitted), (20, 0));
    }

    #[test]
    fn a_crowded_column_moves_up_to_stay_on_the_image() {
        let ys = spread(&[280.0, 285.0, 290.0], 20.0, 300.0);
        assert_eq!(ys.len(), 3);
        assert!(ys[2] <= 280.0 + 1e-9 && ys[1] - ys[0] >= 20.0 && ys[2] - ys[1] >= 20.0);
    }
}
