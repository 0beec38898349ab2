//! Lie-group algebra of rigid-body motion (paper §4.2–4.3, Appendix B), geometric form.
//!
//! | type | what | scalars |
//! |---|---|---|
//! | [`SE3`] | rigid transform (rotation `R`, translation `p`) | 12 |
//! | [`se3`] | twist `(w, v)`, angular first | 6 |
//! | [`dse3`] | wrench `(m, f)`, moment first | 6 |
//! | [`Inertia`] | rigid-body inertia: mass, first moment, rotational | 10 |
//! | `AInertia` (public with the `measure` feature) | articulated inertia, symmetric 6×6 | 21 |
//!
//! nalgebra provides the 3-vectors ([`Vec3`]) and 3×3 blocks ([`Mat3`]); the arithmetic on them
//! is written out component by component in small kernels so that every multiplication and
//! addition is one the operation counts of Table 3 can see.

#![allow(non_camel_case_types)]

mod ainertia;
mod inertia;
mod kernels;
#[cfg(feature = "measure")]
pub mod paper;
mod se3_group;
mod sym3;
mod twist;
mod wrench;

measure_use!(ainertia::AInertia);
pub use inertia::Inertia;
pub(crate) use se3_group::{exp_series, exp_translation, rotation_rows, SERIES_THETA2};
pub use se3_group::{exp_so3, log_so3, SE3};
pub use sym3::Sym3;
pub use twist::se3;
pub use wrench::dse3;

/// A 3-vector (nalgebra).
pub type Vec3<T = f64> = nalgebra::Vector3<T>;
/// A 3×3 matrix (nalgebra).
pub type Mat3<T = f64> = nalgebra::Matrix3<T>;

pub(crate) use kernels::*;
