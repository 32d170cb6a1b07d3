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
    let Some(doc) = &s.doc else { return };
    let pmi = &doc.model.pmi;
    // A drawing sheet's views are listed with the saved views, marked as such.
    let views: Vec<String> = pmi
        .views
        .iter()
        .map(|v| {
            if v.drawing {
                format!("{} (drawing view)", v.name)
            } else {
                v.name.clone()
            }
        })
        .collect();
    let annotations: Vec<(String, usize, usize)> = pmi
        .annotations
        .iter()
        .map(|a| (a.name.clone(), a.faces.len(), a.point_count()))
        .collect();
    let semantic = &pmi.semantic;
    // Each semantic item as a frame writes it, whether an annotation presents it, its faces.
    let presented: std::collections::HashSet<usize> =
        pmi.annotations.iter().filter_map(|a| a.semantic).collect();
    let items: Vec<(String, bool, usize)> = semantic
        .items
        .iter()
        .enumerate()
        .map(|(k, item)| {
            let faces = item.faces().len();
            (
                cadre_render::pmi::semantic_text(item),
                presented.contains(&k),
                faces,
            )
        })
        .collect();
    let summary = format!(
        "{} annotations, {} dimensions, {} tolerances, {} datums, {} datum targets",
        pmi.annotations.len(),
        pmi.occt_dimensions(),
        pmi.occt_tolerances(),
        semantic.datums(),
        semantic.datum_targets()
    );
    let mut open = true;
    let mut chosen_view = None;
    let mut chosen_annotation = None;
    let mut chosen_semantic = None;
    egui::Window::new("PMI")
        .open(&mut open)
        .default_width(320.0)
        .show(&ctx, |ui| {
            ui.label(summary);
            ui.checkbox(&mut s.show_pmi, "Show PMI");
            ui.separator();
            ui.label("Saved views");
            if ui
                .selectable_label(s.pmi_view.is_none(), "(all annotations)")
                .clicked()
            {
                s.pmi_view = None;
            }
            for (k, name) in views.iter().enumerate() {
                if ui.selectable_label(s.pmi_view == Some(k), name).clicked() {
                    chosen_view = Some(k);
                }
            }
            ui.separator();
            ui.label("Annotations (choose one to select its faces)");
            egui::ScrollArea::vertical()
                .max_height(300.0)
                .show(ui, |ui| {
                    for (k, (name, faces, points)) in annotations.iter().enumerate() {
                        let text = format!("{name}  ({faces} faces, {points} points)");
                        if ui
                            .selectable_label(s.pmi_selected == Some(k), text)
                            .clicked()
                        {
                            chosen_annotation = Some(k);
                        }
                    }
                });
            if !items.is_empty() {
                ui.separator();
                ui.label("Semantic PMI (choose one to select its faces)");
                egui::ScrollArea::vertical()
                    .id_salt("semantic")
                    .max_height(200.0)
                    .show(ui, |ui| {
                        for (k, (text, presented, faces)) in items.iter().enumerate() {
                            let text = if *presented {
                                format!("{text}  ({faces} faces, presented)")
                            } else {
                                format!("{text}  ({faces} faces)")
                            };
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
