//! The dialogs: open a file (a model or a CAM program, with a folder browser), screenshot,
//! errors, warnings.

use std::path::{Path, PathBuf};

use super::Action;
use crate::session::Session;

/// The Open, Screenshot, Error and Warnings windows, when shown.
pub(super) fn dialogs(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
    let ctx = ui.ctx().clone();
    if s.show_open {
        let mut open = true;
        egui::Window::new("Open a STEP file or a CAM program (G-code)")
            .open(&mut open)
            .show(&ctx, |ui| {
                ui.horizontal(|ui| {
                    ui.text_edit_singleline(&mut s.open_path);
                    if ui.button("Open").clicked() {
                        actions.push(Action::Open(PathBuf::from(&s.open_path)));
                    }
                });
                file_browser(ui, s, actions);
            });
        if !open || actions.iter().any(|a| matches!(a, Action::Open(_))) {
            s.show_open = false;
        }
    }
    if s.show_screenshot {
        let mut open = true;
        egui::Window::new("Screenshot")
            .open(&mut open)
            .show(&ctx, |ui| {
                ui.horizontal(|ui| {
                    ui.label("Size");
                    ui.add(egui::DragValue::new(&mut s.screenshot_size[0]).range(16..=16384));
                    ui.label("×");
                    ui.add(egui::DragValue::new(&mut s.screenshot_size[1]).range(16..=16384));
                });
                ui.horizontal(|ui| {
                    ui.label("File");
                    ui.text_edit_singleline(&mut s.screenshot_path);
                });
                if ui.button("Save").clicked() {
                    actions.push(Action::Screenshot {
                        width: s.screenshot_size[0],
                        height: s.screenshot_size[1],
                        path: PathBuf::from(&s.screenshot_path),
                    });
                }
            });
        s.show_screenshot = open
            && !actions
                .iter()
                .any(|a| matches!(a, Action::Screenshot { .. }));
    }
    if let Some(e) = s.error.clone() {
        let mut open = true;
        egui::Window::new("Error").open(&mut open).show(&ctx, |ui| {
            ui.label(e);
        });
        if !open {
            s.error = None;
        }
    }
    if s.show_warnings
        && let Some(doc) = &s.doc
    {
        let mut open = true;
        egui::Window::new("Warnings")
            .open(&mut open)
            .show(&ctx, |ui| {
                egui::ScrollArea::vertical()
                    .max_height(400.0)
                    .show(ui, |ui| {
                        for w in &doc.warnings {
                            ui.label(w);
                        }
                    });
            });
        s.show_warnings = open;
    }
}

/// Folders and STEP files of the folder in the path field; a click walks in or opens.
fn file_browser(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
    let path = PathBuf::from(&s.open_path);
    let dir = if path.is_dir() {
        path
    } else {
        path.parent().map(Path::to_path_buf).unwrap_or_default()
    };
    let mut entries: Vec<(bool, PathBuf)> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.filter_map(Result::ok)
                .map(|e| (e.path().is_dir(), e.path()))
                .filter(|(is_dir, p)| {
                    *is_dir
                        || p.extension().is_some_and(|x| {
                            let x = x.to_string_lossy().to_ascii_lowercase();
                            x == "step" || x == "stp"
                        })
                        || crate::session::Toolpath::is_program(p)
                })
                .take(5000)
                .collect()
        })
        .unwrap_or_default();
    entries.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    egui::ScrollArea::vertical()
        .max_height(320.0)
        .show(ui, |ui| {
            if let Some(parent) = dir.parent()
                && ui.link("..").clicked()
            {
                s.open_path = parent.display().to_string();
            }
            for (is_dir, p) in entries {
                let name = p
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
                if is_dir {
                    if ui.link(format!("{name}/")).clicked() {
                        s.open_path = p.display().to_string();
                    }
                } else if ui.link(name).clicked() {
                    actions.push(Action::Open(p));
                }
            }
        });
}
