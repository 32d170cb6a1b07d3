//! Keyboard shortcuts in the 3D view.

use std::path::PathBuf;

use cadre_render::ViewPreset;

use super::Action;
use crate::inspect::Tool;
use crate::navigation::OrbitStyle;
use crate::session::Session;

/// The keyboard shortcuts (README.md lists them).
pub(super) fn keyboard(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
    // Keys are shortcuts unless a text field is being typed in (a clicked button or the
    // 3D view may hold the focus without wanting the keys).
    if ui.ctx().text_edit_focused() {
        return;
    }
    use egui::Key;
    ui.input(|i| {
        let shift = i.modifiers.shift;
        if i.modifiers.command && i.key_pressed(Key::O) {
            s.show_open = true;
        }
        for (key, preset) in [
            (Key::Num0, ViewPreset::Iso),
            (Key::Num1, ViewPreset::Front),
            (Key::Num2, ViewPreset::Back),
            (Key::Num3, ViewPreset::Left),
            (Key::Num4, ViewPreset::Right),
            (Key::Num5, ViewPreset::Top),
            (Key::Num6, ViewPreset::Bottom),
        ] {
            if i.key_pressed(key) {
                actions.push(Action::Preset(preset));
            }
        }
        if i.key_pressed(Key::F) {
            actions.push(if shift {
                Action::FitSelection
            } else {
                Action::FitAll
            });
        }
        if i.key_pressed(Key::O)
            && !i.modifiers.command
            && let Some(nav) = &mut s.nav
        {
            nav.orthographic = !nav.orthographic;
        }
        if i.key_pressed(Key::T)
            && let Some(nav) = &mut s.nav
        {
            nav.style = match nav.style {
                OrbitStyle::Turntable => OrbitStyle::Trackball,
                OrbitStyle::Trackball => OrbitStyle::Turntable,
            };
        }
        if i.key_pressed(Key::Delete)
            && let Some(k) = s.selected_dimension
        {
            s.delete_measurement(k);
        }
        if i.key_pressed(Key::M) {
            s.next_mode();
        }
        if i.key_pressed(Key::Escape) {
            s.stop_measuring();
            s.selection.clear();
        }
        if i.key_pressed(Key::H) {
            if shift {
                s.show_all();
            } else {
                s.hide_selected();
            }
        }
        if i.key_pressed(Key::I) {
            s.isolate();
        }
        if i.key_pressed(Key::S) {
            s.toggle_quick_section();
        }
        for (key, tool) in [
            (Key::D, Tool::Distance),
            (Key::L, Tool::EdgeLength),
            (Key::R, Tool::Radius),
            (Key::A, Tool::Angle),
        ] {
            if i.key_pressed(key) {
                s.choose_tool(tool);
            }
        }
        // F12: the view's size; Shift + F12: the Screenshot dialog's size (4K by default),
        // both numbered files in the screenshot folder. The key event's own modifiers: the
        // frame's may already have seen Shift released.
        for event in &i.events {
            if let egui::Event::Key {
                key: Key::F12,
                pressed: true,
                repeat: false,
                modifiers,
                ..
            } = event
            {
                let [width, height] = if modifiers.shift {
                    s.screenshot_size
                } else {
                    [0, 0]
                };
                actions.push(Action::Screenshot {
                    width,
                    height,
                    path: PathBuf::new(),
                });
            }
        }
    });
}
