//! Dynamics of rigid bodies and articulated trees.
//!
//! * [`rigid_body`] — Eq. (3), `F = J V̇ − ad*_V J V`, and its inverse.
//! * [`aba`] — forward dynamics `q̈ = FD(q, q̇, τ)`: the recursive articulated-body algorithm of
//!   Appendix A, generalised to trees and multi-DOF joints.
//! * [`rnea`] — inverse dynamics `τ = ID(q, q̇, q̈)`, recursive Newton–Euler.
//! * `BodySet` (crate-internal) — the free rigid bodies of a world (structure of arrays).
//! * `solver` (crate-internal) — the soft-step contact and joint solver.
//! * [`mass_matrix`] — the joint-space mass matrix `M(q)` (composite rigid bodies).
//!
//! All take a preallocated [`Workspace`] so that no call allocates. Gravity `g` (from the
//! model) enters as the acceleration `V̇₀ = (0, −g)` of the world frame. Optional external
//! wrenches act on each body, expressed in its body frame.

mod aba;
mod body_set;
mod crba;
mod error;
mod linalg;
pub mod rigid_body;
mod rnea;
pub(crate) mod solver;
mod workspace;

pub use crate::geometry::Material;
pub use aba::aba;
pub use body_set::BodyKind;
pub(crate) use body_set::BodySet;
pub use crba::mass_matrix;
pub use error::DynamicsError;
pub(crate) use linalg::spd_inverse;
pub use linalg::{cholesky_solve, CholeskyError};
pub use rnea::rnea;
pub use workspace::Workspace;
