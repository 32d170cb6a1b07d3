//! The PMI window: the model's annotations and saved views. Choosing a saved view turns the
//! camera to it and draws its annotations alone; choosing an annotation selects the faces
//! it applies to.

use crate::session::Session;

/// The window, when the model has PMI and the window is shown.
pub(super) fn pmi_window(ui: &mut egui::Ui, s: &mut Session, aspect: f64) {
    let ctx = ui.ctx().clone();
    if !s.show_pmi_window {
        return;
    }
    // Written once per document (the semantic items' texts are formatted, not free).
    let Some(rows) = s.pmi_rows() else { return };
    let mut open = true;
    let mut chosen_view = None;
    let mut chosen_annotation = None;
    let mut chosen_semantic = None;
    egui::Window::new("PMI")
        .open(&mut open)
        .default_width(320.0)
        .show(&ctx, |ui| {
            ui.label(&rows.summary);
            ui.checkbox(&mut s.show_pmi, "Show PMI");
            ui.separator();
            ui.label("Saved views");
            if ui
                .selectable_label(s.pmi_view.is_none(), "(all annotations)")
                .clicked()
            {
                s.pmi_view = None;
            }
            for (k, name) in rows.views.iter().enumerate() {
                if ui.selectable_label(s.pmi_view == Some(k), name).clicked() {
                    chosen_view = Some(k);
                }
            }
            ui.separator();
            ui.label("Annotations (choose one to select its faces)");
            egui::ScrollArea::vertical()
                .max_height(300.0)
                .show(ui, |ui| {
                    for (k, text) in rows.annotations.iter().enumerate() {
                        if ui
                            .selectable_label(s.pmi_selected == Some(k), text)
                            .clicked()
                        {
                            chosen_annotation = Some(k);
                        }
                    }
                });
            if !rows.semantic.is_empty() {
                ui.separator();
                ui.label("Semantic PMI (choose one to select its faces)");
                egui::ScrollArea::vertical()
                    .id_salt("semantic")
                    .max_height(200.0)
                    .show(ui, |ui| {
                        for (k, text) in rows.semantic.iter().enumerate() {
                            if ui
                                .selectable_label(s.pmi_semantic_selected == Some(k), text)
                                .clicked()
                            {
                                chosen_semantic = Some(k);
                            }
                        }
                    });
            }
        });
    if let Some(k) = chosen_semantic {
        s.choose_semantic(k);
    }
    if let Some(k) = chosen_view {
        s.choose_saved_view(k, aspect);
    }
    if let Some(k) = chosen_annotation {
        s.choose_annotation(k);
    }
    s.show_pmi_window &= open;
}
