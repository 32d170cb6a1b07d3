//! A viewer's viewport: render targets kept between frames, and picking from the last frame.

use crate::gpu_scene::PickRun;
use crate::layout::FrameUniform;
use crate::passes::visibility::VisibilityTargets;
use crate::view::{Pick, section_cap};
use crate::{Gpu, RenderError};

/// What the pick pass needs of the last frame drawn into a viewport: its uniform, its
/// camera-relative view-projection in `f64` (cropped to the pick window) and its visible
/// runs' edges and vertices.
pub(crate) struct LastFrame {
    pub frame: FrameUniform,
    pub view_proj: glam::DMat4,
    pub pick_runs: Vec<PickRun>,
}

/// Render targets of one size, kept between a viewer's frames (made once per window size),
/// with what the last frame drew, for [`crate::Renderer::pick`].
pub struct Viewport {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    pub(crate) targets: VisibilityTargets,
    /// The per-frame buffers, refilled by every frame.
    pub(crate) buffers: crate::frame_buffers::FrameBuffers,
    pub(crate) last: Option<LastFrame>,
}

impl Viewport {
    /// Targets of `width` × `height` (at least 1 × 1).
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Viewport {
        let (width, height) = (width.max(1), height.max(1));
        Viewport {
            width,
            height,
            targets: VisibilityTargets::new(&gpu.device, (width, height), false),
            buffers: crate::frame_buffers::FrameBuffers::new(&gpu.device),
            last: None,
        }
    }

    /// This viewport if it has the size, else a new one of `width` × `height`.
    pub fn resized(self, gpu: &Gpu, width: u32, height: u32) -> Result<Viewport, RenderError> {
        let max = gpu.max_side();
        if width > max || height > max {
            return Err(RenderError::Size { width, height, max });
        }
        Ok(
            if (self.width, self.height) == (width.max(1), height.max(1)) {
                self
            } else {
                Viewport::new(gpu, width, height)
            },
        )
    }
}

/// The ids in a small window of a frame: faces from the visibility buffer, edges and
/// vertices from the pick pass. Made by [`crate::Renderer::pick`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PickWindow {
    /// Left column of the window in the frame.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width (smaller than asked at the frame's borders).
    pub width: u32,
    /// Height.
    pub height: u32,
    /// The cursor's pixel in the frame.
    pub cursor: (u32, u32),
    /// Per pixel, row by row: face id, instance + 1 (0 = background), material (with
    /// [`crate::SECTION_CAP`] on section caps), depth (`f32` bits).
    pub faces: Vec<[u32; 4]>,
    /// Per pixel: edge or vertex id, instance + 1 (0 = nothing), kind (2 edge, 3 vertex), 0.
    pub lines: Vec<[u32; 4]>,
}

/// What a pick found, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PickHit {
    /// The item.
    pub pick: Pick,
    /// The frame pixel it was found at.
    pub pixel: (u32, u32),
    /// Reverse-Z depth of the nearest surface at that pixel, or of the face under the
    /// cursor for edges and vertices off every surface (0 when there is none).
    pub depth: f32,
}

impl PickWindow {
    /// The window of `radius` pixels each way around `cursor`, clipped to the frame (ids
    /// still empty).
    pub(crate) fn around(
        frame_width: u32,
        frame_height: u32,
        (cx, cy): (u32, u32),
        radius: u32,
    ) -> PickWindow {
        if cx >= frame_width || cy >= frame_height {
            return PickWindow::default();
        }
        let x = cx.saturating_sub(radius);
        let y = cy.saturating_sub(radius);
        let right = cx.saturating_add(radius).min(frame_width - 1);
        let bottom = cy.saturating_add(radius).min(frame_height - 1);
        PickWindow {
            x,
            y,
            width: right - x + 1,
            height: bottom - y + 1,
            cursor: (cx, cy),
            faces: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// The face under the cursor, if any.
    pub fn face(&self) -> Option<PickHit> {
        let (cx, cy) = self.cursor;
        let i = self.index(cx, cy)?;
        let f = self.faces.get(i)?;
        (f[1] != 0).then(|| PickHit {
            // A section cap is no B-Rep face: it picks its part.
            pick: if section_cap(*f).is_some() {
                Pick::Part { instance: f[1] - 1 }
            } else {
                Pick::Face {
                    instance: f[1] - 1,
                    face: f[0],
                }
            },
            pixel: (cx, cy),
            depth: f32::from_bits(f[3]),
        })
    }

    /// The nearest vertex within `radius` pixels of the cursor, else the nearest edge, else
    /// the face under the cursor: the priority CAD users expect (small things first).
    pub fn nearest(&self, radius: f32) -> Option<PickHit> {
        self.nearest_line(3, radius)
            .or_else(|| self.nearest_line(2, radius))
            .or_else(|| self.face())
    }

    /// The nearest pixel of the pick target of `kind` within `radius` of the cursor.
    fn nearest_line(&self, kind: u32, radius: f32) -> Option<PickHit> {
        let (cx, cy) = self.cursor;
        let mut best: Option<(f32, PickHit)> = None;
        for row in 0..self.height {
            for col in 0..self.width {
                let (px, py) = (self.x + col, self.y + row);
                let i = (row * self.width + col) as usize;
                let Some(l) = self.lines.get(i) else { continue };
                if l[1] == 0 || l[2] != kind {
                    continue;
                }
                let d = (px as f32 - cx as f32).hypot(py as f32 - cy as f32);
                if d > radius || best.is_some_and(|(b, _)| b <= d) {
                    continue;
                }
                let instance = l[1] - 1;
                let pick = if kind == 3 {
                    Pick::Vertex {
                        instance,
                        vertex: l[0],
                    }
                } else {
                    Pick::Edge {
                        instance,
                        edge: l[0],
                    }
                };
                let depth = self
                    .faces
                    .get(i)
                    .filter(|f| f[1] != 0)
                    .or_else(|| self.index(cx, cy).and_then(|c| self.faces.get(c)))
                    .map_or(0.0, |f| f32::from_bits(f[3]));
                best = Some((
                    d,
                    PickHit {
                        pick,
                        pixel: (px, py),
                        depth,
                    },
                ));
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// Index of frame pixel (`px`, `py`) in the window's arrays.
    fn index(&self, px: u32, py: u32) -> Option<usize> {
        let (col, row) = (px.checked_sub(self.x)?, py.checked_sub(self.y)?);
        (col < self.width && row < self.height).then_some((row * self.width + col) as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 7 × 7 window around (10, 10) with face 5 of instance 0 everywhere.
    fn window() -> PickWindow {
        let mut w = PickWindow::around(100, 100, (10, 10), 3);
        let n = (w.width * w.height) as usize;
        w.faces = vec![[5, 1, 0, 0.5f32.to_bits()]; n];
        w.lines = vec![[0; 4]; n];
        w
    }

    fn set_line(w: &mut PickWindow, (px, py): (u32, u32), id: u32, kind: u32) {
        let i = w.index(px, py).unwrap();
        w.lines[i] = [id, 2, kind, 0];
    }

    #[test]
    fn the_window_is_clipped_at_the_frame_borders() {
        let w = PickWindow::around(100, 50, (1, 49), 4);
        assert_eq!((w.x, w.y, w.width, w.height), (0, 45, 6, 5));
        assert_eq!(PickWindow::around(100, 50, (100, 0), 4).width, 0);
    }

    #[test]
    fn a_face_alone_is_picked_under_the_cursor() {
        let hit = window().nearest(3.0).unwrap();
        assert_eq!(
            hit.pick,
            Pick::Face {
                instance: 0,
                face: 5
            }
        );
        assert_eq!(hit.depth, 0.5);
    }

    #[test]
    fn an_edge_within_the_tolerance_beats_the_face_and_the_nearest_edge_wins() {
        let mut w = window();
        set_line(&mut w, (12, 10), 77, 2);
        set_line(&mut w, (10, 11), 78, 2);
        let hit = w.nearest(3.0).unwrap();
        assert_eq!(
            hit.pick,
            Pick::Edge {
                instance: 1,
                edge: 78
            }
        );
        assert_eq!(hit.pixel, (10, 11));
        // Out of tolerance: the face.
        assert!(matches!(w.nearest(0.5).unwrap().pick, Pick::Face { .. }));
    }

    #[test]
    fn a_vertex_beats_a_nearer_edge() {
        let mut w = window();
        set_line(&mut w, (10, 10), 78, 2);
        set_line(&mut w, (12, 12), 9, 3);
        assert_eq!(
            w.nearest(3.0).unwrap().pick,
            Pick::Vertex {
                instance: 1,
                vertex: 9
            }
        );
    }

    #[test]
    fn a_section_cap_picks_its_part() {
        let mut w = window();
        w.faces
            .iter_mut()
            .for_each(|f| f[2] = crate::SECTION_CAP | 3);
        assert_eq!(w.nearest(3.0).unwrap().pick, Pick::Part { instance: 0 });
    }

    #[test]
    fn nothing_under_an_empty_window() {
        let mut w = window();
        w.faces.iter_mut().for_each(|f| *f = [0; 4]);
        assert_eq!(w.nearest(3.0), None);
    }
}
