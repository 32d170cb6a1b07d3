//! What is drawn over the 3D view: the axis gizmo, dimension lines, the hovered vertex.

use egui::{Color32, Pos2, Sense, Stroke, Vec2};

use super::Action;
use crate::gizmo;
use crate::inspect;
use crate::session::Session;

/// The axis gizmo and the hovered vertex, over the view (the measurements' dimensions are
/// drawn by the renderer, `cadre_render::dimensions`).
pub(super) fn overlay(
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
    // The hovered vertex as a dot (vertices are not drawn otherwise).
    if let (Some(hover), Some(doc)) = (&s.hover, &s.doc)
        && let Some(p) = inspect::vertex_position(doc, hover.pick).and_then(to_screen)
    {
        painter.circle_filled(p, 5.0, Color32::from_rgb(80, 190, 255));
    }
}
