//! Picking from a viewport's last frame, without a full-size pass and without a stall: the
//! pick pass draws the B-Rep edges and vertices of only the runs whose bounding sphere
//! reaches the window around the cursor, into a target of the window's size through a
//! projection cropped to it, after the window of the visibility buffer's ids (where the
//! depth says something was drawn); both are copied into one buffer and mapped
//! asynchronously. A hover asks
//! ([`Renderer::request_pick`]) and takes the answer on a later frame ([`PendingPick::poll`]);
//! a click waits for it ([`Renderer::pick`]).
//!
//! On lavapipe at 1.1 M triangles (100 instances with edges) the full-size pass and two
//! blocking readbacks took ≈ 440 ms per pointer move (BENCHMARKS.md, "Picking and the viewer's frame").

use glam::{DMat4, DVec3, DVec4};

use crate::gpu_scene::{EdgeCall, FrameInstances, PickRun};
use crate::layout::{Call, Draw, PickRegion};
use crate::passes::pick::{PICK, PickInputs};
use crate::viewport::{PickWindow, Viewport};
use crate::{Gpu, PreparedScene, RenderError, Renderer};

/// Pixels past the window that a run's sphere may reach and still be drawn: the widest quad
/// the pick pass draws (a vertex's square, 1.5 px and a pixel of fringe) with a margin.
const CULL_MARGIN: f64 = 4.0;

/// The clip-space map that takes the window (`x`, `y`, `w`, `h`, pixels, y down) of a
/// `full` image to the whole of a `w` × `h` target: applied after the projection, each
/// window pixel lands on the same pixel of the small target, at the same scale.
pub(crate) fn crop_matrix(full: (u32, u32), (x, y, w, h): (f64, f64, f64, f64)) -> DMat4 {
    let (fw, fh) = (f64::from(full.0), f64::from(full.1));
    // NDC x: window column x ↦ −1, x + w ↦ 1; NDC y points up, rows down.
    let (sx, sy) = (fw / w, fh / h);
    let tx = (fw - 2.0 * x - w) / w;
    let ty = (h - fh + 2.0 * y) / h;
    // Clip coordinates: x' = sx·x + tx·w_clip, so the translation sits in the w row.
    DMat4::from_cols(
        DVec4::new(sx, 0.0, 0.0, 0.0),
        DVec4::new(0.0, sy, 0.0, 0.0),
        DVec4::new(0.0, 0.0, 1.0, 0.0),
        DVec4::new(tx, ty, 0.0, 1.0),
    )
}

/// Whether the sphere (`centre`, `radius`) may reach the clip volume of `clip` (sides and
/// near plane; the far plane culls nothing), by its distance to each plane.
pub(crate) fn sphere_reaches(clip: &DMat4, centre: DVec3, radius: f64) -> bool {
    let rows = [clip.row(0), clip.row(1), clip.row(2), clip.row(3)];
    // Left, right, bottom, top; near (reverse Z: depth z/w ≤ 1).
    let planes = [
        rows[3] + rows[0],
        rows[3] - rows[0],
        rows[3] + rows[1],
        rows[3] - rows[1],
        rows[3] - rows[2],
    ];
    planes.iter().all(|p| {
        let n = p.truncate();
        let len = n.length();
        if !(len > 0.0 && len.is_finite()) {
            return true;
        }
        (n.dot(centre) + p.w) / len >= -radius
    })
}

/// A pick asked for and not yet read: its window and the buffer its ids are copied into.
/// Dropping it drops the answer.
pub struct PendingPick {
    window: PickWindow,
    buffer: Option<wgpu::Buffer>,
    /// Bytes per row of each of the two regions in the buffer (faces, then lines).
    padded: u32,
    mapped: std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    /// A window with nothing to read (the cursor outside the view) not yet answered: the
    /// first poll gives it at once (else a caller polling for it would wait forever).
    empty_unanswered: bool,
}

impl PendingPick {
    /// The window (position and size) this pick reads; its ids are empty until read.
    pub fn window(&self) -> &PickWindow {
        &self.window
    }

    /// The answer if the GPU has finished, without waiting; `None` while it runs. After an
    /// answer (or an error) it gives `None`.
    pub fn poll(&mut self, gpu: &Gpu) -> Option<Result<PickWindow, RenderError>> {
        if std::mem::take(&mut self.empty_unanswered) {
            return Some(Ok(self.window.clone()));
        }
        self.buffer.as_ref()?;
        if let Err(e) = gpu.device.poll(wgpu::PollType::Poll) {
            self.buffer = None;
            return Some(Err(RenderError::Poll(e)));
        }
        match self.mapped.try_recv() {
            Ok(result) => Some(self.read(result)),
            Err(std::sync::mpsc::TryRecvError::Empty) => None,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                self.buffer = None;
                Some(Err(RenderError::ReadbackLost(std::sync::mpsc::RecvError)))
            }
        }
    }

    /// The answer, waiting for the GPU.
    pub fn wait(mut self, gpu: &Gpu) -> Result<PickWindow, RenderError> {
        if self.buffer.is_none() {
            return Ok(self.window);
        }
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(RenderError::Poll)?;
        let result = self.mapped.recv().map_err(RenderError::ReadbackLost)?;
        self.read(result)
    }

    /// Reads the mapped buffer into the window.
    fn read(
        &mut self,
        result: Result<(), wgpu::BufferAsyncError>,
    ) -> Result<PickWindow, RenderError> {
        let buffer = self.buffer.take().ok_or(RenderError::NoFrame)?;
        result.map_err(RenderError::Map)?;
        let (w, h) = (self.window.width as usize, self.window.height as usize);
        let padded = self.padded as usize;
        let mapped = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(RenderError::MapRange)?;
        let region = |at: usize| -> Vec<[u32; 4]> {
            let mut out = Vec::with_capacity(w * h);
            for row in 0..h {
                let start = at + row * padded;
                out.extend(mapped[start..start + 16 * w].chunks_exact(16).map(|p| {
                    std::array::from_fn(|i| {
                        u32::from_le_bytes(p[4 * i..4 * i + 4].try_into().unwrap_or_default())
                    })
                }));
            }
            out
        };
        let mut window = self.window.clone();
        window.faces = region(0);
        window.lines = region(padded * h);
        Ok(window)
    }
}

impl Renderer {
    /// What lies around pixel (`x`, `y`) of the viewport's last frame, `radius` pixels each
    /// way: its face ids and, drawn now by the pick pass, its edge and vertex ids. `scene`
    /// must be the one that frame drew. Waits for the GPU (a click); a hover asks with
    /// [`Renderer::request_pick`] instead.
    pub fn pick(
        &self,
        gpu: &Gpu,
        viewport: &Viewport,
        scene: &PreparedScene,
        cursor: (u32, u32),
        radius: u32,
    ) -> Result<PickWindow, RenderError> {
        self.request_pick(gpu, viewport, scene, cursor, radius)?
            .wait(gpu)
    }

    /// Submits the pick of [`Renderer::pick`] and returns at once; the answer is read from
    /// the [`PendingPick`] on a later frame.
    pub fn request_pick(
        &self,
        gpu: &Gpu,
        viewport: &Viewport,
        scene: &PreparedScene,
        (x, y): (u32, u32),
        radius: u32,
    ) -> Result<PendingPick, RenderError> {
        let Some(last) = &viewport.last else {
            return Err(RenderError::NoFrame);
        };
        let window = PickWindow::around(viewport.width, viewport.height, (x, y), radius);
        let (tx, rx) = std::sync::mpsc::channel();
        if window.width == 0 || window.height == 0 {
            return Ok(PendingPick {
                window,
                buffer: None,
                padded: 0,
                mapped: rx,
                empty_unanswered: true,
            });
        }
        let device = &gpu.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let full = (viewport.width, viewport.height);
        let rect = |margin: f64| {
            (
                f64::from(window.x) - margin,
                f64::from(window.y) - margin,
                f64::from(window.width) + 2.0 * margin,
                f64::from(window.height) + 2.0 * margin,
            )
        };
        let culling = crop_matrix(full, rect(CULL_MARGIN)) * last.view_proj;
        let (headers, records, calls) = pick_calls(&last.pick_runs, &culling);
        let instances =
            match FrameInstances::new(device, &self.instances, &headers, &records, &scene.locals) {
                Ok(i) => i,
                Err(e) => {
                    // The scope must come off the device's stack before leaving.
                    let _ = pollster::block_on(scope.pop());
                    return Err(e);
                }
            };
        let mut frame = last.frame;
        frame.view_proj = (crop_matrix(full, rect(0.0)) * last.view_proj)
            .as_mat4()
            .to_cols_array_2d();
        frame.viewport[0] = window.width as f32;
        frame.viewport[1] = window.height as f32;
        let frame = crate::gpu_scene::buffer(
            device,
            "pick frame",
            bytemuck::bytes_of(&frame),
            wgpu::BufferUsages::UNIFORM,
        );
        let region = PickRegion {
            origin: [window.x, window.y],
            pad: [0; 2],
        };
        let region = crate::gpu_scene::buffer(
            device,
            "pick region",
            bytemuck::bytes_of(&region),
            wgpu::BufferUsages::UNIFORM,
        );
        let size = wgpu::Extent3d {
            width: window.width,
            height: window.height,
            depth_or_array_layers: 1,
        };
        let window_target = |label| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: PICK,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let faces = window_target("pick faces");
        let target = window_target("pick");
        let mut encoder = device.create_command_encoder(&Default::default());
        let inputs = PickInputs {
            frame: &frame,
            region: &region,
            instances: &instances,
            segments: &scene.segments,
            quads: &scene.quad_indices,
            calls: &calls,
        };
        self.pick.record(
            device,
            &mut encoder,
            &viewport.targets,
            &inputs,
            (
                &faces.create_view(&Default::default()),
                &target.create_view(&Default::default()),
            ),
        );
        let padded = (16 * window.width).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let bytes = u64::from(padded) * u64::from(window.height);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pick readback"),
            size: 2 * bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let copy = |encoder: &mut wgpu::CommandEncoder, texture, origin, offset| {
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset,
                        bytes_per_row: Some(padded),
                        rows_per_image: Some(window.height),
                    },
                },
                size,
            );
        };
        copy(&mut encoder, &faces, wgpu::Origin3d::ZERO, 0);
        copy(&mut encoder, &target, wgpu::Origin3d::ZERO, bytes);
        gpu.queue.submit([encoder.finish()]);
        buffer
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| drop(tx.send(r)));
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Gpu(e));
        }
        Ok(PendingPick {
            window,
            buffer: Some(buffer),
            padded,
            mapped: rx,
            empty_unanswered: false,
        })
    }
}

/// The pick pass's calls over the runs whose sphere reaches the `culling` clip volume:
/// their call headers, draw records (one per run) and segment calls.
fn pick_calls(runs: &[PickRun], culling: &DMat4) -> (Vec<Call>, Vec<Draw>, Vec<EdgeCall>) {
    let mut headers = Vec::new();
    let mut records = Vec::new();
    let mut calls = Vec::new();
    for run in runs {
        let (centre, radius) = run.sphere;
        if !sphere_reaches(culling, centre, radius) {
            continue;
        }
        let slot = headers.len() as u32;
        headers.push(Call {
            record: records.len() as u32,
            locals_first: run.locals.0,
            locals_count: run.locals.1,
            instances: run.locals.1.max(1),
            ..Call::default()
        });
        records.push(run.record);
        // Edges, then vertices, so vertices win where both fall.
        for (first, count) in [run.edges, run.points] {
            if count > 0 {
                calls.push(EdgeCall {
                    first,
                    count,
                    slot,
                    instances: run.locals.1.max(1),
                    // The pick pipeline composes every instance through its slot.
                    direct: None,
                });
            }
        }
    }
    (headers, records, calls)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point at the centre of window pixel (c, r) of a `full` image, in NDC.
    fn ndc(full: (u32, u32), (c, r): (f64, f64)) -> DVec4 {
        DVec4::new(
            (c + 0.5) / f64::from(full.0) * 2.0 - 1.0,
            1.0 - (r + 0.5) / f64::from(full.1) * 2.0,
            0.5,
            1.0,
        )
    }

    #[test]
    fn the_crop_puts_each_window_pixel_on_its_target_pixel() {
        let full = (640, 480);
        let crop = crop_matrix(full, (100.0, 50.0, 11.0, 9.0));
        for (col, row) in [(0.0, 0.0), (10.0, 8.0), (5.0, 4.0)] {
            let p = crop * ndc(full, (100.0 + col, 50.0 + row));
            let x = (p.x / p.w + 1.0) * 0.5 * 11.0;
            let y = (1.0 - p.y / p.w) * 0.5 * 9.0;
            assert!((x - (col + 0.5)).abs() < 1e-9, "{x} {col}");
            assert!((y - (row + 0.5)).abs() < 1e-9, "{y} {row}");
        }
        // Perspective: w carries the translation too.
        let q = crop * (ndc(full, (104.0, 53.0)) * 7.0);
        assert!(((q.x / q.w + 1.0) * 0.5 * 11.0 - 4.5).abs() < 1e-9);
    }

    #[test]
    fn spheres_off_the_window_are_culled() {
        let camera = crate::Camera::fit(
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            crate::ViewPreset::Front,
            false,
            1.0,
        );
        let view_proj = camera.projection_matrix(1.0) * camera.view_rotation();
        let full = (200, 200);
        // A window at the image centre: the target (at the centre) is reached, a small
        // sphere at the image's edge and one behind the eye are not.
        let clip = crop_matrix(full, (95.0, 95.0, 11.0, 11.0)) * view_proj;
        let to_target = camera.target - camera.eye;
        assert!(sphere_reaches(&clip, to_target, 0.01));
        let (right, up) = {
            let r = camera.view_rotation().inverse();
            (r.transform_vector3(DVec3::X), r.transform_vector3(DVec3::Y))
        };
        let off = to_target + 0.9 * right + 0.9 * up;
        assert!(!sphere_reaches(&clip, off, 0.01));
        // Negative control: grown to reach the window, it is drawn.
        assert!(sphere_reaches(&clip, off, 1.5));
        assert!(!sphere_reaches(&clip, -to_target, 0.01));
        // The whole image's clip volume holds the off-centre sphere.
        assert!(sphere_reaches(&view_proj, off, 0.01));
    }
}
