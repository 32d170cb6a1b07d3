//! Errors of the mapping layer: each names the instance it is about.

use crate::syntax::Diagnostic;

/// Why one instance could not be mapped. The mapper turns these into model warnings that name
/// the instance and its line, skips what depends on the instance, and goes on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("#{id}: {message}")]
pub struct MapError {
    /// The instance at fault.
    pub id: u64,
    /// What is wrong with it.
    pub message: String,
    /// The instance being mapped when the error arose, when that is not `id` itself (so a
    /// reference to a missing instance can be reported where the reference is written).
    pub context: Option<u64>,
}

impl MapError {
    /// An error about instance `id`.
    pub fn new(id: u64, message: impl Into<String>) -> Self {
        Self {
            id,
            message: message.into(),
            context: None,
        }
    }
}

impl From<Diagnostic> for MapError {
    fn from(d: Diagnostic) -> Self {
        Self {
            id: d.id.unwrap_or(0),
            message: d.message,
            context: None,
        }
    }
}

/// Result of mapping one instance.
pub type MapResult<T> = Result<T, MapError>;
