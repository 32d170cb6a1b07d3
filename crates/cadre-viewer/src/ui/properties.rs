//! The properties panel.

use super::Action;
use crate::inspect::{self, Tool};
use crate::session::Session;

/// The properties of the selected items, their parts' colour and opacity, the measurement
/// tools and results, and the section planes.
pub(super) fn properties_panel(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
    ui.set_min_width(ui.available_width());
    ui.heading("Properties");
    let Some(doc) = &s.doc else { return };
    if s.properties.len() > 1024 {
        s.properties.clear();
    }
    for p in &s.selection {
        s.properties
            .entry(p.pick)
            .or_insert_with(|| inspect::properties(doc, p.pick));
    }
    if s.selection.is_empty() {
        ui.label("Click a face, edge or vertex (vertices first, then edges, within a few pixels); Ctrl+click adds.");
    }
    let mut part_styles: Vec<u32> = Vec::new();
    // Both ways: long values scroll instead of widening the panel.
    egui::ScrollArea::both()
        .auto_shrink([false, true])
        .max_height(ui.available_height() * 0.6)
        .show(ui, |ui| {
            for (k, p) in s.selection.iter().enumerate() {
                if k > 0 {
                    ui.separator();
                }
                egui::Grid::new(("props", k)).striped(true).show(ui, |ui| {
                    for (label, value) in s.properties.get(&p.pick).into_iter().flatten() {
                        ui.label(label);
                        ui.label(value);
                        ui.end_row();
                    }
                });
                part_styles.push(p.pick.instance());
            }
        });
    part_styles.dedup();
    for instance in part_styles {
        let i = instance as usize;
        ui.separator();
        ui.label(format!(
            "Part {}",
            doc.instances.get(i).map_or("", |x| x.name.as_str())
        ));
        let Some(slot) = s.colours.get_mut(i) else {
            continue;
        };
        let mut colour = slot.unwrap_or([0.62, 0.64, 0.66, 1.0]);
        let mut rgb = [colour[0], colour[1], colour[2]];
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.label("Colour");
            changed |= ui.color_edit_button_rgb(&mut rgb).changed();
            if ui.button("Reset").clicked() {
                *slot = None;
            }
        });
        ui.horizontal(|ui| {
            ui.label("Opacity");
            ui.spacing_mut().slider_width = 120.0;
            changed |= ui
                .add(egui::Slider::new(&mut colour[3], 0.05..=1.0))
                .changed();
        });
        if changed {
            colour[..3].copy_from_slice(&rgb);
            *slot = Some(colour);
        }
    }
    if !s.selection.is_empty() && ui.button("Fit selection").clicked() {
        actions.push(Action::FitSelection);
    }
    ui.separator();
    ui.heading("Measure");
    ui.horizontal_wrapped(|ui| {
        for tool in Tool::ALL {
            if ui
                .selectable_label(s.tool == Some(tool), tool.name())
                .clicked()
            {
                s.toggle_tool(tool);
            }
        }
    });
    if let Some(m) = &s.tool_message {
        ui.label(m);
    }
    // Newest first, each with its delete button (dimensions are kept beside the file).
    let mut delete = None;
    for (k, m) in s.measurements.iter().enumerate().rev() {
        ui.horizontal(|ui| {
            if ui
                .small_button("✕")
                .on_hover_text("Delete this dimension")
                .clicked()
            {
                delete = Some(k);
            }
            ui.label(&m.text);
        });
    }
    if let Some(k) = delete {
        s.delete_measurement(k);
    }
    ui.separator();
    super::sections::sections_ui(ui, s);
}
