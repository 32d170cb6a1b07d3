//! Errors of the renderer.

use thiserror::Error;

/// What can go wrong while rendering.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No GPU adapter, native or software, could be found.
    #[error(
        "no GPU adapter found (native drivers, or Mesa's software Vulkan: \
         apt-get install mesa-vulkan-drivers): {}",
        .0.as_ref().map_or_else(|| "no backend tried".to_string(), |e| e.to_string())
    )]
    NoAdapter(#[source] Option<Box<dyn std::error::Error + Send + Sync>>),
    /// The adapter refused to create a device.
    #[error("the GPU adapter refused a device: {0}")]
    Device(#[source] wgpu::RequestDeviceError),
    /// The adapter cannot read storage buffers in vertex shaders (GL below 4.3 or GLES
    /// below 3.1), which edges, picking and draw records need.
    #[error(
        "the GPU adapter cannot run the renderer: {adapter} ({backend:?}) cannot read storage \
         buffers in vertex shaders (GL 4.3 or GLES 3.1 needed)"
    )]
    NoVertexStorage {
        /// The adapter's name.
        adapter: String,
        /// Its back-end.
        backend: wgpu::Backend,
    },
    /// The requested image size is zero or beyond what the adapter supports.
    #[error("image size {width}x{height} is not supported (1 to {max} pixels a side)")]
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Largest side the adapter allows (after supersampling).
        max: u32,
    },
    /// Waiting for the GPU to finish a frame failed.
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[source] wgpu::PollError),
    /// The buffer the image is read back through could not be mapped.
    #[error("reading the image back from the GPU failed: {0}")]
    Map(#[source] wgpu::BufferAsyncError),
    /// The mapped buffer's range could not be read.
    #[error("reading the image back from the GPU failed: {0}")]
    MapRange(#[source] wgpu::MapRangeError),
    /// The GPU dropped the read-back without answering.
    #[error("the GPU dropped the image read-back")]
    ReadbackLost(#[source] std::sync::mpsc::RecvError),
    /// The image read back does not have the size asked for.
    #[error("the image read back is {got} bytes, not the {want} of its size")]
    ReadbackSize {
        /// Bytes read back.
        got: usize,
        /// Bytes the image size needs.
        want: usize,
    },
    /// A viewport was asked for what its last frame drew before it drew one.
    #[error("no frame drawn yet in this viewport")]
    NoFrame,
    /// The GPU reported a validation or out-of-memory error.
    #[error("the GPU reported an error: {0}")]
    Gpu(#[source] wgpu::Error),
    /// A buffer the frame needs is larger than the adapter allows.
    #[error(
        "the scene is too large for this GPU: its {what} take {bytes} bytes, over the \
         adapter's limit of {limit} bytes for one buffer"
    )]
    TooLarge {
        /// What the buffer holds.
        what: &'static str,
        /// Its size.
        bytes: u64,
        /// The adapter's limit for it.
        limit: u64,
    },
    /// One frame's instances would cover the image more times over than
    /// [`crate::MAX_IMAGE_COVERAGE`] (instances piled on each other).
    #[error(
        "the scene is too deep to draw: its {instances} instances would cover the image about \
         {coverage:.0} times over, past the {limit} one frame draws (instances piled on each \
         other); nothing was drawn"
    )]
    Overdrawn {
        /// Estimated images covered.
        coverage: f64,
        /// Visible instances.
        instances: usize,
        /// [`crate::MAX_IMAGE_COVERAGE`].
        limit: f64,
    },
    /// One frame would draw more triangles than [`crate::MAX_FRAME_TRIANGLES`].
    #[error(
        "the scene is too large to draw: {triangles} triangles placed, over the {limit} one \
         frame draws"
    )]
    TooManyTriangles {
        /// Triangles of every visible instance.
        triangles: u64,
        /// [`crate::MAX_FRAME_TRIANGLES`].
        limit: u64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn errors_keep_their_cause() {
        let none = RenderError::NoAdapter(None);
        assert!(none.to_string().ends_with("no backend tried"), "{none}");
        assert!(none.source().is_none());
        let cause = RenderError::NoVertexStorage {
            adapter: "llvmpipe".into(),
            backend: wgpu::Backend::Gl,
        };
        let why = RenderError::NoAdapter(Some(Box::new(cause)));
        assert!(
            why.to_string()
                .ends_with("llvmpipe (Gl) cannot read storage buffers in vertex shaders (GL 4.3 or GLES 3.1 needed)"),
            "{why}"
        );
        let source = why.source().expect("the cause is the source");
        assert!(source.to_string().contains("cannot run the renderer"));
        let size = RenderError::ReadbackSize { got: 4, want: 16 };
        assert_eq!(
            size.to_string(),
            "the image read back is 4 bytes, not the 16 of its size"
        );
    }
}
