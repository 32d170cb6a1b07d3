//! Errors of the renderer.

use thiserror::Error;

/// What can go wrong while rendering.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No GPU adapter, native or software, could be found.
    #[error(
        "no GPU adapter found (native drivers, or Mesa's software Vulkan: \
         apt-get install mesa-vulkan-drivers): {0}"
    )]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("the GPU adapter refused a device: {0}")]
    Device(String),
    /// The adapter lacks a capability the passes need.
    #[error("the GPU adapter cannot run the renderer: {0}")]
    Unsupported(String),
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
    /// Reading the image back from the GPU failed.
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
    /// The GPU reported a validation or out-of-memory error.
    #[error("the GPU reported an error: {0}")]
    Gpu(String),
    /// A buffer the frame needs is larger than the adapter allows.
    #[error(
        "the scene is too large for this GPU: its {what} take {bytes} bytes, over the \
         adapter's limit of {limit} bytes for one buffer"
    )]
    TooLarge {
        /// What the buffer holds.
        what: String,
        /// Its size.
        bytes: u64,
        /// The adapter's limit for it.
        limit: u64,
    },
}
