//! Errors of model construction and loading.

use thiserror::Error;

/// Why a model could not be built or loaded.
#[derive(Debug, Error)]
pub enum ModelError {
    /// A body names a parent that is not an earlier body.
    #[error("body {body} ('{name}'): parent {parent} is not an earlier body")]
    InvalidParent {
        /// Index of the offending body.
        body: usize,
        /// Its name.
        name: String,
        /// The parent index given.
        parent: usize,
    },
    /// A joint axis is zero or not finite.
    #[error("joint axis must be a non-zero finite vector, got {0:?}")]
    InvalidAxis([f64; 3]),
    /// A mass or inertia is not physical.
    #[error("body '{name}': {why}")]
    InvalidInertia {
        /// Body name.
        name: String,
        /// What is wrong.
        why: String,
    },
    /// A joint type name that no joint implements.
    #[error("unknown joint type '{0}'")]
    UnknownJoint(String),
    /// The JSON description could not be parsed.
    #[error("model description: {0}")]
    Json(#[from] serde_json::Error),
}
