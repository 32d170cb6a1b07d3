//! The open toolpath in the 3D view: its lines sampled for the current zoom (arcs within a
//! quarter pixel, sampled again when the view's scale changes by 2×), coloured as the
//! Toolpath window asks, and the tool drawn as an exact cylinder where the simulation is.

use cadre_render::lines::toolpath::{
    ColourBy, ToolpathStyle, pixel_tolerance, tool_marker, toolpath_lines,
};
use cadre_render::{Gpu, InstanceStyle, LineSet, PreparedScene, RenderScene, Renderer, ViewState};

use crate::session::Toolpath;

/// The toolpath as the prepared scene holds it.
pub(crate) struct DrawnToolpath {
    /// What colours it was sampled with.
    colour_by: ColourBy,
    /// The view height (model units) its arcs were sampled for.
    view_height: f64,
    /// The tool's diameter the scene's marker has.
    pub diameter: f64,
    /// Its lines (for the tool's place along them).
    lines: LineSet,
    /// The tool marker's index among the scene's primitives.
    tool: Option<usize>,
    /// Other lines of the scene (the PMI's), kept when the toolpath's are sampled again.
    pub extra: LineSet,
}

/// Lines for `toolpath` sampled for a view `view_height` model units over `rows` pixels.
fn lines_for(toolpath: &Toolpath, view_height: f64, rows: u32) -> LineSet {
    let style = ToolpathStyle {
        colour_by: toolpath.colour_by,
        ..ToolpathStyle::default()
    };
    toolpath_lines(
        &toolpath.program,
        &style,
        pixel_tolerance(view_height, rows),
    )
}

/// `scene` with `toolpath`'s lines and its tool (at the path's start), sampled for the view.
pub(crate) fn add_toolpath(
    mut scene: RenderScene,
    toolpath: &Toolpath,
    (view_height, rows): (f64, u32),
) -> (RenderScene, DrawnToolpath) {
    let lines = lines_for(toolpath, view_height, rows);
    let start = lines.point_at_travel(0.0).unwrap_or_default();
    let diameter = toolpath.tool_diameter.max(1e-3);
    let marker = tool_marker(start, diameter);
    let tool = marker.map(|m| {
        scene.primitives.push(m);
        scene.primitives.len() - 1
    });
    scene.lines = lines.clone();
    (
        scene,
        DrawnToolpath {
            colour_by: toolpath.colour_by,
            view_height,
            diameter,
            lines,
            tool,
            extra: LineSet::default(),
        },
    )
}

impl DrawnToolpath {
    /// Samples the lines again where the colours or the zoom (past 2×) changed, and moves
    /// the tool to where the simulation is.
    pub fn update(
        &mut self,
        (gpu, renderer): (&Gpu, &Renderer),
        prepared: &mut PreparedScene,
        toolpath: &Toolpath,
        (view_height, rows): (f64, u32),
    ) {
        let ratio = view_height / self.view_height.max(1e-300);
        if self.colour_by != toolpath.colour_by || !(0.5..=2.0).contains(&ratio) {
            self.lines = lines_for(toolpath, view_height, rows);
            let mut all = self.lines.clone();
            all.extend(self.extra.clone());
            renderer.replace_lines(gpu, prepared, &all);
            self.colour_by = toolpath.colour_by;
            self.view_height = view_height;
        }
        // (Walking the path for the tool's place only while it is shown.)
        let tip = toolpath
            .simulate
            .then(|| self.lines.point_at_travel(toolpath.up_to))
            .flatten();
        if let (Some(k), Some(tip)) = (self.tool, tip) {
            prepared.move_primitive(
                k,
                cadre_geom::Frame {
                    origin: tip,
                    ..cadre_geom::Frame::WORLD
                },
            );
        }
    }

    /// `state` with the tool shown only while simulating.
    pub fn show_tool(&self, state: &mut ViewState, prepared: &PreparedScene, simulate: bool) {
        if let Some(k) = self.tool {
            let instance = prepared.primitive_instance(k) as usize;
            if state.instances.len() <= instance {
                state
                    .instances
                    .resize(instance + 1, InstanceStyle::default());
            }
            state.instances[instance].visible = simulate;
        }
    }
}
