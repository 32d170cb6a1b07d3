//! The Toolpath window: the open program's summary and warnings, the simulation slider (the
//! path up to a distance along it, with the tool there), the colours, and the clipping box.

use cadre_render::lines::toolpath::ColourBy;

use crate::session::Session;

/// The window, when a toolpath is open and the window is shown.
pub(super) fn toolpath_window(ui: &mut egui::Ui, s: &mut Session) {
    let ctx = ui.ctx().clone();
    let Some(tp) = &mut s.toolpath else {
        return;
    };
    if !s.show_toolpath {
        return;
    }
    let mut open = true;
    egui::Window::new("Toolpath")
        .open(&mut open)
        .default_width(320.0)
        .show(&ctx, |ui| {
            let name = tp
                .path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            ui.label(format!(
                "{name}: {} moves, {:.1} mm of path (written in {})",
                tp.program.moves.len(),
                tp.travel,
                tp.program.program_units
            ));
            ui.separator();
            ui.checkbox(&mut tp.simulate, "Simulate: the path up to");
            ui.add_enabled(
                tp.simulate,
                egui::Slider::new(&mut tp.up_to, 0.0..=tp.travel.max(1e-9))
                    .suffix(" mm")
                    .clamping(egui::SliderClamping::Always),
            );
            ui.horizontal(|ui| {
                ui.label("Tool diameter");
                ui.add(
                    egui::DragValue::new(&mut tp.tool_diameter)
                        .range(0.01..=500.0)
                        .speed(0.1)
                        .suffix(" mm"),
                );
            });
            ui.separator();
            ui.horizontal(|ui| {
                ui.label("Colour cuts by");
                ui.radio_value(&mut tp.colour_by, ColourBy::Feed, "feed");
                ui.radio_value(&mut tp.colour_by, ColourBy::Tool, "tool");
                ui.radio_value(&mut tp.colour_by, ColourBy::Kind, "one colour");
            });
            ui.separator();
            ui.checkbox(&mut tp.clip, "Clip to a box (mm)");
            for (corner, name) in [(0, "min"), (1, "max")] {
                ui.horizontal(|ui| {
                    ui.label(name);
                    for axis in 0..3 {
                        ui.add_enabled(
                            tp.clip,
                            egui::DragValue::new(&mut tp.clip_box[corner][axis]).speed(0.5),
                        );
                    }
                });
            }
            if !tp.program.warnings.is_empty() {
                ui.separator();
                egui::CollapsingHeader::new(format!("{} warnings", tp.program.warnings.len()))
                    .show(ui, |ui| {
                        egui::ScrollArea::vertical()
                            .max_height(200.0)
                            .show(ui, |ui| {
                                for w in &tp.program.warnings {
                                    ui.label(format!("line {}: {}", w.line, w.message));
                                }
                            });
                    });
            }
        });
    s.show_toolpath = open;
}
