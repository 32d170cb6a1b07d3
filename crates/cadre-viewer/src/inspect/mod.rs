//! What the properties panel and the measurement tools say about picked items, from the
//! exact B-Rep (lengths along curves, radii of surfaces, areas on the exact surface), placed
//! in the world by the picked instance.

mod format;
pub mod min_distance;

use cadre_brep::measure::{angle_between_faces, edge_properties, face_properties};
use cadre_render::Pick;
use glam::DVec3;

use crate::document::Document;

/// A measurement tool: what it needs picked and what it reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Minimum distance between two picked entities (faces, edges, vertices).
    Distance,
    /// Length of a picked edge.
    EdgeLength,
    /// Radius and diameter of a picked cylinder, sphere, circle or arc.
    Radius,
    /// Angle between two picked planar faces.
    Angle,
}

impl Tool {
    /// Every tool, for menus.
    pub const ALL: [Tool; 4] = [Tool::Distance, Tool::EdgeLength, Tool::Radius, Tool::Angle];

    /// Its name in the UI.
    pub fn name(self) -> &'static str {
        match self {
            Tool::Distance => "Distance",
            Tool::EdgeLength => "Edge length",
            Tool::Radius => "Radius / diameter",
            Tool::Angle => "Angle between planes",
        }
    }

    /// How many picks it takes.
    pub fn picks(self) -> usize {
        match self {
            Tool::Distance | Tool::Angle => 2,
            Tool::EdgeLength | Tool::Radius => 1,
        }
    }
}

/// A picked item with the world point where it was picked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Picked {
    /// The item.
    pub pick: Pick,
    /// World point under the cursor (on the surface, or the vertex itself).
    pub point: DVec3,
}

/// A finished measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The tool.
    pub tool: Tool,
    /// Its value: mm, or radians for angles.
    pub value: f64,
    /// What it shows, e.g. "Distance 12.500 mm (dx 3.000, dy …)".
    pub text: String,
    /// World points its dimension is drawn through, as
    /// `cadre_render::dimensions::shape` reads them for its kind (may be empty).
    pub points: Vec<DVec3>,
}

/// The world position of vertex `pick` (exact, from the model), if it is one.
pub fn vertex_position(doc: &Document, pick: Pick) -> Option<DVec3> {
    let Pick::Vertex { instance, vertex } = pick else {
        return None;
    };
    let v = doc.vertex(vertex)?;
    let world = doc.instances.get(instance as usize)?.world;
    Some(world.transform_point3(doc.model.vertices.get(v.index())?.point))
}

/// The world plane (a point on it, outward unit normal) of a picked planar face.
pub fn world_plane(doc: &Document, pick: Pick) -> Option<(DVec3, DVec3)> {
    let Pick::Face { instance, face } = pick else {
        return None;
    };
    // The plane alone: the sections window asks for it every frame.
    let plane = cadre_brep::measure::face_plane(&doc.model, doc.face(face)?)?;
    let world = doc.instances.get(instance as usize)?.world;
    let normal = (world.matrix3.inverse().transpose() * plane.normal).normalize_or_zero();
    (normal != DVec3::ZERO).then(|| (world.transform_point3(plane.origin), normal))
}

/// Rows for the properties panel: the part, then the picked item's own properties.
pub fn properties(doc: &Document, pick: Pick) -> Vec<(String, String)> {
    let instance = pick.instance() as usize;
    let mut rows = Vec::new();
    if let Some(info) = doc.instances.get(instance) {
        rows.push(("Part".to_string(), info.name.clone()));
    }
    match pick {
        Pick::Face { instance, face } => {
            rows.push(("Face".into(), doc.step_label(pick)));
            if let Some(f) = doc.face(face) {
                if let Some(p) = face_properties(&doc.model, f) {
                    rows.extend(format::face_rows(&face_in_world(p, doc, instance as usize)));
                }
                if let Some(Some(fm)) = doc.mesh.faces.get(f.index()) {
                    let area = cadre_mesh::face_area::face_area(&doc.model, f, fm);
                    let scale = scale_of(doc, instance as usize);
                    rows.push(("Area".into(), format!("{:.4} mm²", area * scale * scale)));
                }
            }
        }
        Pick::Edge { instance, edge } => {
            rows.push(("Edge".into(), doc.step_label(pick)));
            if let Some(e) = doc.edge(edge)
                && let Some(p) = edge_properties(&doc.model, e)
            {
                rows.extend(format::edge_rows(&edge_in_world(p, doc, instance as usize)));
            }
        }
        Pick::Vertex { .. } => {
            rows.push(("Vertex".into(), doc.step_label(pick)));
            if let Some(p) = vertex_position(doc, pick) {
                rows.push((
                    "Position".into(),
                    format!("({:.4}, {:.4}, {:.4}) mm", p.x, p.y, p.z),
                ));
            }
        }
        Pick::Part { instance } => {
            if let Some((lo, hi)) = doc.instance_bounds(instance as usize) {
                let d = hi - lo;
                rows.push((
                    "Size".into(),
                    format!("{:.3} × {:.3} × {:.3} mm", d.x, d.y, d.z),
                ));
            }
        }
    }
    rows
}

/// A placement's maps for points, directions and lengths.
struct Placement {
    world: glam::DAffine3,
    scale: f64,
}

impl Placement {
    fn of(doc: &Document, instance: usize) -> Placement {
        Placement {
            world: doc
                .instances
                .get(instance)
                .map_or(glam::DAffine3::IDENTITY, |i| i.world),
            scale: scale_of(doc, instance),
        }
    }

    fn point(&self, p: DVec3) -> DVec3 {
        self.world.transform_point3(p)
    }

    fn direction(&self, d: DVec3) -> DVec3 {
        self.world.transform_vector3(d).normalize_or_zero()
    }

    /// Normals turn by the inverse transpose (a mirror keeps them outward).
    fn normal(&self, n: DVec3) -> DVec3 {
        (self.world.matrix3.inverse().transpose() * n).normalize_or_zero()
    }

    fn axis(&self, a: cadre_brep::measure::Axis) -> cadre_brep::measure::Axis {
        cadre_brep::measure::Axis {
            origin: self.point(a.origin),
            direction: self.direction(a.direction),
        }
    }
}

/// A face's properties placed by `instance`: points, axes and normals in world coordinates,
/// lengths scaled (the panel shows what the user sees, not the part's own frame).
fn face_in_world(
    mut p: cadre_brep::measure::FaceProperties,
    doc: &Document,
    instance: usize,
) -> cadre_brep::measure::FaceProperties {
    let t = Placement::of(doc, instance);
    p.radius = p.radius.map(|r| r * t.scale);
    p.major_radius = p.major_radius.map(|r| r * t.scale);
    p.minor_radius = p.minor_radius.map(|r| r * t.scale);
    p.offset = p.offset.map(|o| o * t.scale);
    p.apex = p.apex.map(|a| t.point(a));
    p.centre = p.centre.map(|c| t.point(c));
    p.axis = p.axis.map(|a| t.axis(a));
    p.direction = p.direction.map(|d| t.world.transform_vector3(d));
    p.plane = p.plane.map(|pl| cadre_brep::measure::Plane {
        origin: t.point(pl.origin),
        normal: t.normal(pl.normal),
    });
    p
}

/// An edge's properties placed by `instance` (see [`face_in_world`]).
fn edge_in_world(
    mut p: cadre_brep::measure::EdgeProperties,
    doc: &Document,
    instance: usize,
) -> cadre_brep::measure::EdgeProperties {
    let t = Placement::of(doc, instance);
    p.length = p.length.map(|l| l * t.scale);
    p.radius = p.radius.map(|r| r * t.scale);
    p.semi_axes = p.semi_axes.map(|(a, b)| (a * t.scale, b * t.scale));
    p.start = t.point(p.start);
    p.end = t.point(p.end);
    p.centre = p.centre.map(|c| t.point(c));
    p.axis = p.axis.map(|a| t.axis(a));
    p.direction = p.direction.map(|d| t.direction(d));
    p
}

/// Uniform scale of an instance's placement (1 for rigid placements).
fn scale_of(doc: &Document, instance: usize) -> f64 {
    doc.instances
        .get(instance)
        .map_or(1.0, |i| i.world.matrix3.determinant().abs().cbrt())
}

/// Runs `tool` on `picks` (as many as it takes); `Err` says what is wrong with them.
pub fn measure(doc: &Document, tool: Tool, picks: &[Picked]) -> Result<Measurement, String> {
    match (tool, picks) {
        (Tool::Distance, [a, b]) => {
            let picked = (
                vertex_position(doc, a.pick).unwrap_or(a.point),
                vertex_position(doc, b.pick).unwrap_or(b.point),
            );
            // The entities' minimum distance; the clicked points for what has no geometry.
            let (length, pa, pb, what) = match min_distance::min_distance(doc, a.pick, b.pick) {
                Some((d, pa, pb)) => (d, pa, pb, "Minimum distance"),
                None => (
                    picked.0.distance(picked.1),
                    picked.0,
                    picked.1,
                    "Distance between the picked points",
                ),
            };
            let d = pb - pa;
            Ok(Measurement {
                tool,
                value: length,
                text: format!(
                    "{what} {length:.4} mm (dx {:.4}, dy {:.4}, dz {:.4})",
                    d.x, d.y, d.z
                ),
                points: vec![pa, pb],
            })
        }
        (Tool::EdgeLength, [a]) => {
            let Pick::Edge { instance, edge } = a.pick else {
                return Err("pick an edge".into());
            };
            let e = doc
                .edge(edge)
                .ok_or_else(|| format!("edge {} is not in the model", doc.step_label(a.pick)))?;
            let p = edge_properties(&doc.model, e).ok_or("the edge has no geometry")?;
            let length = p.length.ok_or("the edge's curve does not evaluate")?
                * scale_of(doc, instance as usize);
            // The dimension follows the edge: its samples, placed.
            let points = {
                use cadre_brep::trim::EdgeSamples;
                let t = Placement::of(doc, instance as usize);
                doc.mesh
                    .edges
                    .samples(e)
                    .iter()
                    .map(|s| t.point(DVec3::new(s.xyz.x, s.xyz.y, s.xyz.z)))
                    .collect()
            };
            Ok(Measurement {
                tool,
                value: length,
                text: format!(
                    "Edge {}: length {length:.4} mm ({})",
                    doc.step_label(a.pick),
                    p.kind
                ),
                points,
            })
        }
        (Tool::Radius, [a]) => {
            let instance = a.pick.instance() as usize;
            // The radius, its centre and axis in the world, and whether it is a circle's
            // (the picked point is taken into its plane) or a surface's.
            let (radius, centre, axis, circle, what) = match a.pick {
                Pick::Face { face, .. } => {
                    let f = doc.face(face).ok_or("face not in the model")?;
                    let p = face_properties(&doc.model, f).ok_or("the face has no surface")?;
                    let what = format!("Face {} ({})", doc.step_label(a.pick), p.kind);
                    let p = face_in_world(p, doc, instance);
                    (p.radius, p.centre, p.axis, false, what)
                }
                Pick::Edge { edge, .. } => {
                    let e = doc.edge(edge).ok_or("edge not in the model")?;
                    let p = edge_properties(&doc.model, e).ok_or("the edge has no geometry")?;
                    let what = format!("Edge {} ({})", doc.step_label(a.pick), p.kind);
                    let p = edge_in_world(p, doc, instance);
                    (p.radius, p.centre, p.axis, true, what)
                }
                _ => return Err("pick a cylinder, sphere, circle or arc".into()),
            };
            let r = radius.ok_or(format!("{what} has no radius"))?;
            Ok(Measurement {
                tool,
                value: r,
                text: format!("{what}: radius {r:.4} mm, diameter {:.4} mm", 2.0 * r),
                points: radius_points(centre, axis, circle, r, a.point),
            })
        }
        (Tool::Angle, [a, b]) => {
            let face_of = |p: Pick| match p {
                Pick::Face { face, instance } => doc.face(face).map(|f| (f, instance as usize)),
                _ => None,
            };
            let ((fa, ia), (fb, ib)) = face_of(a.pick)
                .zip(face_of(b.pick))
                .ok_or("pick two planar faces")?;
            let angle =
                angle_between_faces(&doc.model, fa, fb).ok_or("both faces must be planar")?;
            // Normals in the world: each turned by its own instance's placement.
            let normal = |n: DVec3, i: usize| {
                doc.instances
                    .get(i)
                    .map_or(n, |info| info.world.matrix3.inverse().transpose() * n)
                    .normalize_or_zero()
            };
            let (na, nb) = (normal(angle.normal_a, ia), normal(angle.normal_b, ib));
            let between = na.dot(nb).clamp(-1.0, 1.0).acos();
            let planes = between.min(std::f64::consts::PI - between);
            let mut text = format!(
                "Angle between planes {:.4}° (normals {:.4}°)",
                planes.to_degrees(),
                between.to_degrees()
            );
            if ia == ib
                && let Some(interior) = angle.interior
            {
                text.push_str(&format!(
                    ", through the material {:.4}°",
                    interior.to_degrees()
                ));
            }
            let points = match (world_plane(doc, a.pick), world_plane(doc, b.pick)) {
                (Some(pa), Some(pb)) => angle_points(pa, pb, (a.point, b.point), planes),
                _ => vec![a.point, b.point],
            };
            Ok(Measurement {
                tool,
                value: planes,
                text,
                points,
            })
        }
        _ => Err(format!("{} takes {} pick(s)", tool.name(), tool.picks())),
    }
}

/// The points a radius dimension is drawn through (`[centre, at, centre + axis]`, the last
/// when there is an axis): the centre nearest `picked` (on the axis of a cylinder), and the
/// point at `r` from it towards `picked` — in the circle's plane for a `circle`. Empty when
/// neither centre nor axis is known or `picked` is at the centre.
fn radius_points(
    centre: Option<DVec3>,
    axis: Option<cadre_brep::measure::Axis>,
    circle: bool,
    r: f64,
    picked: DVec3,
) -> Vec<DVec3> {
    let c = match (centre, axis) {
        (Some(c), _) => c,
        (None, Some(ax)) => ax.origin + ax.direction * (picked - ax.origin).dot(ax.direction),
        (None, None) => return Vec::new(),
    };
    let mut radial = picked - c;
    if let (true, Some(ax)) = (circle, axis) {
        radial -= ax.direction * radial.dot(ax.direction);
    }
    let Some(out) = radial.try_normalize() else {
        return Vec::new();
    };
    let mut points = vec![c, c + out * r];
    if let Some(ax) = axis {
        points.push(c + ax.direction);
    }
    points
}

/// The points an angle dimension between two planes (each a point on it and its normal) is
/// drawn through, `[vertex, a, b]`: the vertex on their line nearest the middle of the picked
/// points, and the arc's ends at the nearer pick's distance, each in its plane on its pick's
/// side — the second turned over the line when the half-planes make the supplement of
/// `angle` (the arc then shows the angle between the first face and the second one's
/// extension). Parallel planes, or picks on the line, give the picked points.
fn angle_points(
    (oa, na): (DVec3, DVec3),
    (ob, nb): (DVec3, DVec3),
    (pa, pb): (DVec3, DVec3),
    angle: f64,
) -> Vec<DVec3> {
    let line = na.cross(nb);
    let Some(along) = line.try_normalize() else {
        return vec![pa, pb];
    };
    // A point of both planes, then the one nearest the picks' middle.
    let (da, db) = (na.dot(oa), nb.dot(ob));
    let x0 = (nb.cross(line) * da + line.cross(na) * db) / line.length_squared();
    let middle = 0.5 * (pa + pb);
    let vertex = x0 + along * (middle - x0).dot(along);
    let off_line = |p: DVec3| {
        let d = p - vertex;
        d - along * d.dot(along)
    };
    let (ra, rb) = (off_line(pa), off_line(pb));
    let (Some(ua), Some(mut ub)) = (ra.try_normalize(), rb.try_normalize()) else {
        return vec![pa, pb];
    };
    let drawn = ua.dot(ub).clamp(-1.0, 1.0).acos();
    if (std::f64::consts::PI - drawn - angle).abs() < (drawn - angle).abs() {
        ub = -ub;
    }
    let r = ra.length().min(rb.length());
    vec![vertex, vertex + ua * r, vertex + ub * r]
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_brep::{EdgeId, FaceId};
    use cadre_mesh::scene::SceneIds;
    use std::path::Path;

    fn doc(name: &str) -> Document {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let path = [
            root.join("examples").join(name),
            root.join("crates/cadre-render/tests/data").join(name),
        ]
        .into_iter()
        .find(|p| p.is_file())
        .expect("fixture");
        Document::load(&path, &|_| {}).expect("loads")
    }

    fn pick_of(doc: &Document, pick: Pick) -> Picked {
        Picked {
            pick,
            point: doc.bounds.map_or(DVec3::ZERO, |(lo, _)| lo),
        }
    }

    #[test]
    fn a_pins_cylinder_reports_its_radius_area_and_edge_lengths() {
        let doc = doc("pin-assembly.step");
        // Every cylindrical face's radius, and a circle edge's length 2πr.
        let mut cylinders = 0;
        for k in 0..doc.model.faces.len() {
            let f = FaceId(k as u32);
            let Some(p) = face_properties(&doc.model, f) else {
                continue;
            };
            let Some(r) = p.radius else { continue };
            cylinders += 1;
            let pick = Pick::Face {
                instance: 0,
                face: SceneIds::face_id(f),
            };
            let m = measure(&doc, Tool::Radius, &[pick_of(&doc, pick)]).expect("radius");
            assert!(
                (m.value - r).abs() < 1e-12 && m.text.contains("diameter"),
                "{m:?}"
            );
            // Its dimension runs from the axis to the surface, a radius long, square to
            // the axis (the third point: the centre moved along it).
            let [c, at, ax] = m.points[..] else {
                panic!("{m:?}")
            };
            assert!((c.distance(at) - r).abs() < 1e-9, "{m:?}");
            assert!((at - c).dot(ax - c).abs() < 1e-9, "{m:?}");
            let rows = properties(&doc, pick);
            assert!(
                rows.iter().any(|(k, v)| k == "Area" && v.ends_with("mm²")),
                "{rows:?}"
            );
            assert!(rows.iter().any(|(k, _)| k == "Part"), "{rows:?}");
        }
        assert!(cylinders > 0);
        let circle = (0..doc.model.edges.len() as u32)
            .map(EdgeId)
            .find(|&e| {
                edge_properties(&doc.model, e).is_some_and(|p| p.radius.is_some() && p.closed)
            })
            .expect("a full circle");
        let pick = Pick::Edge {
            instance: 0,
            edge: SceneIds::edge_id(circle),
        };
        let p = edge_properties(&doc.model, circle).unwrap();
        let m = measure(&doc, Tool::EdgeLength, &[pick_of(&doc, pick)]).expect("length");
        let expected = 2.0 * std::f64::consts::PI * p.radius.unwrap();
        assert!(
            (m.value - expected).abs() < 1e-6 * expected,
            "{} vs {expected}",
            m.value
        );
        // The length's dimension follows the circle: its samples, a radius from the centre.
        let centre = doc.instances[0].world.transform_point3(p.centre.unwrap());
        assert!(m.points.len() > 8, "{}", m.points.len());
        for q in &m.points {
            assert!((q.distance(centre) - p.radius.unwrap()).abs() < 1e-6, "{q}");
        }
        // A circle's radius dimension stays in its plane whatever point was picked.
        let m = measure(&doc, Tool::Radius, &[pick_of(&doc, pick)]).expect("radius");
        let axis = edge_in_world(p.clone(), &doc, 0).axis.unwrap();
        assert!(((m.points[1] - m.points[0]).dot(axis.direction)).abs() < 1e-9);
    }

    #[test]
    fn radius_points_go_from_the_centre_towards_the_pick() {
        let axis = cadre_brep::measure::Axis {
            origin: DVec3::new(0.0, 0.0, -5.0),
            direction: DVec3::Z,
        };
        // A cylinder of radius 2 about z, picked at (0, 3, 7): centre (0, 0, 7), at (0, 2, 7).
        let p = radius_points(None, Some(axis), false, 2.0, DVec3::new(0.0, 3.0, 7.0));
        assert_eq!(
            p,
            vec![
                DVec3::new(0.0, 0.0, 7.0),
                DVec3::new(0.0, 2.0, 7.0),
                DVec3::new(0.0, 0.0, 8.0)
            ]
        );
        // A circle centred at the origin: the pick above its plane is taken into it.
        let p = radius_points(
            Some(DVec3::ZERO),
            Some(axis),
            true,
            2.0,
            DVec3::new(3.0, 0.0, 4.0),
        );
        assert_eq!(p[1], DVec3::new(2.0, 0.0, 0.0));
        // A sphere (a centre, no axis): towards the pick in space.
        let p = radius_points(
            Some(DVec3::ZERO),
            None,
            false,
            5.0,
            DVec3::new(0.0, 6.0, 8.0),
        );
        assert_eq!(p.len(), 2);
        assert!(p[1].distance(DVec3::new(0.0, 3.0, 4.0)) < 1e-12, "{p:?}");
        // Nothing to go by, or the pick at the centre: no points.
        assert!(radius_points(None, None, false, 1.0, DVec3::X).is_empty());
        assert!(radius_points(Some(DVec3::ZERO), None, false, 1.0, DVec3::ZERO).is_empty());
    }

    #[test]
    fn an_angles_arc_spans_the_angle_it_reports() {
        let deg = |p: &[DVec3]| {
            let (a, b) = (p[1] - p[0], p[2] - p[0]);
            a.angle_between(b).to_degrees()
        };
        // A block's top (z = 0, normal +z) and its side (x = 0, normal +x), picked on each:
        // the arc spans their 90° about the shared edge, at the nearer pick's distance.
        let top = (DVec3::ZERO, DVec3::Z);
        let side = (DVec3::ZERO, DVec3::X);
        let p = angle_points(
            top,
            side,
            (DVec3::new(-3.0, 1.0, 0.0), DVec3::new(0.0, 1.0, -2.0)),
            std::f64::consts::FRAC_PI_2,
        );
        assert!((deg(&p) - 90.0).abs() < 1e-9);
        assert!(p[0].distance(DVec3::new(0.0, 1.0, 0.0)) < 1e-12, "{p:?}");
        assert!(p[1].distance(DVec3::new(-2.0, 1.0, 0.0)) < 1e-12, "{p:?}");
        assert!(p[2].distance(DVec3::new(0.0, 1.0, -2.0)) < 1e-12, "{p:?}");
        // A 45° chamfer on the top's edge: the half-planes the picks are on make 135°; the
        // measured angle is 45°, so the arc runs to the chamfer's extension past the edge.
        let chamfer = (DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0).normalize());
        let p = angle_points(
            top,
            chamfer,
            (DVec3::new(-3.0, 0.0, 0.0), DVec3::new(1.0, 0.0, -1.0)),
            std::f64::consts::FRAC_PI_4,
        );
        assert!((deg(&p) - 45.0).abs() < 1e-9, "{p:?}");
        // Negative control: kept at the half-planes, the same arc would span 135°.
        let kept = angle_points(
            top,
            chamfer,
            (DVec3::new(-3.0, 0.0, 0.0), DVec3::new(1.0, 0.0, -1.0)),
            3.0 * std::f64::consts::FRAC_PI_4,
        );
        assert!((deg(&kept) - 135.0).abs() < 1e-9, "{kept:?}");
        // Parallel planes: the picked points.
        let picks = (DVec3::X, DVec3::Y);
        assert_eq!(
            angle_points(top, (DVec3::Z, DVec3::Z), picks, 0.0),
            vec![DVec3::X, DVec3::Y]
        );
    }

    #[test]
    fn properties_are_shown_where_the_instance_places_them() {
        let doc = doc("pin-assembly.step");
        assert!(doc.instances.len() >= 2);
        let (a, b) = (doc.instances[0].world, doc.instances[1].world);
        assert!(
            (a.translation - b.translation).length() > 1e-6,
            "the pins are apart"
        );
        let face = (0..doc.model.faces.len() as u32)
            .map(FaceId)
            .find(|&f| {
                face_properties(&doc.model, f)
                    .is_some_and(|p| p.axis.is_some() && p.radius.is_some())
            })
            .expect("a cylinder");
        let rows = |instance| {
            properties(
                &doc,
                Pick::Face {
                    instance,
                    face: SceneIds::face_id(face),
                },
            )
        };
        let get = |rows: &[(String, String)], key: &str| {
            rows.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone())
        };
        let (r0, r1) = (rows(0), rows(1));
        assert_eq!(get(&r0, "Radius"), get(&r1, "Radius"));
        assert!(get(&r0, "Axis origin").is_some(), "{r0:?}");
        assert_ne!(
            get(&r0, "Axis origin"),
            get(&r1, "Axis origin"),
            "{r0:?} {r1:?}"
        );
        // The shown origin is the part's axis origin placed by the instance.
        let p = face_properties(&doc.model, face).unwrap();
        let placed = face_in_world(p.clone(), &doc, 1).axis.unwrap().origin;
        assert!((placed - b.transform_point3(p.axis.unwrap().origin)).length() < 1e-12);
    }

    #[test]
    fn distance_between_vertices_is_exact_and_angles_need_planes() {
        let doc = doc("pin-assembly.step");
        let v: Vec<u32> = (0..doc.model.vertices.len() as u32)
            .map(|k| SceneIds::vertex_id(cadre_brep::VertexId(k)))
            .collect();
        assert!(v.len() >= 2);
        let (a, b) = (
            Pick::Vertex {
                instance: 0,
                vertex: v[0],
            },
            Pick::Vertex {
                instance: 1,
                vertex: v[1],
            },
        );
        let m = measure(&doc, Tool::Distance, &[pick_of(&doc, a), pick_of(&doc, b)]).unwrap();
        let expected =
            (vertex_position(&doc, b).unwrap() - vertex_position(&doc, a).unwrap()).length();
        assert!((m.value - expected).abs() < 1e-12);
        assert_eq!(m.points.len(), 2);
        // Planar faces: the pins' end caps are parallel (0°) or not planar at all.
        let planar: Vec<u32> = (0..doc.model.faces.len() as u32)
            .map(FaceId)
            .filter(|&f| face_properties(&doc.model, f).is_some_and(|p| p.plane.is_some()))
            .map(SceneIds::face_id)
            .collect();
        assert!(planar.len() >= 2);
        let fa = Pick::Face {
            instance: 0,
            face: planar[0],
        };
        let fb = Pick::Face {
            instance: 0,
            face: planar[1],
        };
        let m = measure(&doc, Tool::Angle, &[pick_of(&doc, fa), pick_of(&doc, fb)]).unwrap();
        assert!(m.value.abs() < 1e-9, "end caps are parallel: {}", m.text);
        // Wrong picks give a message, not a panic.
        assert!(measure(&doc, Tool::Angle, &[pick_of(&doc, a), pick_of(&doc, fb)]).is_err());
        assert!(measure(&doc, Tool::EdgeLength, &[pick_of(&doc, fa)]).is_err());
        assert!(measure(&doc, Tool::Distance, &[pick_of(&doc, fa)]).is_err());
    }

    #[test]
    fn step_ids_past_u32_are_shown_whole() {
        // The pin assembly with every id moved past 2³²: the panel shows the file's ids.
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let text = std::fs::read_to_string(root.join("examples/pin-assembly.step")).unwrap();
        let offset = (1u64 << 32) + 1000;
        let out = cadre_step::syntax::shift_entity_ids(&text, offset).unwrap();
        let path = std::env::temp_dir().join(format!("cadre-big-ids-{}.step", std::process::id()));
        std::fs::write(&path, out).unwrap();
        let doc = Document::load(&path, &|_| {}).expect("loads");
        let _ = std::fs::remove_file(&path);
        let face = FaceId(0);
        let step = doc.model.faces[0].step_id;
        assert!(step > u64::from(u32::MAX));
        let pick = Pick::Face {
            instance: 0,
            face: SceneIds::face_id(face),
        };
        let rows = properties(&doc, pick);
        assert!(
            rows.iter()
                .any(|(k, v)| k == "Face" && *v == format!("#{step}")),
            "{rows:?}"
        );
        let edge = Pick::Edge {
            instance: 0,
            edge: SceneIds::edge_id(EdgeId(0)),
        };
        assert_eq!(
            doc.step_label(edge),
            format!("#{}", doc.model.edges[0].step_id)
        );
    }
}
