//! Dynamics of rigid bodies and articulated trees.
//!
//! * `rigid_body` — Eq. (3), `F = J V̇ − ad*_V J V`, and its inverse.
//! * `aba` — forward dynamics `q̈ = FD(q, q̇, τ)`: the recursive articulated-body algorithm of
//!   Appendix A, generalised to trees and multi-DOF joints.
//! * `rnea` — inverse dynamics `τ = ID(q, q̇, q̈)`, recursive Newton–Euler.
//! * `BodySet` (crate-internal) — the free rigid bodies of a world (structure of arrays).
//! * `solver` (crate-internal) — the soft-step contact and joint solver.
//! * `mass_matrix` — the joint-space mass matrix `M(q)` (composite rigid bodies).
//!
//! The world steps trees with these; as free functions (with `cholesky_solve`) they are
//! public with the `measure` feature, for `vphys`, the tests and the Pinocchio comparison.
//! All take a preallocated `Workspace` so that no call allocates. Gravity `g` (from the
//! model) enters as the acceleration `V̇₀ = (0, −g)` of the world frame. Optional external
//! wrenches act on each body, expressed in its body frame.

mod aba;
mod body_set;
mod crba;
mod error;
mod linalg;
#[cfg(feature = "measure")]
pub mod rigid_body;
#[cfg(not(feature = "measure"))]
#[allow(dead_code)]
mod rigid_body;
mod rnea;
pub(crate) mod solver;
mod workspace;

pub use crate::geometry::Material;
measure_use!(aba::aba);
pub use body_set::BodyKind;
pub(crate) use body_set::BodySet;
measure_use!(crba::mass_matrix);
pub use error::DynamicsError;
pub(crate) use linalg::spd_inverse;
measure_use!(linalg::{cholesky_solve, CholeskyError});
measure_use!(rnea::rnea);
measure_use!(workspace::Workspace);
