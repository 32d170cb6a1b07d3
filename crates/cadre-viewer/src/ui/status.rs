//! The status bar: loading progress or the model's summary, warnings, the hovered item, the
//! 3D mouse and the frame time.

use cadre_render::Pick;

use crate::document::Document;
use crate::session::Session;

/// The status bar; returns its rectangle.
pub(super) fn status_bar(ui: &mut egui::Ui, s: &mut Session) -> egui::Rect {
    egui::Panel::bottom("status")
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                if let Some((path, stage)) = &s.loading {
                    ui.label(format!(
                        "Loading {}: {}",
                        path.file_name()
                            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                        stage.label()
                    ));
                    ui.add(
                        egui::ProgressBar::new(stage.fraction())
                            .desired_width(240.0)
                            .show_percentage(),
                    );
                } else {
                    ui.label(&s.status);
                }
                if let Some(doc) = &s.doc
                    && !doc.warnings.is_empty()
                    && ui
                        .link(format!("{} warnings", doc.warnings.len()))
                        .clicked()
                {
                    s.show_warnings = true;
                }
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    ui.label(format!("{:.1} ms", s.frame_ms));
                    if let Some(m) = &s.spacemouse {
                        ui.label(m);
                    }
                    if let (Some(h), Some(doc)) = (&s.hover, &s.doc) {
                        ui.label(pick_label(doc, h.pick));
                    }
                });
            });
        })
        .response
        .rect
}

/// A short name for a picked item, with its STEP id.
fn pick_label(doc: &Document, pick: Pick) -> String {
    let step = doc.step_label(pick);
    match pick {
        Pick::Face { instance, .. } => format!("part {instance} · face {step}"),
        Pick::Edge { instance, .. } => format!("part {instance} · edge {step}"),
        Pick::Vertex { instance, .. } => format!("part {instance} · vertex {step}"),
        Pick::Part { instance } => format!("part {instance}"),
    }
}
