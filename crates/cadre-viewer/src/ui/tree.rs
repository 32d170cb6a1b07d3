//! The model tree panel.

use cadre_render::Pick;

use crate::session::Session;

/// The model tree: show all, isolate, a name filter, and a row per node with its visibility.
pub(super) fn tree_panel(ui: &mut egui::Ui, s: &mut Session) {
    ui.set_min_width(ui.available_width());
    ui.heading("Model");
    ui.horizontal(|ui| {
        if ui.button("Show all").clicked() {
            s.show_all();
        }
        if ui
            .button("Isolate")
            .on_hover_text("Hide every part but the selected ones")
            .clicked()
        {
            s.isolate();
        }
    });
    ui.horizontal(|ui| {
        ui.label("Find");
        ui.text_edit_singleline(&mut s.tree_filter);
    });
    ui.separator();
    let filter = s.tree_filter.trim().to_lowercase();
    egui::ScrollArea::vertical().show(ui, |ui| {
        let Some(doc) = &s.doc else { return };
        if filter.is_empty() {
            let roots = doc.scene.assembly.roots.clone();
            for root in roots {
                node_ui(ui, s, root, 0);
            }
            return;
        }
        // A flat list of the parts whose name matches (large assemblies: no digging).
        let matches: Vec<usize> = doc
            .instances
            .iter()
            .enumerate()
            .filter(|(_, info)| info.name.to_lowercase().contains(&filter))
            .map(|(i, _)| i)
            .take(2000)
            .collect();
        if matches.is_empty() {
            ui.label("No part matches");
        }
        for i in matches {
            let Some(doc) = &s.doc else { return };
            let node = doc.instances[i].node;
            let name = doc.instances[i].name.clone();
            ui.horizontal(|ui| {
                let mut visible = !s.hidden.get(node).copied().unwrap_or(false);
                if ui.checkbox(&mut visible, "").changed()
                    && let Some(h) = s.hidden.get_mut(node)
                {
                    *h = !visible;
                }
                let pick = Pick::Part { instance: i as u32 };
                let selected = s.selection.iter().any(|p| p.pick == pick);
                if ui.selectable_label(selected, name).clicked() {
                    s.select_part(i);
                }
            });
        }
    });
}

/// One tree row (and its children, collapsed by default).
fn node_ui(ui: &mut egui::Ui, s: &mut Session, node: usize, depth: usize) {
    let Some(doc) = &s.doc else { return };
    if depth > 64 {
        return;
    }
    let name = doc.scene.assembly.nodes[node].name.clone();
    let name = if name.is_empty() {
        format!("node {node}")
    } else {
        name
    };
    let children = doc.scene.assembly.nodes[node].children.clone();
    let instance = doc.instance_of_node.get(node).copied().flatten();
    let selected = instance.is_some_and(|i| {
        s.selection
            .iter()
            .any(|p| p.pick == Pick::Part { instance: i as u32 })
    });
    let row = |ui: &mut egui::Ui, s: &mut Session| {
        let mut visible = !s.hidden.get(node).copied().unwrap_or(false);
        if ui.checkbox(&mut visible, "").changed()
            && let Some(h) = s.hidden.get_mut(node)
        {
            *h = !visible;
        }
        if ui.selectable_label(selected, &name).clicked()
            && let Some(i) = instance
        {
            s.select_part(i);
        }
    };
    if children.is_empty() {
        ui.horizontal(|ui| row(ui, s));
    } else {
        let id = ui.scope_id().with(("node", node));
        egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, depth == 0)
            .show_header(ui, |ui| row(ui, s))
            .body(|ui| {
                for c in children {
                    node_ui(ui, s, c, depth + 1);
                }
            });
    }
}
