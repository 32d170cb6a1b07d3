//! The viewer's state that the interface shows and edits: the open model, camera, display
//! mode, visibility and colours, hover, selection, measurement tool, section planes and
//! dialogs, with the operations on them that are not drawing (selection by click, isolate,
//! hide, the renderer's view state), unit-tested here without a window.

use std::path::PathBuf;

use cadre_render::{DisplayMode, Pick};

use crate::document::{Document, LoadStage};
use crate::inspect::{self, Measurement, Picked, Tool};
use crate::navigation::Navigator;

/// Display modes by name, in the order the M key walks them.
pub(crate) const DISPLAY_MODES: [(&str, DisplayMode); 5] = [
    ("Shaded", DisplayMode::Shaded),
    ("Shaded with edges", DisplayMode::ShadedEdges),
    ("Wireframe", DisplayMode::Wireframe),
    ("Hidden line", DisplayMode::HiddenLine),
    ("X-ray", DisplayMode::XRay),
];

/// A CAM program opened over the model (File → Open a `.ngc`, `.nc`, …): its moves, and
/// the simulation slider and clipping box that show part of it.
pub(crate) struct Toolpath {
    /// The program's file.
    pub path: PathBuf,
    /// The interpreted program.
    pub program: cadre_gcode::Program,
    /// Its path's length, mm (the slider's end).
    pub travel: f64,
    /// Its box (machine coordinates), for framing it.
    pub bounds: Option<(glam::DVec3, glam::DVec3)>,
    /// The simulation is on: the path is shown up to `up_to`, with the tool there.
    pub simulate: bool,
    /// How far along the path the simulation is, mm.
    pub up_to: f64,
    /// Only the part inside `clip_box` is shown.
    pub clip: bool,
    /// The clipping box's low and high corners, mm.
    pub clip_box: [[f64; 3]; 2],
    /// What colours the cutting moves.
    pub colour_by: cadre_render::lines::toolpath::ColourBy,
    /// The tool's diameter where it is drawn, mm.
    pub tool_diameter: f64,
}

impl Toolpath {
    /// Reads and interprets a program file.
    pub fn load(path: &std::path::Path) -> Result<Toolpath, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let program = cadre_gcode::interpret(&String::from_utf8_lossy(&bytes));
        let coarse =
            cadre_render::lines::toolpath::toolpath_lines(&program, &Default::default(), 0.05);
        let bounds = coarse.bounds();
        let travel = coarse.travel();
        let (lo, hi) = bounds.unwrap_or((glam::DVec3::ZERO, glam::DVec3::ZERO));
        Ok(Toolpath {
            path: path.to_path_buf(),
            program,
            travel,
            bounds,
            simulate: false,
            up_to: travel,
            clip: false,
            clip_box: [lo.to_array(), hi.to_array()],
            colour_by: Default::default(),
            tool_diameter: 6.0,
        })
    }

    /// Whether `path` names a CAM program (by its extension).
    pub fn is_program(path: &std::path::Path) -> bool {
        cadre_gcode::is_program_path(path)
    }

    /// What of it a frame shows.
    pub fn line_view(&self) -> cadre_render::LineView {
        cadre_render::LineView {
            up_to: self.simulate.then_some(self.up_to),
            clip_box: self.clip.then(|| {
                let (a, b) = (
                    glam::DVec3::from(self.clip_box[0]),
                    glam::DVec3::from(self.clip_box[1]),
                );
                (a.min(b), a.max(b))
            }),
        }
    }
}

/// The viewer's state the interface shows and edits.
pub(crate) struct Session {
    /// A CAM program shown over the model.
    pub toolpath: Option<Toolpath>,
    /// The Toolpath window is shown.
    pub show_toolpath: bool,
    /// The open model, once loaded.
    pub doc: Option<Document>,
    /// The camera and its gestures, once a model is open.
    pub nav: Option<Navigator>,
    /// How faces and edges are drawn.
    pub mode: DisplayMode,
    /// Faces drawn from their exact surfaces, trimmed per pixel (the trim back-end), instead
    /// of their static meshes.
    pub exact_faces: bool,
    /// The key light casts shadows (a shadow map every back-end writes).
    pub shadows: bool,
    /// With exact faces, the crack pass's exact fill also solves the pixels beside
    /// silhouettes once the camera stops (`CrackOptions::silhouettes`; on by default).
    pub silhouette_fill: bool,
    /// A grey-blue gradient behind the model (off by default: a flat light grey).
    pub gradient: bool,
    /// A ground grid under the model.
    pub grid: bool,
    /// Per scene node: hidden by the user.
    pub hidden: Vec<bool>,
    /// Per instance: a colour (sRGB + opacity) the user gave it.
    pub colours: Vec<Option<[f32; 4]>>,
    /// What the cursor is over (answered a frame after the pointer moved).
    pub hover: Option<Picked>,
    /// Selected items, in the order picked.
    pub selection: Vec<Picked>,
    /// The measurement tool in use: clicks feed it instead of the selection.
    pub tool: Option<Tool>,
    /// Items picked for the tool so far.
    pub tool_picks: Vec<Picked>,
    /// Finished measurements, drawn as dimension lines.
    pub measurements: Vec<Measurement>,
    /// What the tool asks for, or its last result or error.
    pub tool_message: Option<String>,
    /// A model being loaded and its stage.
    pub loading: Option<(PathBuf, LoadStage)>,
    /// An error to show in a window until dismissed.
    pub error: Option<String>,
    /// The Open dialog is shown.
    pub show_open: bool,
    /// The Open dialog's path field.
    pub open_path: String,
    /// The Screenshot dialog is shown.
    pub show_screenshot: bool,
    /// The Screenshot dialog's size, pixels.
    pub screenshot_size: [u32; 2],
    /// The Screenshot dialog's file.
    pub screenshot_path: String,
    /// The model's warnings are shown.
    pub show_warnings: bool,
    /// The status bar's text.
    pub status: String,
    /// The last frame's time, milliseconds.
    pub frame_ms: f64,
    /// The 3D mouse's state, when one is connected.
    pub spacemouse: Option<String>,
    /// The 3D view's texture, drawn as the central panel's image.
    pub view_texture: Option<egui::TextureId>,
    /// Section planes (at most [`cadre_render::MAX_SECTIONS`]).
    pub sections: Vec<Section>,
    /// Text the model tree is filtered by (part names containing it).
    pub tree_filter: String,
    /// The model's PMI is drawn over it (Display → PMI, or the PMI window).
    pub show_pmi: bool,
    /// The PMI window is shown.
    pub show_pmi_window: bool,
    /// Part names as callouts beside the model (Display → Part labels), laid out again
    /// whenever the view settles.
    pub part_labels: bool,
    /// The document's callout anchors (part names, generated PMI), found once per document:
    /// the layout runs again whenever the view settles, the anchors do not move.
    callout_anchors: std::cell::OnceCell<(
        Vec<cadre_render::text::leaders::PartAnchor>,
        Vec<cadre_render::text::leaders::PartAnchor>,
    )>,
    /// The PMI window's rows, written once per document (not every frame it is open).
    pmi_rows: std::cell::OnceCell<std::rc::Rc<PmiRows>>,
    /// The dimension chosen by a click on its label (Delete removes it).
    pub selected_dimension: Option<usize>,
    /// The saved view chosen in the PMI window: only its annotations are drawn.
    pub pmi_view: Option<usize>,
    /// The annotation chosen in the PMI window (its faces are selected).
    pub pmi_selected: Option<usize>,
    /// The semantic PMI item chosen in the PMI window (its faces are the selection).
    pub pmi_semantic_selected: Option<usize>,
    /// Properties rows of picked items, worked out once per item (exact areas and lengths
    /// are integrals: not every frame).
    pub properties: std::collections::HashMap<Pick, Vec<(String, String)>>,
}

/// The PMI window's text: its summary and a row per saved view, annotation and semantic
/// item, in the model's order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PmiRows {
    /// The counts, as OCCT's XCAF counts them.
    pub summary: String,
    /// Saved views by name (a drawing sheet's marked).
    pub views: Vec<String>,
    /// Annotations: name, faces, points.
    pub annotations: Vec<String>,
    /// Semantic items as a frame writes them, with their faces and whether presented.
    pub semantic: Vec<String>,
}

impl PmiRows {
    /// The rows of `pmi`.
    pub fn of(pmi: &cadre_brep::pmi::Pmi) -> PmiRows {
        let presented: std::collections::HashSet<usize> =
            pmi.annotations.iter().filter_map(|a| a.semantic).collect();
        PmiRows {
            summary: format!(
                "{} annotations, {} dimensions, {} tolerances, {} datums, {} datum targets",
                pmi.annotations.len(),
                pmi.occt_dimensions(),
                pmi.occt_tolerances(),
                pmi.semantic.datums(),
                pmi.semantic.datum_targets()
            ),
            views: pmi
                .views
                .iter()
                .map(|v| {
                    if v.drawing {
                        format!("{} (drawing view)", v.name)
                    } else {
                        v.name.clone()
                    }
                })
                .collect(),
            annotations: pmi
                .annotations
                .iter()
                .map(|a| {
                    format!(
                        "{}  ({} faces, {} points)",
                        a.name,
                        a.faces.len(),
                        a.point_count()
                    )
                })
                .collect(),
            semantic: pmi
                .semantic
                .items
                .iter()
                .enumerate()
                .map(|(k, item)| {
                    let text = cadre_render::pmi::semantic_text(item);
                    let faces = item.faces().len();
                    if presented.contains(&k) {
                        format!("{text}  ({faces} faces, presented)")
                    } else {
                        format!("{text}  ({faces} faces)")
                    }
                })
                .collect(),
        }
    }
}

/// A measurement as a dimension to draw and keep.
fn dimension_of(m: &Measurement) -> cadre_render::dimensions::Dimension {
    let kind = match m.tool {
        Tool::Distance => "distance",
        Tool::EdgeLength => "length",
        Tool::Radius => "radius",
        Tool::Angle => "angle",
    };
    cadre_render::dimensions::Dimension {
        kind: kind.into(),
        value: m.value,
        text: cadre_render::dimensions::value_text(kind, m.value),
        points: m.points.iter().map(|p| p.to_array()).collect(),
    }
}

/// A kept dimension as a measurement of the session (an unknown kind reads as a distance).
fn measurement_of(d: &cadre_render::dimensions::Dimension) -> Measurement {
    let tool = match d.kind.as_str() {
        "length" => Tool::EdgeLength,
        "radius" => Tool::Radius,
        "angle" => Tool::Angle,
        _ => Tool::Distance,
    };
    Measurement {
        tool,
        value: d.value,
        text: format!("{} {}", tool.name(), d.text),
        points: d.points.iter().map(|&p| glam::DVec3::from(p)).collect(),
    }
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

/// The extent of the box `lo`..`hi` along `normal`: the least and greatest `normal · p` of
/// its corners.
fn box_extent(normal: glam::DVec3, lo: glam::DVec3, hi: glam::DVec3) -> (f64, f64) {
    (0..8)
        .map(|i| {
            glam::DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
            .dot(normal)
        })
        .fold((f64::MAX, f64::MIN), |(a, b), d| (a.min(d), b.max(d)))
}

impl Section {
    /// The section that cuts as `plane` does, its position taken across the model's box
    /// `lo`..`hi` (clamped to it); `None` for a plane without a usable normal.
    pub fn of_plane(
        plane: cadre_render::SectionPlane,
        lo: glam::DVec3,
        hi: glam::DVec3,
    ) -> Option<Section> {
        let normal = plane.normal.try_normalize()?;
        let offset = plane.offset / plane.normal.length();
        let (min, max) = box_extent(normal, lo, hi);
        let position = if max > min {
            (offset - min) / (max - min)
        } else {
            0.5
        };
        Some(Section {
            enabled: true,
            normal,
            position: position.clamp(0.0, 1.0),
        })
    }

    /// The plane across the model's box `lo`..`hi`.
    pub fn plane(&self, lo: glam::DVec3, hi: glam::DVec3) -> cadre_render::SectionPlane {
        let (min, max) = box_extent(self.normal, lo, hi);
        cadre_render::SectionPlane {
            normal: self.normal,
            offset: min + (max - min) * self.position.clamp(0.0, 1.0),
        }
    }
}

impl Session {
    /// A session with no model, dialogs pointing at the current folder.
    pub fn new() -> Session {
        let cwd = std::env::current_dir().unwrap_or_default();
        Session {
            toolpath: None,
            show_toolpath: false,
            doc: None,
            nav: None,
            mode: DisplayMode::ShadedEdges,
            exact_faces: false,
            shadows: false,
            silhouette_fill: true,
            gradient: false,
            grid: false,
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
            show_pmi: false,
            show_pmi_window: false,
            part_labels: false,
            callout_anchors: std::cell::OnceCell::new(),
            pmi_rows: std::cell::OnceCell::new(),
            selected_dimension: None,
            pmi_view: None,
            pmi_selected: None,
            pmi_semantic_selected: None,
            properties: std::collections::HashMap::new(),
        }
    }

    /// The PMI window's rows for the open document (written the first time they are asked
    /// for), `None` without a document.
    pub fn pmi_rows(&self) -> Option<std::rc::Rc<PmiRows>> {
        let doc = self.doc.as_ref()?;
        Some(
            self.pmi_rows
                .get_or_init(|| std::rc::Rc::new(PmiRows::of(&doc.model.pmi)))
                .clone(),
        )
    }

    /// The background and the ground grid the Display menu asks for.
    pub fn backdrop(&self) -> (cadre_render::Background, Option<cadre_render::GroundGrid>) {
        (
            if self.gradient {
                cadre_render::Background::cad_gradient()
            } else {
                cadre_render::Background::Solid
            },
            self.grid.then(cadre_render::GroundGrid::default),
        )
    }

    /// A model replaced the last one: fresh styles, selection and camera.
    pub fn set_document(&mut self, doc: Document, aspect: f64) {
        let (lo, hi) = doc
            .bounds
            .unwrap_or((glam::DVec3::splat(-1.0), glam::DVec3::splat(1.0)));
        self.nav = Some(Navigator::new(lo, hi, aspect));
        self.hidden = vec![false; doc.scene.assembly.nodes.len()];
        self.colours = vec![None; doc.instances.len()];
        self.hover = None;
        self.selection.clear();
        self.tool_picks.clear();
        self.measurements.clear();
        self.selected_dimension = None;
        self.sections.clear();
        self.callout_anchors = std::cell::OnceCell::new();
        self.pmi_rows = std::cell::OnceCell::new();
        self.properties.clear();
        // The dimensions kept beside the file come back.
        match cadre_render::dimensions::DimensionFile::read(
            &cadre_render::dimensions::sidecar_path(&doc.path),
        ) {
            Ok(Some(file)) => {
                self.measurements = file.dimensions.iter().map(measurement_of).collect();
            }
            Ok(None) => {}
            Err(e) => self.error = Some(e.to_string()),
        }
        // A file with PMI opens with it shown.
        self.show_pmi =
            !doc.model.pmi.annotations.is_empty() || !doc.model.pmi.semantic.items.is_empty();
        self.pmi_view = None;
        self.pmi_selected = None;
        self.pmi_semantic_selected = None;
        self.status = format!(
            "{}: {} parts, {} faces, loaded in {:.2} s",
            doc.title(),
            doc.instances.len(),
            doc.model.faces.len(),
            doc.load_seconds
        );
        self.doc = Some(doc);
    }

    /// The PMI overlay the view draws: the chosen saved view's annotations (all of them
    /// without one), or nothing when PMI is off. The generated callouts of semantic PMI are
    /// laid out per view with the part names ([`Session::view_callouts`]).
    pub fn pmi_overlay(&self, background: [f32; 4]) -> Option<cadre_render::pmi::PmiOverlay> {
        let doc = self.doc.as_ref()?;
        if !self.show_pmi || doc.model.pmi.is_empty() {
            return None;
        }
        let pmi = &doc.model.pmi;
        let view = self.pmi_view.and_then(|k| pmi.views.get(k));
        let placements = cadre_render::pmi::Placements::of(&doc.model);
        Some(cadre_render::pmi::overlay(
            pmi,
            view,
            background,
            &placements,
        ))
    }

    /// Whether the view lays out callouts: the part names, or generated PMI callouts (PMI
    /// shown without a saved view, which shows only what its author placed).
    pub fn wants_callouts(&self) -> bool {
        self.part_labels || (self.show_pmi && self.pmi_view.is_none())
    }

    /// The callouts for `camera` on a `size` view, laid out together so that no two boxes
    /// overlap: the part names (when on) and the semantic PMI no annotation presents (when
    /// PMI is shown without a saved view); how many did not fit.
    pub fn view_callouts(
        &self,
        camera: &cadre_render::Camera,
        size: (u32, u32),
    ) -> cadre_render::text::leaders::Callouts {
        let Some(doc) = self.doc.as_ref() else {
            return Default::default();
        };
        let (parts, pmi) = self.callout_anchors.get_or_init(|| {
            let placements = cadre_render::pmi::Placements::of(&doc.model);
            (
                cadre_render::text::leaders::part_anchors(&doc.scene.assembly),
                cadre_render::pmi::semantic_anchors(&doc.model, &placements),
            )
        });
        let mut anchors = Vec::new();
        if self.part_labels {
            anchors.extend_from_slice(parts);
        }
        if self.show_pmi && self.pmi_view.is_none() {
            anchors.extend_from_slice(pmi);
        }
        if anchors.is_empty() {
            return Default::default();
        }
        cadre_render::text::leaders::lay_out_callouts(&anchors, doc.bounds, camera, size, 11.0)
    }

    /// Chooses saved view `k` of the model's PMI: its annotations alone are drawn, and the
    /// camera turns (animated) to its direction and projection.
    pub fn choose_saved_view(&mut self, k: usize, aspect: f64) {
        let (Some(doc), Some(nav)) = (&self.doc, &mut self.nav) else {
            return;
        };
        let Some(view) = doc.model.pmi.views.get(k) else {
            return;
        };
        let placements = cadre_render::pmi::Placements::of(&doc.model);
        let placement = placements.get(view.part)[0];
        let v = |p: cadre_geom::Vec3| placement.transform_vector3(glam::DVec3::new(p.x, p.y, p.z));
        nav.orthographic = view.parallel;
        nav.view_along((-v(view.direction), v(view.up)), aspect);
        // The view's clipping planes become its sections (a saved view is a whole display
        // state: the sections set before give way to it).
        if let Some((lo, hi)) = doc.bounds {
            self.sections = cadre_render::pmi::saved_view_sections(view, &placements)
                .into_iter()
                .filter_map(|p| Section::of_plane(p, lo, hi))
                .collect();
        }
        self.pmi_view = Some(k);
        self.show_pmi = true;
    }

    /// Chooses annotation `k`: the faces it applies to become the selection (on every
    /// placement of the part: PMI belongs to the part).
    pub fn choose_annotation(&mut self, k: usize) {
        let Some(doc) = &self.doc else { return };
        let Some(annotation) = doc.model.pmi.annotations.get(k) else {
            return;
        };
        let faces = annotation.faces.clone();
        self.pmi_selected = Some(k);
        self.pmi_semantic_selected = None;
        self.select_faces(&faces);
    }

    /// Chooses semantic PMI item `k` (a dimension, tolerance or datum): the faces it applies
    /// to become the selection.
    pub fn choose_semantic(&mut self, k: usize) {
        let Some(doc) = &self.doc else { return };
        let Some(item) = doc.model.pmi.semantic.items.get(k) else {
            return;
        };
        let faces = item.faces().to_vec();
        self.pmi_semantic_selected = Some(k);
        self.pmi_selected = None;
        self.select_faces(&faces);
    }

    /// Makes `faces` (on every instance) the selection.
    fn select_faces(&mut self, faces: &[cadre_brep::FaceId]) {
        let Some(doc) = &self.doc else { return };
        self.selection.clear();
        for instance in 0..doc.instances.len() as u32 {
            for face in faces {
                let pick = Pick::Face {
                    instance,
                    face: cadre_mesh::scene::SceneIds::face_id(*face),
                };
                self.selection.push(crate::inspect::Picked {
                    pick,
                    point: doc
                        .bounds
                        .map_or(glam::DVec3::ZERO, |(lo, hi)| 0.5 * (lo + hi)),
                });
            }
        }
    }

    /// The measurements as the renderer draws and the file beside the model keeps them.
    pub fn dimensions(&self) -> Vec<cadre_render::dimensions::Dimension> {
        self.measurements.iter().map(dimension_of).collect()
    }

    /// Writes the measurements beside the model file (`FILE.dimensions.json`); a failure is
    /// shown, the measurements kept.
    pub fn save_dimensions(&mut self) {
        let Some(doc) = &self.doc else { return };
        let path = cadre_render::dimensions::sidecar_path(&doc.path);
        let file = cadre_render::dimensions::DimensionFile {
            dimensions: self.dimensions(),
        };
        if let Err(e) = file.write(&path) {
            self.error = Some(e.to_string());
        }
    }

    /// Deletes measurement `k` (and from the file beside the model).
    pub fn delete_measurement(&mut self, k: usize) {
        if k < self.measurements.len() {
            self.measurements.remove(k);
            self.selected_dimension = match self.selected_dimension {
                Some(s) if s == k => None,
                Some(s) if s > k => Some(s - 1),
                other => other,
            };
            self.save_dimensions();
        }
    }

    /// The renderer's view state: visibility, colours, hover and selection.
    pub fn view_state(&self) -> cadre_render::ViewState {
        let Some(doc) = &self.doc else {
            return cadre_render::ViewState {
                lines: self.line_view(),
                ..cadre_render::ViewState::default()
            };
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
            lines: self.line_view(),
        }
    }

    /// What of the toolpath is shown: up to the simulation slider's distance, inside the
    /// clipping box when it is on.
    pub fn line_view(&self) -> cadre_render::LineView {
        self.toolpath
            .as_ref()
            .map(Toolpath::line_view)
            .unwrap_or_default()
    }

    /// A program opened: shown over the model (framed alone when no model is open).
    pub fn set_toolpath(&mut self, toolpath: Toolpath, aspect: f64) {
        if self.nav.is_none()
            && let Some((lo, hi)) = toolpath.bounds
        {
            self.nav = Some(Navigator::new(lo, hi, aspect));
        }
        self.status = format!(
            "{}: {} moves, {:.1} mm of path, {} warnings",
            toolpath.path.display(),
            toolpath.program.moves.len(),
            toolpath.travel,
            toolpath.program.warnings.len()
        );
        self.show_toolpath = true;
        self.toolpath = Some(toolpath);
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
                            self.save_dimensions();
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

    /// Takes `tool` for the next clicks (the picks so far are dropped).
    pub fn choose_tool(&mut self, tool: Tool) {
        self.tool = Some(tool);
        self.tool_picks.clear();
        self.tool_message = Some(format!("{}: pick {} item(s)", tool.name(), tool.picks()));
    }

    /// Takes `tool`, or stops measuring when it is the one in use.
    pub fn toggle_tool(&mut self, tool: Tool) {
        if self.tool == Some(tool) {
            self.stop_measuring();
        } else {
            self.choose_tool(tool);
        }
    }

    /// Clicks select again; finished measurements stay.
    pub fn stop_measuring(&mut self) {
        self.tool = None;
        self.tool_picks.clear();
        self.tool_message = None;
    }

    /// Selects the whole part of instance `instance` alone (from the model tree).
    pub fn select_part(&mut self, instance: usize) {
        self.selection = vec![Picked {
            pick: Pick::Part {
                instance: instance as u32,
            },
            point: glam::DVec3::ZERO,
        }];
    }

    /// Shows every node again.
    pub fn show_all(&mut self) {
        self.hidden.iter_mut().for_each(|h| *h = false);
    }

    /// Hides the parts of the selected items and clears the selection.
    pub fn hide_selected(&mut self) {
        let Some(doc) = &self.doc else { return };
        for p in &self.selection {
            if let Some(info) = doc.instances.get(p.pick.instance() as usize)
                && let Some(h) = self.hidden.get_mut(info.node)
            {
                *h = true;
            }
        }
        self.selection.clear();
    }

    /// A section across the middle of the model, normal to y, or none when any exists.
    pub fn toggle_quick_section(&mut self) {
        if self.sections.is_empty() {
            self.sections.push(Section {
                enabled: true,
                normal: glam::DVec3::Y,
                position: 0.5,
            });
        } else {
            self.sections.clear();
        }
    }

    /// The next display mode of [`DISPLAY_MODES`], round.
    pub fn next_mode(&mut self) {
        let k = DISPLAY_MODES
            .iter()
            .position(|(_, m)| *m == self.mode)
            .unwrap_or(0);
        self.mode = DISPLAY_MODES[(k + 1) % DISPLAY_MODES.len()].1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// A copy of the bundled pin assembly in a folder of the test's own (measurements are
    /// kept beside the file: not beside the repository's example).
    fn document() -> Document {
        static COUNT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("cadre-session-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        let path = dir.join("pin-assembly.step");
        let example =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pin-assembly.step");
        std::fs::copy(example, &path).expect("copied");
        Document::load(&path, &|_| {}).expect("the example loads")
    }

    /// A session with the pin assembly open.
    fn session() -> Session {
        let mut s = Session::new();
        s.set_document(document(), 1.5);
        s
    }

    fn face(instance: u32, face: u32) -> Picked {
        Picked {
            pick: Pick::Face { instance, face },
            point: glam::DVec3::ZERO,
        }
    }

    #[test]
    fn a_toolpath_opens_alone_and_its_slider_and_box_make_the_line_view() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/toolpath/plate.ngc");
        assert!(Toolpath::is_program(&path));
        assert!(!Toolpath::is_program(Path::new("part.step")));
        let toolpath = Toolpath::load(&path).expect("the example program loads");
        assert!(toolpath.program.warnings.is_empty());
        assert!(toolpath.travel > 1000.0, "{}", toolpath.travel);
        let mut s = Session::new();
        s.set_toolpath(toolpath, 1.5);
        // Without a model the view frames the path.
        assert!(s.nav.is_some() && s.show_toolpath);
        assert_eq!(s.view_state().lines, cadre_render::LineView::default());
        let tp = s.toolpath.as_mut().expect("open");
        tp.simulate = true;
        tp.up_to = 100.0;
        tp.clip = true;
        tp.clip_box = [[10.0, 0.0, 0.0], [-10.0, 50.0, 20.0]];
        let view = s.view_state().lines;
        assert_eq!(view.up_to, Some(100.0));
        assert_eq!(
            view.clip_box,
            Some((
                glam::DVec3::new(-10.0, 0.0, 0.0),
                glam::DVec3::new(10.0, 50.0, 20.0)
            ))
        );
        // A model opened after keeps the toolpath over it.
        s.set_document(document(), 1.5);
        assert_eq!(s.view_state().lines.up_to, Some(100.0));
    }

    #[test]
    fn a_click_selects_ctrl_click_toggles_and_a_click_on_nothing_clears() {
        let mut s = session();
        s.clicked(Some(face(0, 1)), false);
        s.clicked(Some(face(1, 2)), true);
        assert_eq!(s.selection, vec![face(0, 1), face(1, 2)]);
        s.clicked(Some(face(0, 1)), true);
        assert_eq!(s.selection, vec![face(1, 2)]);
        s.clicked(None, true);
        assert_eq!(s.selection, vec![face(1, 2)], "ctrl-click on nothing keeps");
        s.clicked(Some(face(0, 3)), false);
        assert_eq!(s.selection, vec![face(0, 3)]);
        s.clicked(None, false);
        assert!(s.selection.is_empty());
        s.select_part(1);
        assert_eq!(s.selection.len(), 1);
        assert_eq!(s.selection[0].pick, Pick::Part { instance: 1 });
    }

    #[test]
    fn a_tool_takes_the_clicks_and_measures_when_it_has_enough() {
        let mut s = session();
        s.clicked(Some(face(0, 1)), false);
        s.choose_tool(Tool::Distance);
        let a = Picked {
            pick: Pick::Part { instance: 0 },
            point: glam::DVec3::ZERO,
        };
        let b = Picked {
            point: glam::DVec3::new(3.0, 4.0, 0.0),
            ..a
        };
        s.clicked(Some(a), false);
        assert_eq!(s.tool_picks.len(), 1);
        assert!(s.measurements.is_empty());
        s.clicked(None, false);
        assert_eq!(s.tool_picks.len(), 1, "a click on nothing is no pick");
        s.clicked(Some(b), false);
        assert!(s.tool_picks.is_empty());
        assert_eq!(s.measurements.len(), 1);
        assert!((s.measurements[0].value - 5.0).abs() < 1e-12);
        assert_eq!(s.selection, vec![face(0, 1)], "the selection is left alone");
        // The tool's picks show as selected in the view state.
        s.clicked(Some(a), false);
        assert_eq!(s.view_state().selection.len(), 2);
        s.toggle_tool(Tool::Distance);
        assert_eq!((s.tool, s.tool_picks.len()), (None, 0));
    }

    #[test]
    fn isolate_hides_every_other_part_and_keeps_the_kept_parts_ancestors() {
        let mut s = session();
        let doc = document();
        assert!(doc.instances.len() >= 2);
        s.selection = vec![face(1, 0)];
        s.isolate();
        let state = s.view_state();
        let visible: Vec<bool> = state.instances.iter().map(|i| i.visible).collect();
        assert!(visible[1]);
        assert!(
            visible.iter().enumerate().all(|(i, v)| *v == (i == 1)),
            "{visible:?}"
        );
        let mut n = doc.parents[doc.instances[1].node];
        while let Some(node) = n {
            assert!(!s.hidden[node], "ancestor {node} hidden");
            n = doc.parents[node];
        }
        // Negative control: nothing selected isolates nothing.
        s.show_all();
        s.selection.clear();
        s.isolate();
        assert!(s.view_state().instances.iter().all(|i| i.visible));
    }

    #[test]
    fn hiding_the_selection_hides_its_parts_and_clears_it() {
        let mut s = session();
        s.selection = vec![face(0, 0)];
        s.hide_selected();
        assert!(s.selection.is_empty());
        let state = s.view_state();
        assert!(!state.instances[0].visible);
        assert!(state.instances[1..].iter().all(|i| i.visible));
        s.show_all();
        assert!(s.view_state().instances.iter().all(|i| i.visible));
    }

    #[test]
    fn the_view_state_carries_colours_hover_and_enabled_sections() {
        let mut s = session();
        s.colours[0] = Some([1.0, 0.0, 0.0, 0.5]);
        s.hover = Some(face(0, 2));
        s.toggle_quick_section();
        s.sections.push(Section {
            enabled: false,
            normal: glam::DVec3::X,
            position: 0.1,
        });
        let state = s.view_state();
        let colour = state.instances[0].colour.expect("colour");
        assert!((colour[0] - 1.0).abs() < 1e-6 && colour[1] == 0.0 && colour[3] == 0.5);
        assert_eq!(state.instances[1].colour, None);
        assert_eq!(state.hover, Some(face(0, 2).pick));
        assert_eq!(state.sections.len(), 1, "the disabled plane does not cut");
        // The quick section halves the model's box along y.
        let (lo, hi) = s.doc.as_ref().unwrap().bounds.unwrap();
        let plane = state.sections[0];
        assert_eq!(plane.normal, glam::DVec3::Y);
        assert!((plane.offset - 0.5 * (lo.y + hi.y)).abs() < 1e-9 * (hi - lo).length());
        s.toggle_quick_section();
        assert!(s.view_state().sections.is_empty());
    }

    #[test]
    fn a_section_spans_the_box_along_its_normal() {
        let (lo, hi) = (
            glam::DVec3::new(-1.0, 0.0, 0.0),
            glam::DVec3::new(3.0, 2.0, 1.0),
        );
        let mut section = Section {
            enabled: true,
            normal: glam::DVec3::new(1.0, 1.0, 0.0).normalize(),
            position: 0.0,
        };
        let at = |s: &Section| s.plane(lo, hi).offset;
        let k = std::f64::consts::FRAC_1_SQRT_2;
        assert!((at(&section) + k).abs() < 1e-12);
        section.position = 1.0;
        assert!((at(&section) - 5.0 * k).abs() < 1e-12);
        section.position = 7.0;
        assert!((at(&section) - 5.0 * k).abs() < 1e-12, "clamped");
    }

    #[test]
    fn the_mode_key_walks_every_mode_round() {
        let mut s = Session::new();
        let start = s.mode;
        let mut seen = vec![start];
        for _ in 1..DISPLAY_MODES.len() {
            s.next_mode();
            seen.push(s.mode);
        }
        s.next_mode();
        assert_eq!(s.mode, start);
        seen.sort_by_key(|m| format!("{m:?}"));
        seen.dedup();
        assert_eq!(seen.len(), DISPLAY_MODES.len());
    }

    #[test]
    fn a_new_document_clears_the_last_ones_state() {
        let mut s = session();
        s.selection = vec![face(0, 0)];
        s.toggle_quick_section();
        s.properties.insert(face(0, 0).pick, Vec::new());
        s.set_document(document(), 1.0);
        assert!(s.selection.is_empty() && s.sections.is_empty() && s.properties.is_empty());
        assert!(s.status.contains("pin-assembly.step"), "{}", s.status);
    }

    #[test]
    fn part_labels_name_every_placed_part_for_the_view() {
        let mut s = session();
        let camera = s.nav.as_ref().expect("a view").camera();
        assert!(
            s.view_callouts(&camera, (800, 600))
                .labels
                .labels
                .is_empty(),
            "off by default"
        );
        s.part_labels = true;
        let labels = s.view_callouts(&camera, (800, 600)).labels;
        let doc = s.doc.as_ref().expect("open");
        assert_eq!(labels.labels.len(), doc.instances.len());
        assert!(
            labels
                .labels
                .iter()
                .all(|l| l.leader.is_some() && !l.text.is_empty())
        );
    }

    #[test]
    fn measurements_are_kept_beside_the_file_and_deleted_from_it() {
        let mut s = session();
        let path = cadre_render::dimensions::sidecar_path(&s.doc.as_ref().expect("open").path);
        assert!(!path.exists());
        s.measurements.push(Measurement {
            tool: Tool::Distance,
            value: 5.0,
            text: "Minimum distance 5 mm".into(),
            points: vec![glam::DVec3::ZERO, glam::DVec3::new(0.0, 0.0, 5.0)],
        });
        s.save_dimensions();
        assert!(path.exists());
        // Opened again, the file's dimensions come back.
        let doc = Document::load(&s.doc.as_ref().expect("open").path, &|_| {}).expect("loads");
        let mut again = Session::new();
        again.set_document(doc, 1.5);
        assert_eq!(again.measurements.len(), 1);
        assert_eq!(again.measurements[0].points, s.measurements[0].points);
        assert_eq!(again.dimensions()[0].text, "5.000 mm");
        again.selected_dimension = Some(0);
        again.delete_measurement(0);
        assert!(again.measurements.is_empty() && !path.exists());
        assert_eq!(again.selected_dimension, None);
        let _ = std::fs::remove_dir_all(path.parent().expect("folder"));
    }

    #[test]
    fn a_clipped_saved_view_becomes_sections_across_the_model() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pmi/block-pmi.step");
        let mut doc = Document::load(&path, &|_| {}).expect("the example loads");
        let (lo, hi) = doc.bounds.expect("a box");
        let centre = (lo + hi) / 2.0;
        let c = cadre_geom::Vec3::new(centre.x, centre.y, centre.z);
        doc.model.pmi.views[0].clip_planes = vec![(c, cadre_geom::Vec3::X)];
        let mut s = Session::new();
        s.set_document(doc, 1.5);
        // A section set before gives way to the view's.
        s.sections.push(Section {
            enabled: true,
            normal: glam::DVec3::Z,
            position: 0.2,
        });
        s.choose_saved_view(0, 1.5);
        assert_eq!(s.sections.len(), 1);
        let section = &s.sections[0];
        assert!(section.enabled);
        assert_eq!(section.normal, glam::DVec3::X);
        assert!(
            (section.position - 0.5).abs() < 1e-9,
            "{}",
            section.position
        );
        // The plane it draws is the view's: through the centre, cutting away +x.
        let plane = section.plane(lo, hi);
        assert!(plane.keeps(centre - glam::DVec3::X) && !plane.keeps(centre + glam::DVec3::X));
        // Negative control: a view without clipping leaves no section.
        if let Some(doc) = s.doc.as_mut() {
            doc.model.pmi.views[0].clip_planes.clear();
        }
        s.choose_saved_view(0, 1.5);
        assert!(s.sections.is_empty());
    }

    #[test]
    fn pmi_shows_its_saved_views_and_an_annotation_selects_its_faces() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/pmi/block-pmi.step");
        let mut s = Session::new();
        s.set_document(
            Document::load(&path, &|_| {}).expect("the example loads"),
            1.5,
        );
        assert!(s.show_pmi, "a file with PMI opens with it shown");
        let white = [1.0, 1.0, 1.0, 1.0];
        let all = s.pmi_overlay(white).expect("drawn");
        assert_eq!(all.annotations, 1);
        // The callout's two texts; the two generated callouts (the length, datum A) are laid
        // out for the view, in the PMI colour.
        assert_eq!(all.labels.labels.len(), 2);
        let camera = s.nav.as_ref().expect("a view").camera();
        assert!(s.wants_callouts());
        let generated = s.view_callouts(&camera, (800, 600)).labels;
        assert_eq!(generated.labels.len(), 2);
        assert!(
            generated
                .labels
                .iter()
                .all(|l| l.colour == cadre_render::pmi::PMI_COLOUR && l.leader.is_some())
        );
        s.choose_saved_view(0, 1.5);
        assert_eq!(s.pmi_view, Some(0));
        assert!(s.nav.as_ref().is_some_and(|n| n.orthographic));
        // A saved view shows its own annotations, without generated callouts.
        assert_eq!(s.pmi_overlay(white).expect("drawn").labels.labels.len(), 2);
        assert!(!s.wants_callouts());
        assert!(
            s.view_callouts(&camera, (800, 600))
                .labels
                .labels
                .is_empty()
        );
        // A semantic item selects its faces too: datum A, on the block's bottom.
        let datum = s
            .doc
            .as_ref()
            .expect("open")
            .model
            .pmi
            .semantic
            .items
            .iter()
            .position(|i| matches!(i, cadre_brep::pmi::SemanticItem::Datum { .. }))
            .expect("datum A");
        s.choose_semantic(datum);
        assert_eq!(s.pmi_semantic_selected, Some(datum));
        assert_eq!(s.selection.len(), 1);
        s.choose_annotation(0);
        assert_eq!(s.pmi_semantic_selected, None);
        assert_eq!(s.selection.len(), 1);
        assert!(matches!(
            s.selection[0].pick,
            Pick::Face { instance: 0, .. }
        ));
        s.show_pmi = false;
        assert!(s.pmi_overlay(white).is_none());
        // Negative control: the pin assembly has none.
        assert!(session().pmi_overlay(white).is_none() && !session().show_pmi);
        // The window's rows, written once per document: a row per saved view, annotation
        // and semantic item; the next document gets its own.
        let rows = s.pmi_rows().expect("a document");
        let pmi = &s.doc.as_ref().expect("open").model.pmi;
        assert_eq!(rows.views.len(), pmi.views.len());
        assert_eq!(rows.annotations.len(), 1);
        assert_eq!(rows.semantic.len(), pmi.semantic.items.len());
        assert!(
            rows.summary.starts_with("1 annotations"),
            "{}",
            rows.summary
        );
        assert!(rows.semantic[datum].starts_with('A'), "{:?}", rows.semantic);
        assert!(std::rc::Rc::ptr_eq(&rows, &s.pmi_rows().expect("again")));
        let pins = session();
        assert!(pins.pmi_rows().expect("a document").annotations.is_empty());
        assert!(Session::new().pmi_rows().is_none());
    }
}
