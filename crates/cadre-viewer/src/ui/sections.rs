//! The section planes' part of the properties panel.

use crate::inspect;
use crate::session::{Section, Session};

/// Section planes: add (along an axis or a selected planar face), move, flip, remove.
pub(super) fn sections_ui(ui: &mut egui::Ui, s: &mut Session) {
    ui.heading("Sections");
    ui.horizontal(|ui| {
        let room = s.sections.len() < cadre_render::MAX_SECTIONS;
        for (name, normal) in [
            ("+X", glam::DVec3::X),
            ("+Y", glam::DVec3::Y),
            ("+Z", glam::DVec3::Z),
        ] {
            if ui.add_enabled(room, egui::Button::new(name)).clicked() {
                s.sections.push(Section {
                    enabled: true,
                    normal,
                    position: 0.5,
                });
            }
        }
        let face_normal = s
            .selection
            .first()
            .and_then(|p| s.doc.as_ref().and_then(|d| inspect::world_plane(d, p.pick)));
        if ui
            .add_enabled(
                room && face_normal.is_some(),
                egui::Button::new("From face"),
            )
            .on_hover_text("A plane through the selected planar face")
            .clicked()
            && let (Some((origin, normal)), Some((lo, hi))) =
                (face_normal, s.doc.as_ref().and_then(|d| d.bounds))
        {
            // The position that puts the plane through the face.
            let mut section = Section {
                enabled: true,
                normal: -normal,
                position: 0.0,
            };
            let (a, b) = (section.plane(lo, hi).offset, {
                section.position = 1.0;
                section.plane(lo, hi).offset
            });
            let d = (-normal).dot(origin);
            section.position = if (b - a).abs() > 1e-300 {
                (d - a) / (b - a)
            } else {
                0.5
            };
            s.sections.push(section);
        }
    });
    let mut remove = None;
    for (k, section) in s.sections.iter_mut().enumerate() {
        ui.horizontal(|ui| {
            ui.checkbox(&mut section.enabled, format!("{}", k + 1));
            ui.spacing_mut().slider_width = 120.0;
            ui.add(egui::Slider::new(&mut section.position, 0.0..=1.0).show_value(false));
            if ui.button("Flip").clicked() {
                section.normal = -section.normal;
                section.position = 1.0 - section.position;
            }
            if ui.button("✕").clicked() {
                remove = Some(k);
            }
        });
    }
    if let Some(k) = remove {
        s.sections.remove(k);
    }
}
