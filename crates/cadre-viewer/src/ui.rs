//! The egui interface: menu bar, model tree, properties and measurements, status bar, open
//! and screenshot dialogs, and the 3D view's area (its gestures are read here and applied by
//! the app). Drawing only changes [`Session`] fields or asks for [`Action`]s.

use std::path::{Path, PathBuf};

use cadre_render::{DisplayMode, Pick, ViewPreset};
use egui::{Color32, Pos2, Sense, Stroke, Vec2};

use crate::document::{Document, LoadStage};
use crate::gizmo;
use crate::inspect::{self, Measurement, Picked, Tool};
use crate::navigation::{Navigator, OrbitStyle};

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

/// The viewer's state the interface shows and edits.
pub(crate) struct Session {
    pub doc: Option<Document>,
    pub nav: Option<Navigator>,
    pub mode: DisplayMode,
    /// Per scene node: hidden by the user.
    pub hidden: Vec<bool>,
    /// Per instance: a colour (sRGB + opacity) the user gave it.
    pub colours: Vec<Option<[f32; 4]>>,
    pub hover: Option<Picked>,
    pub selection: Vec<Picked>,
    pub tool: Option<Tool>,
    pub tool_picks: Vec<Picked>,
    pub measurements: Vec<Measurement>,
    pub tool_message: Option<String>,
    pub loading: Option<(PathBuf, LoadStage)>,
    pub error: Option<String>,
    pub show_open: bool,
    pub open_path: String,
    pub show_screenshot: bool,
    pub screenshot_size: [u32; 2],
    pub screenshot_path: String,
    pub show_warnings: bool,
    pub status: String,
    pub frame_ms: f64,
    pub spacemouse: Option<String>,
    /// The 3D view's texture, drawn as the central panel's image.
    pub view_texture: Option<egui::TextureId>,
    /// Section planes (at most [`cadre_render::MAX_SECTIONS`]).
    pub sections: Vec<Section>,
    /// Text the model tree is filtered by (part names containing it).
    pub tree_filter: String,
    /// Properties rows of picked items, worked out once per item (exact areas and lengths
    /// are integrals: not every frame).
    pub properties: std::collections::HashMap<Pick, Vec<(String, String)>>,
}

/// A section plane as the user sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Section {
    /// Whether it cuts.
    pub enabled: bool,
    /// Unit normal (world): the side it points to is cut away.
    pub normal: glam::DVec3,
    /// Position along the normal across the model's box, 0..1.
    pub position: f64,
}

impl Section {
    /// The plane across the model's box `lo`..`hi`.
    pub fn plane(&self, lo: glam::DVec3, hi: glam::DVec3) -> cadre_render::SectionPlane {
        // The box's extent along the normal.
        let corners = (0..8).map(|i| {
            glam::DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
            .dot(self.normal)
        });
        let (min, max) = corners.fold((f64::MAX, f64::MIN), |(a, b), d| (a.min(d), b.max(d)));
        cadre_render::SectionPlane {
            normal: self.normal,
            offset: min + (max - min) * self.position.clamp(0.0, 1.0),
        }
    }
}

impl Session {
    pub fn new() -> Session {
        let cwd = std::env::current_dir().unwrap_or_default();
        Session {
            doc: None,
            nav: None,
            mode: DisplayMode::ShadedEdges,
            hidden: Vec::new(),
            colours: Vec::new(),
            hover: None,
            selection: Vec::new(),
            tool: None,
            tool_picks: Vec::new(),
            measurements: Vec::new(),
            tool_message: None,
            loading: None,
            error: None,
            show_open: false,
            open_path: cwd.display().to_string(),
            show_screenshot: false,
            screenshot_size: [3840, 2160],
            screenshot_path: cwd.join("screenshot.png").display().to_string(),
            show_warnings: false,
            status: String::new(),
            frame_ms: 0.0,
            spacemouse: None,
            view_texture: None,
            sections: Vec::new(),
            tree_filter: String::new(),
            properties: std::collections::HashMap::new(),
        }
    }

    /// A model replaced the last one: fresh styles, selection and camera.
    pub fn set_document(&mut self, doc: Document, aspect: f64) {
        let (lo, hi) = doc
            .bounds
            .unwrap_or((glam::DVec3::splat(-1.0), glam::DVec3::splat(1.0)));
        self.nav = Some(Navigator::new(lo, hi, aspect));
        self.hidden = vec![false; doc.scene.nodes.len()];
        self.colours = vec![None; doc.instances.len()];
        self.hover = None;
        self.selection.clear();
        self.tool_picks.clear();
        self.measurements.clear();
        self.sections.clear();
        self.properties.clear();
        self.status = format!(
            "{}: {} parts, {} faces, loaded in {:.2} s",
            doc.title(),
            doc.instances.len(),
            doc.model.faces.len(),
            doc.load_seconds
        );
        self.doc = Some(doc);
    }

    /// The renderer's view state: visibility, colours, hover and selection.
    pub fn view_state(&self) -> cadre_render::ViewState {
        let Some(doc) = &self.doc else {
            return cadre_render::ViewState::default();
        };
        let instances = doc
            .instances
            .iter()
            .enumerate()
            .map(|(i, info)| cadre_render::InstanceStyle {
                visible: !doc.node_hidden(info.node, &self.hidden),
                colour: self.colours.get(i).copied().flatten().map(|c| {
                    let lin = |x: f32| egui::ecolor::linear_f32_from_gamma_u8((x * 255.0) as u8);
                    [lin(c[0]), lin(c[1]), lin(c[2]), c[3]]
                }),
            })
            .collect();
        cadre_render::ViewState {
            instances,
            hover: self.hover.map(|h| h.pick),
            selection: self
                .selection
                .iter()
                .chain(&self.tool_picks)
                .map(|p| p.pick)
                .collect(),
            sections: match doc.bounds {
                Some((lo, hi)) => self
                    .sections
                    .iter()
                    .filter(|s| s.enabled)
                    .map(|s| s.plane(lo, hi))
                    .collect(),
                None => Vec::new(),
            },
        }
    }

    /// Handles a pick from a click: the measurement tool takes it, else the selection.
    pub fn clicked(&mut self, picked: Option<Picked>, add: bool) {
        if let Some(tool) = self.tool {
            let Some(p) = picked else { return };
            self.tool_picks.push(p);
            if self.tool_picks.len() >= tool.picks() {
                let picks = std::mem::take(&mut self.tool_picks);
                if let Some(doc) = &self.doc {
                    match inspect::measure(doc, tool, &picks) {
                        Ok(m) => {
                            self.tool_message = Some(m.text.clone());
                            self.measurements.push(m);
                        }
                        Err(e) => self.tool_message = Some(e),
                    }
                }
            }
            return;
        }
        match (picked, add) {
            (Some(p), true) => {
                if let Some(i) = self.selection.iter().position(|s| s.pick == p.pick) {
                    self.selection.remove(i);
                } else {
                    self.selection.push(p);
                }
            }
            (Some(p), false) => self.selection = vec![p],
            (None, false) => self.selection.clear(),
            (None, true) => {}
        }
    }

    /// Hides every instance but the selected parts'.
    pub fn isolate(&mut self) {
        let Some(doc) = &self.doc else { return };
        let keep: Vec<u32> = self.selection.iter().map(|p| p.pick.instance()).collect();
        if keep.is_empty() {
            return;
        }
        for (i, info) in doc.instances.iter().enumerate() {
            if let Some(h) = self.hidden.get_mut(info.node) {
                *h = !keep.contains(&(i as u32));
            }
        }
        // Ancestors of kept parts must show.
        for &k in &keep {
            let mut n = doc.instances.get(k as usize).map(|i| i.node);
            while let Some(node) = n {
                if let Some(h) = self.hidden.get_mut(node) {
                    *h = false;
                }
                n = doc.parents.get(node).copied().flatten();
            }
        }
    }
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
    let top = menu_bar(ui, s, &mut actions);
    let bottom = status_bar(ui, s);
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
            .show(ui, |ui| tree_panel(ui, s));
        let right = egui::Panel::right("properties")
            .exact_size(300.0)
            .show(ui, |ui| properties_panel(ui, s, &mut actions));
        rect.min.x = rect.min.x.max(left.response.rect.max.x);
        rect.max.x = rect.max.x.min(right.response.rect.min.x);
    }
    dialogs(ui, s, &mut actions);
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
        overlay(ui, s, rect, aspect, &mut actions);
        keyboard(ui, s, &mut actions);
    }
    let ppp = ui.pixels_per_point();
    let rect = egui::Rect::from_min_max(
        Pos2::new(rect.min.x * ppp, rect.min.y * ppp),
        Pos2::new(rect.max.x * ppp, rect.max.y * ppp),
    );
    (rect, input, actions)
}

/// The menu bar; returns its rectangle.
fn menu_bar(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) -> egui::Rect {
    egui::Panel::top("menu")
        .show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| {
                    if ui.button("Open…  (Ctrl+O)").clicked() {
                        s.show_open = true;
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
                    for (name, mode) in MODES {
                        ui.radio_value(&mut s.mode, mode, name);
                    }
                });
                ui.menu_button("Measure", |ui| {
                    ui.label("Keys: D distance, L edge length, R radius, A angle");
                    for tool in Tool::ALL {
                        if ui.radio(s.tool == Some(tool), tool.name()).clicked() {
                            s.tool = Some(tool);
                            s.tool_picks.clear();
                            s.tool_message =
                                Some(format!("{}: pick {} item(s)", tool.name(), tool.picks()));
                        }
                    }
                    if ui.button("Stop measuring  (Esc)").clicked() {
                        s.tool = None;
                        s.tool_picks.clear();
                    }
                    if ui.button("Clear measurements").clicked() {
                        s.measurements.clear();
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

/// Display modes by name.
const MODES: [(&str, DisplayMode); 5] = [
    ("Shaded", DisplayMode::Shaded),
    ("Shaded with edges", DisplayMode::ShadedEdges),
    ("Wireframe", DisplayMode::Wireframe),
    ("Hidden line", DisplayMode::HiddenLine),
    ("X-ray", DisplayMode::XRay),
];

/// The status bar; returns its rectangle.
fn status_bar(ui: &mut egui::Ui, s: &mut Session) -> egui::Rect {
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
fn pick_label(doc: &crate::document::Document, pick: Pick) -> String {
    let step = doc.step_label(pick);
    match pick {
        Pick::Face { instance, .. } => format!("part {instance} · face {step}"),
        Pick::Edge { instance, .. } => format!("part {instance} · edge {step}"),
        Pick::Vertex { instance, .. } => format!("part {instance} · vertex {step}"),
        Pick::Part { instance } => format!("part {instance}"),
    }
}

fn tree_panel(ui: &mut egui::Ui, s: &mut Session) {
    ui.set_min_width(ui.available_width());
    ui.heading("Model");
    ui.horizontal(|ui| {
        if ui.button("Show all").clicked() {
            s.hidden.iter_mut().for_each(|h| *h = false);
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
            let roots = doc.scene.roots.clone();
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
                    s.selection = vec![Picked {
                        pick,
                        point: glam::DVec3::ZERO,
                    }];
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
    let name = doc.scene.nodes[node].name.clone();
    let name = if name.is_empty() {
        format!("node {node}")
    } else {
        name
    };
    let children = doc.scene.nodes[node].children.clone();
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
            s.selection = vec![Picked {
                pick: Pick::Part { instance: i as u32 },
                point: glam::DVec3::ZERO,
            }];
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

fn properties_panel(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
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
                s.tool = (s.tool != Some(tool)).then_some(tool);
                s.tool_picks.clear();
                s.tool_message = s
                    .tool
                    .map(|t| format!("{}: pick {} item(s)", t.name(), t.picks()));
            }
        }
    });
    if let Some(m) = &s.tool_message {
        ui.label(m);
    }
    for m in s.measurements.iter().rev() {
        ui.label(&m.text);
    }
    ui.separator();
    sections_ui(ui, s);
}

/// Section planes: add (along an axis or a selected planar face), move, flip, remove.
fn sections_ui(ui: &mut egui::Ui, s: &mut Session) {
    ui.heading("Sections");
    ui.horizontal(|ui| {
        let room = s.sections.len() < cadre_render::MAX_SECTIONS;
        for (name, normal) in [
            ("+X", glam::DVec3::X),
            ("+Y", glam::DVec3::Y),
            ("+Z", glam::DVec3::Z),
        ] {
            if ui.add_enabled(room, egui::Button::new(name)).clicked() {
                s.sections.push(Section {
                    enabled: true,
                    normal,
                    position: 0.5,
                });
            }
        }
        let face_normal = s
            .selection
            .first()
            .and_then(|p| s.doc.as_ref().and_then(|d| inspect::world_plane(d, p.pick)));
        if ui
            .add_enabled(
                room && face_normal.is_some(),
                egui::Button::new("From face"),
            )
            .on_hover_text("A plane through the selected planar face")
            .clicked()
            && let (Some((origin, normal)), Some((lo, hi))) =
                (face_normal, s.doc.as_ref().and_then(|d| d.bounds))
        {
            // The position that puts the plane through the face.
            let mut section = Section {
                enabled: true,
                normal: -normal,
                position: 0.0,
            };
            let (a, b) = (section.plane(lo, hi).offset, {
                section.position = 1.0;
                section.plane(lo, hi).offset
            });
            let d = (-normal).dot(origin);
            section.position = if (b - a).abs() > 1e-300 {
                (d - a) / (b - a)
            } else {
                0.5
            };
            s.sections.push(section);
        }
    });
    let mut remove = None;
    for (k, section) in s.sections.iter_mut().enumerate() {
        ui.horizontal(|ui| {
            ui.checkbox(&mut section.enabled, format!("{}", k + 1));
            ui.spacing_mut().slider_width = 120.0;
            ui.add(egui::Slider::new(&mut section.position, 0.0..=1.0).show_value(false));
            if ui.button("Flip").clicked() {
                section.normal = -section.normal;
                section.position = 1.0 - section.position;
            }
            if ui.button("✕").clicked() {
                remove = Some(k);
            }
        });
    }
    if let Some(k) = remove {
        s.sections.remove(k);
    }
}

fn dialogs(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
    let ctx = ui.ctx().clone();
    if s.show_open {
        let mut open = true;
        egui::Window::new("Open a STEP file")
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

/// The axis gizmo, the measurements' dimension lines and the hovered vertex, over the view.
fn overlay(
    ui: &mut egui::Ui,
    s: &mut Session,
    rect: egui::Rect,
    aspect: f64,
    actions: &mut Vec<Action>,
) {
    let Some(nav) = &s.nav else {
        if s.doc.is_none() && s.loading.is_none() {
            ui.centered_and_justified(|ui| {
                ui.label("File → Open, or drop a STEP file here");
            });
        }
        return;
    };
    let camera = nav.camera();
    let painter = ui.painter();
    // Gizmo, bottom left.
    let centre = Pos2::new(rect.min.x + 60.0, rect.max.y - 60.0);
    let radius = 40.0;
    painter.circle_filled(centre, radius + 12.0, Color32::from_black_alpha(24));
    for axis in gizmo::axes(&camera) {
        let tip = centre + Vec2::new(axis.tip.x as f32, axis.tip.y as f32) * radius;
        let colour = Color32::from_rgb(axis.colour[0], axis.colour[1], axis.colour[2]);
        let alpha = if axis.towards_viewer { 1.0 } else { 0.5 };
        painter.line_segment(
            [centre, tip],
            Stroke::new(2.5, colour.gamma_multiply(alpha)),
        );
        let label_rect = egui::Rect::from_center_size(tip, Vec2::splat(18.0));
        let response = ui.interact(
            label_rect,
            ui.scope_id().with(("gizmo", axis.label)),
            Sense::click(),
        );
        painter.circle_filled(tip, 9.0, colour.gamma_multiply(alpha));
        painter.text(
            tip,
            egui::Align2::CENTER_CENTER,
            axis.label,
            egui::FontId::proportional(12.0),
            Color32::WHITE,
        );
        if response.clicked() {
            actions.push(Action::Preset(axis.preset));
        }
    }
    // Dimension lines.
    let ppp = ui.pixels_per_point() as f64;
    let (w, h) = ((rect.width() as f64), (rect.height() as f64));
    let view_proj = camera.projection_matrix(aspect) * camera.view_rotation();
    let to_screen = |p: glam::DVec3| {
        let c = view_proj * (p - camera.eye).extend(1.0);
        (c.w > 0.0).then(|| {
            let (x, y) = (c.x / c.w, c.y / c.w);
            Pos2::new(
                (rect.min.x as f64 + (x + 1.0) * 0.5 * w) as f32,
                (rect.min.y as f64 + (1.0 - y) * 0.5 * h) as f32,
            )
        })
    };
    let _ = ppp;
    for m in &s.measurements {
        if let [a, b] = m.points[..]
            && let (Some(pa), Some(pb)) = (to_screen(a), to_screen(b))
        {
            painter.line_segment([pa, pb], Stroke::new(2.0, Color32::from_rgb(230, 120, 20)));
            painter.circle_filled(pa, 3.5, Color32::from_rgb(230, 120, 20));
            painter.circle_filled(pb, 3.5, Color32::from_rgb(230, 120, 20));
            let label = format!(
                "{:.3}",
                if m.tool == Tool::Angle {
                    m.value.to_degrees()
                } else {
                    m.value
                }
            );
            painter.text(
                pa + (pb - pa) * 0.5,
                egui::Align2::CENTER_BOTTOM,
                if m.tool == Tool::Angle {
                    format!("{label}°")
                } else {
                    format!("{label} mm")
                },
                egui::FontId::proportional(14.0),
                Color32::from_rgb(160, 70, 0),
            );
        }
    }
    // The hovered vertex as a dot (vertices are not drawn otherwise).
    if let (Some(hover), Some(doc)) = (&s.hover, &s.doc)
        && let Some(p) = inspect::vertex_position(doc, hover.pick).and_then(to_screen)
    {
        painter.circle_filled(p, 5.0, Color32::from_rgb(80, 190, 255));
    }
}

fn keyboard(ui: &mut egui::Ui, s: &mut Session, actions: &mut Vec<Action>) {
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
        if i.key_pressed(Key::M) {
            let k = MODES.iter().position(|(_, m)| *m == s.mode).unwrap_or(0);
            s.mode = MODES[(k + 1) % MODES.len()].1;
        }
        if i.key_pressed(Key::Escape) {
            s.tool = None;
            s.tool_picks.clear();
            s.selection.clear();
        }
        if i.key_pressed(Key::H) {
            if shift {
                s.hidden.iter_mut().for_each(|h| *h = false);
            } else if let Some(doc) = &s.doc {
                for p in &s.selection {
                    if let Some(info) = doc.instances.get(p.pick.instance() as usize)
                        && let Some(h) = s.hidden.get_mut(info.node)
                    {
                        *h = true;
                    }
                }
                s.selection.clear();
            }
        }
        if i.key_pressed(Key::I) {
            s.isolate();
        }
        if i.key_pressed(Key::S) {
            // A quick section across the middle, or none.
            if s.sections.is_empty() {
                s.sections.push(Section {
                    enabled: true,
                    normal: glam::DVec3::Y,
                    position: 0.5,
                });
            } else {
                s.sections.clear();
            }
        }
        for (key, tool) in [
            (Key::D, Tool::Distance),
            (Key::L, Tool::EdgeLength),
            (Key::R, Tool::Radius),
            (Key::A, Tool::Angle),
        ] {
            if i.key_pressed(key) {
                s.tool = Some(tool);
                s.tool_picks.clear();
                s.tool_message = Some(format!("{}: pick {} item(s)", tool.name(), tool.picks()));
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
