//! The menu bar: File, View (presets, fits, projection, orbit style), Display, Measure.

use cadre_render::ViewPreset;

use super::Action;
use crate::inspect::Tool;
use crate::navigation::OrbitStyle;
use crate::session::{DISPLAY_MODES, Session};

/// The menu bar; returns its rectangle.
pub(super) fn menu_bar(
    ui: &mut egui::Ui,
    s: &mut Session,
    actions: &mut Vec<Action>,
) -> egui::Rect {
    egui::Panel::top("menu")
        .show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| {
                    if ui.button("Open…  (Ctrl+O)").clicked() {
                        s.show_open = true;
                    }
                    if ui
                        .add_enabled(s.toolpath.is_some(), egui::Button::new("Toolpath…"))
                        .clicked()
                    {
                        s.show_toolpath = true;
                    }
                    if ui.button("Screenshot…  (F12: quick)").clicked() {
                        s.show_screenshot = true;
                    }
                    if ui.button("Quit").clicked() {
                        actions.push(Action::Quit);
                    }
                });
                ui.menu_button("View", |ui| {
                    for (name, preset, key) in PRESETS {
                        if ui.button(format!("{name}  ({key})")).clicked() {
                            actions.push(Action::Preset(preset));
                        }
                    }
                    ui.separator();
                    if ui.button("Fit all  (F)").clicked() {
                        actions.push(Action::FitAll);
                    }
                    if ui.button("Fit selection  (Shift+F)").clicked() {
                        actions.push(Action::FitSelection);
                    }
                    if let Some(nav) = &mut s.nav {
                        ui.separator();
                        ui.checkbox(&mut nav.orthographic, "Orthographic  (O)");
                        ui.radio_value(&mut nav.style, OrbitStyle::Turntable, "Turntable orbit");
                        ui.radio_value(&mut nav.style, OrbitStyle::Trackball, "Trackball orbit");
                    }
                });
                ui.menu_button("Display", |ui| {
                    for (name, mode) in DISPLAY_MODES {
                        ui.radio_value(&mut s.mode, mode, name);
                    }
                    ui.separator();
                    ui.checkbox(&mut s.exact_faces, "Exact faces (GPU trimming)")
                        .on_hover_text(
                            "Faces drawn from their exact surfaces, tessellated to the \
                             screen each frame and trimmed per pixel, instead of their meshes",
                        );
                    ui.add_enabled(
                        s.exact_faces,
                        egui::Checkbox::new(&mut s.silhouette_fill, "Exact silhouettes"),
                    )
                    .on_hover_text(
                        "Once the camera stops, pixels a face's grid leaves short of its true \
                         silhouette are given the exact surface",
                    );
                    ui.checkbox(&mut s.shadows, "Shadows").on_hover_text(
                        "The key light casts shadows (a shadow map drawn each frame)",
                    );
                    ui.checkbox(&mut s.gradient, "Gradient background");
                    ui.checkbox(&mut s.grid, "Ground grid").on_hover_text(
                        "A grid on the plane under the model, its spacing following the zoom",
                    );
                    ui.separator();
                    ui.checkbox(&mut s.part_labels, "Part labels")
                        .on_hover_text("Part names in boxes beside the model, with leaders");
                    let has_pmi = s.doc.as_ref().is_some_and(|d| !d.model.pmi.is_empty());
                    ui.add_enabled(has_pmi, egui::Checkbox::new(&mut s.show_pmi, "PMI"))
                        .on_hover_text("The file's annotations and generated callouts");
                    if ui
                        .add_enabled(has_pmi, egui::Button::new("PMI and saved views…"))
                        .clicked()
                    {
                        s.show_pmi_window = true;
                    }
                });
                ui.menu_button("Measure", |ui| {
                    ui.label("Keys: D distance, L edge length, R radius, A angle");
                    for tool in Tool::ALL {
                        if ui.radio(s.tool == Some(tool), tool.name()).clicked() {
                            s.choose_tool(tool);
                        }
                    }
                    if ui.button("Stop measuring  (Esc)").clicked() {
                        s.stop_measuring();
                    }
                    if ui.button("Clear measurements").clicked() {
                        s.measurements.clear();
                        s.save_dimensions();
                    }
                });
            });
        })
        .response
        .rect
}

/// View presets with their keys.
const PRESETS: [(&str, ViewPreset, &str); 7] = [
    ("Iso", ViewPreset::Iso, "0"),
    ("Front", ViewPreset::Front, "1"),
    ("Back", ViewPreset::Back, "2"),
    ("Left", ViewPreset::Left, "3"),
    ("Right", ViewPreset::Right, "4"),
    ("Top", ViewPreset::Top, "5"),
    ("Bottom", ViewPreset::Bottom, "6"),
];
