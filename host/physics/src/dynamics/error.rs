//! Errors of the dynamics routines.

use thiserror::Error;

/// Why a dynamics call failed.
#[derive(Debug, Error, PartialEq)]
pub enum DynamicsError {
    /// A vector has the wrong length.
    #[error("{what}: expected length {expected}, got {got}")]
    Dimension {
        /// Which argument.
        what: &'static str,
        /// Required length.
        expected: usize,
        /// Given length.
        got: usize,
    },
    /// The workspace was made for another model.
    #[error("workspace was built for a model with {expected} bodies / {dofs} dofs")]
    Workspace {
        /// Bodies the workspace holds.
        expected: usize,
        /// Dofs the workspace holds.
        dofs: usize,
    },
    /// A joint's articulated inertia `Sᵀ Ĵ S` is not positive definite (massless subtree).
    #[error("body {body}: joint-space articulated inertia is singular")]
    Singular {
        /// Body index.
        body: usize,
    },
}
