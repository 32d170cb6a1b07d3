//! What a frame writes for the GPU, kept between a viewer's frames: the frame's uniform, draw
//! records and calls, materials, lights, selection and analytic primitives, each in a buffer
//! that grows on demand and is refilled with `write_buffer`, and the bind groups over them,
//! made again only when one of their buffers or textures is new ([`BindCache`]). A frame used
//! to allocate all of them, and every bind group, afresh.

use std::collections::HashMap;
use std::sync::Mutex;

use crate::error::RenderError;
use crate::gpu_scene::buffer_limit;

/// A buffer refilled each frame, reallocated (at least doubling) only when the data outgrows
/// it.
pub(crate) struct GrowingBuffer {
    label: &'static str,
    usage: wgpu::BufferUsages,
    buffer: wgpu::Buffer,
    /// Whether it is bound whole (its binding limit applies), or a window of it at dynamic
    /// offsets (only the buffer limit does).
    bound_whole: bool,
}

/// Bytes every growing buffer starts with (storage bindings may not be empty).
const INITIAL_BYTES: u64 = 256;

impl GrowingBuffer {
    /// An empty buffer of `usage` (plus `COPY_DST`).
    pub fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowingBuffer {
            label,
            usage,
            bound_whole: true,
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: INITIAL_BYTES,
                usage,
                mapped_at_creation: false,
            }),
        }
    }

    /// Writes `bytes` at its start, growing it first when they do not fit; refuses what the
    /// device's limits for its usage do not allow.
    pub fn write(&mut self, gpu: &crate::Gpu, bytes: &[u8]) -> Result<(), RenderError> {
        let len = bytes.len() as u64;
        if len > self.buffer.size() {
            let limits = gpu.device.limits();
            let limit = if self.bound_whole {
                buffer_limit(&limits, self.usage)
            } else {
                limits.max_buffer_size
            };
            if len > limit {
                return Err(RenderError::TooLarge {
                    what: self.label,
                    bytes: len,
                    limit,
                });
            }
            let size = (2 * self.buffer.size()).max(len).min(limit);
            self.buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(self.label),
                size: size.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
                usage: self.usage,
                mapped_at_creation: false,
            });
        }
        if !bytes.is_empty() {
            gpu.queue.write_buffer(&self.buffer, 0, bytes);
        }
        Ok(())
    }

    /// An empty buffer of this one's label and usage (another chunk of the same records).
    pub fn sibling(&self, device: &wgpu::Device) -> Self {
        GrowingBuffer {
            bound_whole: self.bound_whole,
            ..GrowingBuffer::new(device, self.label, self.usage)
        }
    }

    /// This buffer, bound at dynamic offsets one window wide (only the buffer limit caps it).
    pub fn windowed(mut self) -> Self {
        self.bound_whole = false;
        self
    }

    /// The buffer as it is now (a handle: it stays valid after a later reallocation).
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

/// The per-frame buffers of one viewport (or of one image).
pub(crate) struct FrameBuffers {
    pub frame: GrowingBuffer,
    pub draws: GrowingBuffer,
    pub calls: GrowingBuffer,
    pub materials: GrowingBuffer,
    pub lights: GrowingBuffer,
    pub selection: GrowingBuffer,
    /// The opaque analytic primitives' records, in chunks of at most a storage binding.
    pub primitives: Vec<GrowingBuffer>,
    /// The see-through analytic primitives' records, in chunks.
    pub see_through_primitives: Vec<GrowingBuffer>,
    /// The cutting planes of the frame's quadrics, in their boxes' frames.
    pub primitive_planes: GrowingBuffer,
}

impl FrameBuffers {
    /// Empty buffers, grown by the first frame.
    pub fn new(device: &wgpu::Device) -> FrameBuffers {
        use wgpu::BufferUsages as U;
        FrameBuffers {
            frame: GrowingBuffer::new(device, "frame", U::UNIFORM),
            draws: GrowingBuffer::new(device, "draw records", U::STORAGE | U::VERTEX),
            // Bound one call wide at a dynamic offset: only the buffer limit applies.
            calls: GrowingBuffer::new(device, "draw calls", U::UNIFORM).windowed(),
            materials: GrowingBuffer::new(device, "materials", U::STORAGE),
            lights: GrowingBuffer::new(device, "lights", U::UNIFORM),
            selection: GrowingBuffer::new(device, "selection", U::STORAGE),
            primitives: vec![GrowingBuffer::new(device, "primitives", U::STORAGE)],
            see_through_primitives: vec![GrowingBuffer::new(
                device,
                "see-through primitives",
                U::STORAGE,
            )],
            primitive_planes: GrowingBuffer::new(device, "primitive planes", U::STORAGE),
        }
    }
}

/// What a bind group entry binds, as a cache key: the resource itself (wgpu's handles compare
/// by identity), with the buffer range.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Bound {
    Buffer(wgpu::Buffer, u64, Option<u64>),
    View(wgpu::TextureView),
}

/// A bind group's layout and what each of its entries binds.
type BindKey = (wgpu::BindGroupLayout, Vec<Bound>);

/// Bind groups by layout and resources: a frame that binds the same buffers and textures as
/// the last gets the same bind group back instead of a new one. Entries not used by a frame
/// are dropped at its end ([`BindCache::end_frame`]), so the cache holds one frame's worth.
#[derive(Default)]
pub(crate) struct BindCache {
    entries: Mutex<HashMap<BindKey, (wgpu::BindGroup, bool)>>,
    /// Bind groups made so far.
    made: std::sync::atomic::AtomicUsize,
}

impl BindCache {
    /// The bind group of `layout` over `resources` (binding `i` at index `i`), made on a miss.
    pub fn get(
        &self,
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        resources: &[wgpu::BindingResource<'_>],
    ) -> wgpu::BindGroup {
        let mut key = Vec::with_capacity(resources.len());
        for r in resources {
            key.push(match r {
                wgpu::BindingResource::Buffer(b) => {
                    Bound::Buffer(b.buffer.clone(), b.offset, b.size.map(|s| s.get()))
                }
                wgpu::BindingResource::TextureView(v) => Bound::View((*v).clone()),
                // No pass binds anything else: made, not cached.
                _ => return crate::passes::common::bind_group(device, label, layout, resources),
            });
        }
        let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        let entry = entries.entry((layout.clone(), key)).or_insert_with(|| {
            self.made.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            (
                crate::passes::common::bind_group(device, label, layout, resources),
                true,
            )
        });
        entry.1 = true;
        entry.0.clone()
    }

    /// Drops the bind groups the frame just recorded did not use, and starts counting anew.
    pub fn end_frame(&self) {
        let mut entries = self.entries.lock().unwrap_or_else(|e| e.into_inner());
        entries.retain(|_, (_, used)| std::mem::take(used));
    }

    /// Bind groups made so far (cache misses).
    #[cfg(test)]
    pub fn made(&self) -> usize {
        self.made.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Bind groups held.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.entries.lock().map_or(0, |e| e.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_growing_buffer_keeps_its_buffer_until_the_data_outgrows_it() {
        let Ok(gpu) = crate::Gpu::headless() else {
            eprintln!("no adapter: skipped");
            return;
        };
        let mut b = GrowingBuffer::new(&gpu.device, "test", wgpu::BufferUsages::STORAGE);
        let first = b.buffer().clone();
        b.write(&gpu, &[1u8; 200]).unwrap();
        assert_eq!(*b.buffer(), first, "200 bytes fit in the first 256");
        b.write(&gpu, &[2u8; 1000]).unwrap();
        assert_ne!(*b.buffer(), first, "1000 bytes do not");
        assert!(b.buffer().size() >= 1000);
        let grown = b.buffer().clone();
        b.write(&gpu, &[3u8; 16]).unwrap();
        assert_eq!(*b.buffer(), grown, "it does not shrink");
    }

    #[test]
    fn the_same_resources_get_the_same_bind_group_and_unused_ones_are_dropped() {
        let Ok(gpu) = crate::Gpu::headless() else {
            eprintln!("no adapter: skipped");
            return;
        };
        let device = &gpu.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &crate::passes::common::entries(
                &[crate::layout::Binding::Storage("x")],
                wgpu::ShaderStages::FRAGMENT,
            ),
        });
        let a = GrowingBuffer::new(device, "a", wgpu::BufferUsages::STORAGE);
        let b = GrowingBuffer::new(device, "b", wgpu::BufferUsages::STORAGE);
        let cache = BindCache::default();
        let ga = cache.get(device, "t", &layout, &[a.buffer().as_entire_binding()]);
        let again = cache.get(device, "t", &layout, &[a.buffer().as_entire_binding()]);
        assert_eq!(ga, again);
        // Negative control: another buffer, another bind group.
        let gb = cache.get(device, "t", &layout, &[b.buffer().as_entire_binding()]);
        assert_ne!(ga, gb);
        cache.end_frame();
        assert_eq!(cache.len(), 2);
        let _ = cache.get(device, "t", &layout, &[a.buffer().as_entire_binding()]);
        cache.end_frame();
        assert_eq!(
            cache.len(),
            1,
            "b's went with the frame that did not use it"
        );
    }
}
