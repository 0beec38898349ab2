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
    /// A body's pose or velocity became non-finite during a step. The world was put back as
    /// it was before the step (see `World::step`).
    #[error(
        "body {body} ('{name}'): its {quantity} became non-finite during the step; \
         the world is as it was before the step"
    )]
    NonFinite {
        /// Body index.
        body: usize,
        /// Body name (may be empty).
        name: String,
        /// `position`, `rotation`, `velocity` or `angular velocity`.
        quantity: &'static str,
    },
    /// An articulated tree's `q` or `q̇` became non-finite during a step. The world was put
    /// back as it was before the step.
    #[error(
        "articulated tree {tree}: its {quantity} became non-finite during the step; \
         the world is as it was before the step"
    )]
    NonFiniteTree {
        /// Tree index (`World::articulated`).
        tree: usize,
        /// `q` or `qd`.
        quantity: &'static str,
    },
    /// The broad phase found more pairs of overlapping bounding boxes than
    /// [`MAX_CONTACT_PAIRS_PER_BODY`](crate::pipeline::MAX_CONTACT_PAIRS_PER_BODY) per body:
    /// bodies overlap en masse (many placed at one point), and the contacts of the step would
    /// grow as the square of their number. The world is as it was before the step.
    #[error(
        "{pairs} pairs of overlapping bounding boxes among {bodies} bodies, more than the \
         limit of {limit} ({per_body} per body): bodies overlap en masse (many placed at one \
         point?); the world is as it was before the step"
    )]
    TooManyContactPairs {
        /// Pairs found (at least; the broad phase stops counting past the limit).
        pairs: usize,
        /// Bodies in the world, tree links' proxies included.
        bodies: usize,
        /// The limit.
        limit: usize,
        /// The limit per body.
        per_body: usize,
    },
    /// A world parameter the step cannot use (`dt`, gravity, a solver setting); nothing
    /// was stepped.
    #[error("{what} must be {expected}, got {value}")]
    InvalidParameter {
        /// Which parameter, e.g. `dt` or `gravity[2]`.
        what: String,
        /// What it must be.
        expected: &'static str,
        /// What it is.
        value: f64,
    },
    /// A body's property or state the step cannot use (a dynamic body of mass ≤ 0, NaN or
    /// ∞, a non-finite size, a huge velocity, …); nothing was stepped.
    #[error("body {body} ('{name}'): {what} must be {expected}, got {value}")]
    InvalidBody {
        /// Body index.
        body: usize,
        /// Body name (may be empty).
        name: String,
        /// Which property, e.g. `mass` or `velocity`.
        what: &'static str,
        /// What it must be.
        expected: &'static str,
        /// What it is.
        value: f64,
    },
    /// An articulated tree's state the step cannot use (non-finite or huge `q`, `q̇`, `τ`);
    /// nothing was stepped.
    #[error("articulated tree {tree}: {what}[{index}] must be {expected}, got {value}")]
    InvalidTree {
        /// Tree index (`World::articulated`).
        tree: usize,
        /// `q`, `qd` or `tau`.
        what: &'static str,
        /// Entry.
        index: usize,
        /// What it must be.
        expected: &'static str,
        /// What it is.
        value: f64,
    },
}
