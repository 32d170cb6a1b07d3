//! The text of the properties panel: figures from [`cadre_brep::measure`] as (label, value)
//! rows, lengths in millimetres and angles in degrees, numbers with up to six decimals.

use cadre_brep::measure::{EdgeProperties, FaceProperties};
use glam::DVec3 as Vec3;

/// A face's properties `p` as (label, value) rows: lengths in mm, angles in degrees.
pub fn face_rows(p: &FaceProperties) -> Vec<(String, String)> {
    let mut rows = Rows::default();
    rows.push("Type", p.kind.name().to_string());
    if let Some((shape, deviation)) = p.recognised {
        rows.push(
            "Recognised",
            format!("{shape} (within {} mm)", sci(deviation)),
        );
    }
    rows.push("STEP id", format!("#{}", p.step_id));
    if let Some(r) = p.radius {
        rows.push("Radius", mm(r));
        rows.push("Diameter", mm(2.0 * r));
    }
    if let Some(a) = p.semi_angle {
        rows.push("Semi-angle", deg(a));
    }
    if let Some(apex) = p.apex {
        rows.push("Apex", point(apex));
    }
    if let Some(r) = p.major_radius {
        rows.push("Major radius", mm(r));
    }
    if let Some(r) = p.minor_radius {
        rows.push("Minor radius", mm(r));
    }
    if let Some(c) = p.centre {
        rows.push("Centre", point(c));
    }
    if let Some(a) = p.axis {
        rows.push("Axis origin", point(a.origin));
        rows.push("Axis direction", vector(a.direction));
    }
    if let Some(plane) = p.plane {
        rows.push("Plane origin", point(plane.origin));
        rows.push("Normal", vector(plane.normal));
    }
    if let Some(d) = p.direction {
        rows.push("Extrusion", vector(d));
    }
    if let Some(d) = p.offset {
        rows.push("Offset", mm(d));
    }
    rows.0
}

/// An edge's properties `p` as (label, value) rows: lengths in mm, angles in degrees.
pub fn edge_rows(p: &EdgeProperties) -> Vec<(String, String)> {
    let mut rows = Rows::default();
    rows.push("Type", p.kind.name().to_string());
    if let Some((shape, deviation)) = p.recognised {
        rows.push(
            "Recognised",
            format!("{shape} (within {} mm)", sci(deviation)),
        );
    }
    rows.push("STEP id", format!("#{}", p.step_id));
    rows.push("Length", p.length.map_or_else(|| "—".to_string(), mm));
    rows.push("Start", point(p.start));
    rows.push("End", point(p.end));
    if let Some(r) = p.radius {
        rows.push("Radius", mm(r));
        rows.push("Diameter", mm(2.0 * r));
    }
    if let Some((a, b)) = p.semi_axes {
        rows.push("Semi-axes", format!("{} × {} mm", num(a), num(b)));
    }
    if let Some(c) = p.centre {
        rows.push("Centre", point(c));
    }
    if let Some(a) = p.axis {
        rows.push("Axis", vector(a.direction));
    }
    if let Some(a) = p.arc_angle {
        rows.push("Arc angle", deg(a));
    }
    if let Some(d) = p.direction {
        rows.push("Direction", vector(d));
    }
    rows.0
}

/// Display rows under construction.
#[derive(Default)]
struct Rows(Vec<(String, String)>);

impl Rows {
    fn push(&mut self, label: &str, value: String) {
        self.0.push((label.to_string(), value));
    }
}

/// A number with up to six decimals, trailing zeros dropped.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        &s
    };
    if s == "-0" { "0".into() } else { s.into() }
}

/// A length in millimetres.
fn mm(x: f64) -> String {
    format!("{} mm", num(x))
}

/// An angle given in radians, shown in degrees.
fn deg(radians: f64) -> String {
    format!("{}°", num(radians.to_degrees()))
}

/// A point in millimetres.
/// A small figure in scientific notation (`2.5e-13`), 0 as `0`.
fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else {
        format!("{x:.1e}")
    }
}

fn point(p: Vec3) -> String {
    format!("({}, {}, {}) mm", num(p.x), num(p.y), num(p.z))
}

/// A direction.
fn vector(v: Vec3) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use cadre_brep::measure::{Axis, CurveKind, SurfaceKind};
    use cadre_brep::{EdgeId, FaceId};

    #[test]
    fn numbers_format_compactly() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.0000001), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(f64::INFINITY), "inf");
        assert_eq!(deg(std::f64::consts::FRAC_PI_4), "45°");
        assert_eq!(point(Vec3::new(1.0, -2.5, 0.0)), "(1, -2.5, 0) mm");
    }

    #[test]
    fn a_cylinder_shows_its_type_id_diameter_and_axis() {
        let p = FaceProperties {
            face: FaceId(0),
            step_id: 42,
            kind: SurfaceKind::Cylinder,
            reversed: false,
            radius: Some(4.0),
            semi_angle: None,
            apex: None,
            major_radius: None,
            minor_radius: None,
            centre: None,
            axis: Some(Axis {
                origin: Vec3::ZERO,
                direction: Vec3::Z,
            }),
            plane: None,
            direction: None,
            offset: None,
            recognised: None,
        };
        let rows = face_rows(&p);
        let row = |l: &str, v: &str| (l.to_string(), v.to_string());
        assert_eq!(rows[0], row("Type", "cylinder"));
        assert_eq!(rows[1], row("STEP id", "#42"));
        assert!(rows.contains(&row("Radius", "4 mm")));
        assert!(rows.contains(&row("Diameter", "8 mm")));
        assert!(rows.contains(&row("Axis direction", "(0, 0, 1)")));
        assert!(
            !rows
                .iter()
                .any(|(l, _)| l == "Semi-angle" || l == "Recognised")
        );
        // A B-spline found to be a cylinder says so, with how closely.
        let b = FaceProperties {
            kind: SurfaceKind::BSpline,
            recognised: Some(("cylinder", 2.5e-13)),
            ..p
        };
        let rows = face_rows(&b);
        assert_eq!(rows[1], row("Recognised", "cylinder (within 2.5e-13 mm)"));
        assert!(rows.contains(&row("Radius", "4 mm")));
    }

    #[test]
    fn an_arc_shows_its_length_and_angle_and_an_unknown_length_a_dash() {
        let mut p = EdgeProperties {
            edge: EdgeId(0),
            step_id: 7,
            kind: CurveKind::Circle,
            length: Some(std::f64::consts::PI),
            start: Vec3::X,
            end: Vec3::NEG_X,
            closed: false,
            range: Some((0.0, std::f64::consts::PI)),
            radius: Some(1.0),
            centre: Some(Vec3::ZERO),
            axis: None,
            arc_angle: Some(std::f64::consts::PI),
            semi_axes: None,
            direction: None,
            recognised: None,
        };
        let row = |l: &str, v: &str| (l.to_string(), v.to_string());
        let rows = edge_rows(&p);
        assert!(rows.contains(&row("Length", "3.141593 mm")));
        assert!(rows.contains(&row("Arc angle", "180°")));
        assert!(rows.contains(&row("Start", "(1, 0, 0) mm")));
        p.length = None;
        assert!(edge_rows(&p).contains(&row("Length", "—")));
    }
}
