//! Per-pass GPU timings of a frame: timestamps written on the command encoder between the
//! frame's stages (`wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS`), resolved with the
//! frame and read back after it, so a benchmark can say where a frame's GPU time goes
//! (trim tessellation, visibility, shading, readback) on the adapter it runs on. Adapters
//! without the feature time nothing; the frame is drawn the same.

use std::sync::Mutex;

use crate::Gpu;

/// Timestamps a frame may write: its start and the end of each stage.
const MAX_MARKS: u32 = 16;

/// The timestamps of the frame being recorded, and the stage each one ends.
pub(crate) struct PassTimer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Nanoseconds a timestamp tick.
    period: f64,
    /// The stages marked in the frame being recorded (the first mark is the frame's start).
    marks: Mutex<Vec<&'static str>>,
    /// The last finished frame's stages and their durations in milliseconds.
    last: Mutex<Vec<(&'static str, f64)>>,
}

impl PassTimer {
    /// A timer on `gpu`, or `None` where its device cannot write timestamps on encoders.
    pub(crate) fn new(gpu: &Gpu) -> Option<PassTimer> {
        let needed =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        if !gpu.device.features().contains(needed) {
            return None;
        }
        let bytes = 8 * u64::from(MAX_MARKS);
        let buffer = |label, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(PassTimer {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_MARKS,
            }),
            resolved: buffer(
                "pass timestamps resolved",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "pass timestamps readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            period: f64::from(gpu.queue.get_timestamp_period()),
            marks: Mutex::new(Vec::new()),
            last: Mutex::new(Vec::new()),
        })
    }

    /// Starts a frame's timings on `encoder`.
    pub(crate) fn start(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut marks = self.marks.lock().unwrap_or_else(|e| e.into_inner());
        marks.clear();
        marks.push("start");
        encoder.write_timestamp(&self.queries, 0);
    }

    /// Marks the end of stage `stage` (the time since the previous mark is its); past
    /// [`MAX_MARKS`] stages merge into the last.
    pub(crate) fn mark(&self, encoder: &mut wgpu::CommandEncoder, stage: &'static str) {
        let mut marks = self.marks.lock().unwrap_or_else(|e| e.into_inner());
        if marks.is_empty() || marks.len() as u32 >= MAX_MARKS {
            return;
        }
        encoder.write_timestamp(&self.queries, marks.len() as u32);
        marks.push(stage);
    }

    /// Resolves the frame's timestamps into the readback buffer (before `encoder` is
    /// submitted).
    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let count = self.marks.lock().unwrap_or_else(|e| e.into_inner()).len() as u32;
        if count < 2 {
            return;
        }
        encoder.resolve_query_set(&self.queries, 0..count, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, 8 * u64::from(count));
    }

    /// Reads the submitted frame's timestamps back (waiting for it) as stage durations.
    pub(crate) fn read(&self, gpu: &Gpu) {
        let marks = std::mem::take(&mut *self.marks.lock().unwrap_or_else(|e| e.into_inner()));
        if marks.len() < 2 {
            return;
        }
        let slice = self.readback.slice(..8 * marks.len() as u64);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
        if !matches!(rx.recv(), Ok(Ok(()))) {
            return;
        }
        let ticks: Vec<u64> = match slice.get_mapped_range() {
            Ok(bytes) => bytes
                .chunks_exact(8)
                .map(|b| u64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
                .collect(),
            Err(_) => return,
        };
        self.readback.unmap();
        *self.last.lock().unwrap_or_else(|e| e.into_inner()) =
            durations(&marks, &ticks, self.period);
    }

    /// The last read frame's stages and their durations in milliseconds.
    pub(crate) fn last(&self) -> Vec<(&'static str, f64)> {
        self.last.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

/// Each stage's milliseconds from the timestamps ending them (`marks[0]` is the start):
/// a clock that ran backwards (some drivers' across command buffers) counts 0.
fn durations(marks: &[&'static str], ticks: &[u64], period_ns: f64) -> Vec<(&'static str, f64)> {
    ticks
        .windows(2)
        .zip(&marks[1..])
        .map(|(w, &stage)| (stage, w[1].saturating_sub(w[0]) as f64 * period_ns * 1e-6))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_take_the_time_since_the_previous_mark() {
        let marks = ["start", "visibility", "shade"];
        let got = durations(&marks, &[1_000, 3_000_000, 3_500_000], 2.0);
        let stages: Vec<&str> = got.iter().map(|(s, _)| *s).collect();
        assert_eq!(stages, ["visibility", "shade"]);
        assert!((got[0].1 - 5.998).abs() < 1e-9, "{got:?}");
        assert!((got[1].1 - 1.0).abs() < 1e-9, "{got:?}");
        // A clock running backwards gives 0, not a wrapped huge figure.
        let got = durations(&marks, &[5_000, 4_000, 6_000], 1.0);
        assert_eq!(got[0], ("visibility", 0.0));
    }
}
