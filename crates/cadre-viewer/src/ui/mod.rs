//! The egui interface: menu bar, model tree, properties and measurements, section planes,
//! status bar, open and screenshot dialogs, and the 3D view's area (its gestures are read here
//! and applied by the app). Drawing only changes [`Session`] fields, through its methods where
//! there is logic, or asks for [`Action`]s. One file per panel.

mod dialogs;
mod keys;
mod menu;
mod overlay;
mod pmi;
mod properties;
mod sections;
mod status;
mod toolpath;
mod tree;

use std::path::PathBuf;

use cadre_render::ViewPreset;
use egui::{Color32, Pos2, Sense, Vec2};

use crate::session::Session;

/// What the interface asks the app to do after drawing.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Action {
    /// Open a file.
    Open(PathBuf),
    /// Write a screenshot of `width` × `height` to `path`.
    Screenshot {
        /// Pixels.
        width: u32,
        /// Pixels.
        height: u32,
        /// PNG file.
        path: PathBuf,
    },
    /// Move to a view preset.
    Preset(ViewPreset),
    /// Frame everything.
    FitAll,
    /// Frame the selection.
    FitSelection,
    /// Close the window.
    Quit,
}

/// A gesture in the 3D view this frame.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ViewInput {
    /// Pointer position in physical pixels, when over the 3D view.
    pub hover: Option<Pos2>,
    /// Where a drag began (physical pixels) when one began this frame.
    pub drag_started: Option<Pos2>,
    /// Orbit drag (primary button) this frame, physical pixels.
    pub orbit: Vec2,
    /// Pan drag (middle or secondary button, or shift + primary), physical pixels.
    pub pan: Vec2,
    /// Zoom steps (positive = closer).
    pub zoom: f32,
    /// A click (no drag) at the pointer: select; `add` with ctrl or shift.
    pub click: Option<(Pos2, bool)>,
    /// The click picks the whole part (alt held).
    pub part: bool,
}

/// Draws the whole interface; returns the 3D view's rectangle (physical pixels), its
/// gestures and the actions asked.
pub(crate) fn draw(
    ui: &mut egui::Ui,
    s: &mut Session,
    aspect: f64,
) -> (egui::Rect, ViewInput, Vec<Action>) {
    let mut actions = Vec::new();
    let whole = ui.max_rect();
    let top = menu::menu_bar(ui, s, &mut actions);
    let bottom = status::status_bar(ui, s);
    // The 3D view is what the panels leave, taken from their own rectangles (a panel
    // whose content is wider than itself must not push the view under it).
    let mut rect = egui::Rect::from_min_max(
        Pos2::new(whole.min.x, top.max.y),
        Pos2::new(whole.max.x, bottom.min.y),
    );
    if s.doc.is_some() {
        // Fixed widths: the 3D view must not jump when a selection fills the properties.
        let left = egui::Panel::left("tree")
            .exact_size(240.0)
            .show(ui, |ui| tree::tree_panel(ui, s));
        let right = egui::Panel::right("properties")
            .exact_size(300.0)
            .show(ui, |ui| properties::properties_panel(ui, s, &mut actions));
        rect.min.x = rect.min.x.max(left.response.rect.max.x);
        rect.max.x = rect.max.x.min(right.response.rect.min.x);
    }
    dialogs::dialogs(ui, s, &mut actions);
    toolpath::toolpath_window(ui, s);
    pmi::pmi_window(ui, s, aspect);
    let mut input = ViewInput::default();
    {
        if let (Some(id), Some(_)) = (s.view_texture, &s.nav) {
            ui.painter().image(
                id,
                rect,
                egui::Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
                Color32::WHITE,
            );
        }
        let response = ui.interact(rect, ui.scope_id().with("3d"), Sense::click_and_drag());
        let ppp = ui.pixels_per_point();
        let phys = |p: Pos2| Pos2::new(p.x * ppp, p.y * ppp);
        input.hover = response.hover_pos().map(phys);
        let (shift, ctrl) = ui.input(|i| (i.modifiers.shift, i.modifiers.command));
        if response.drag_started() {
            input.drag_started = response.interact_pointer_pos().map(phys);
        }
        let delta = response.drag_delta() * ppp;
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            input.orbit = delta;
        } else if response.dragged_by(egui::PointerButton::Middle)
            || response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Primary)
        {
            input.pan = delta;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            input.zoom = scroll / 50.0;
        }
        if response.clicked() {
            input.click = response
                .interact_pointer_pos()
                .map(|p| (phys(p), shift || ctrl));
            input.part = ui.input(|i| i.modifiers.alt);
        }
        if response.double_clicked() {
            actions.push(Action::FitSelection);
        }
        overlay::overlay(ui, s, rect, aspect, &mut actions);
        keys::keyboard(ui, s, &mut actions);
    }
    let ppp = ui.pixels_per_point();
    let rect = egui::Rect::from_min_max(
        Pos2::new(rect.min.x * ppp, rect.min.y * ppp),
        Pos2::new(rect.max.x * ppp, rect.max.y * ppp),
    );
    (rect, input, actions)
}
