//! # Virtual Physics
//!
//! The physics engine of Space Foosball (paper §4), part 1: the Lie-group algebra of
//! rigid-body motion written in the geometric form of Eq. (4), articulated models
//! (trees of bodies connected by joints) and their recursive dynamics.
//!
//! "The paper" and its numbers (§4.3, Eq. (6), Table 3, Appendix A) refer to Bang, Heo,
//! Kim and Kim, "Space Foosball: Coupling Tangible Interfaces with a Real-time Game Physics
//! Engine"; what the project takes from it, section by section, is in docs/paper.md in the
//! repository.
//!
//! * [`algebra`] — `SE3`, `se3` (twists), `dse3` (wrenches), `Inertia`, `AInertia` and the
//!   operations of the paper's Appendix B, generic over the scalar ([`Real`]).
//! * [`model`] — joints (one type per file, behind the [`model::Joint`] trait), bodies and
//!   articulated trees, and their JSON description shared with the Pinocchio peer script.
//! * [`dynamics`] — the articulated-body forward dynamics of Appendix A, recursive inverse
//!   dynamics (RNEA), the joint-space mass matrix, and the single-body Eq. (3).
//! * `measure` (feature `measure`: `vphys`, the tests and benchmarks, not the game) —
//!   operation counting (a counting scalar) and the matrix-form baseline that reproduce the
//!   paper's Table 3, the accuracy report's problems and the hard-case battery.
//!
//! Part 2 — contacts, stacking, scenes that declare their effects:
//!
//! * [`scene`] — the JSON scene format, validation with located messages, built-in scenes.
//! * [`geometry`] — shapes, grid broad phase, narrow phase with persistent manifolds,
//!   box–box SAT with clipping, continuous collision by speculative margins.
//! * `dynamics::solver` (crate-internal) — soft-step contact and joint constraints (friction cone,
//!   restitution, rolling resistance, warm starting).
//! * [`pipeline`] — the world and its step, built from the declared effects, with counters;
//!   five integrators selectable per scene; islands and sleeping.
//!
//! Part 3 — what accuracy costs: the integrators ([`pipeline::IntegratorKind`]), the reference
//! problems of `vphys accuracy` (`measure::accuracy`) and the hard-case battery
//! (`tests/hard_cases.rs`).
//!
//! ## Conventions (used everywhere)
//! * A twist `se3 = (w, v)`: angular part first, then linear; a wrench `dse3 = (m, f)`:
//!   moment first, then force. Both are expressed in a body frame unless said otherwise.
//! * `⟨F, V⟩ = m·w + f·v` (power, W).
//! * `SE3 (R, p)` written `T_ab` is the pose of frame `b` in frame `a`: `x_a = R x_b + p`.
//!   `Ad(T_ab)` maps a twist in `b` coordinates to `a` coordinates; `dAd(T_ab) = Ad(T_ab)ᵀ`
//!   maps a wrench in `a` coordinates to `b` coordinates.
//! * Rigid body (Eq. 3): `F = J V̇ − ad*_V J V` with `ad*_V F = ad_Vᵀ F = (m × w + f × v, f × w)`
//!   exactly as Eq. (4). (The paper prints Eq. (3) with `+`; with the `ad*` of Eq. (4) the sign
//!   is `−`, as Appendix A writes it.)
//! * SI units: m, kg, s, rad, N, N·m.

/// Re-exports with the `measure` feature, crate-internal without it: the comparison and
/// benchmark surface (the paper's algorithms as free functions, collision as pure functions,
/// reference models and scenes, the step's counters) that `vphys`, the tests and the
/// benchmarks read and a game does not.
macro_rules! measure_use {
    ($($path:tt)*) => {
        #[cfg(feature = "measure")]
        pub use $($path)*;
        #[cfg(not(feature = "measure"))]
        #[allow(unused_imports)]
        pub(crate) use $($path)*;
    };
}
/// A function public with the `measure` feature and crate-internal without it (one that the
/// engine uses itself and whose public form belongs to the `measure` surface).
macro_rules! measure_pub_fn {
    ($(#[$attr:meta])* fn $name:ident $($rest:tt)*) => {
        $(#[$attr])*
        #[cfg(feature = "measure")]
        pub fn $name $($rest)*
        $(#[$attr])*
        #[cfg(not(feature = "measure"))]
        pub(crate) fn $name $($rest)*
    };
}

/// A struct whose fields are public with the `measure` feature and crate-internal without it:
/// the data of a file format that `vphys`, the tests and the benchmarks edit field by field,
/// while a game loads, checks and builds it whole. `measure struct` makes the struct itself
/// public only with the feature.
macro_rules! measure_pub_fields {
    (
        $(#[$sattr:meta])*
        pub struct $name:ident { $( $(#[$fattr:meta])* $field:ident : $ty:ty ),* $(,)? }
    ) => {
        $(#[$sattr])*
        pub struct $name {
            $(
                $(#[$fattr])*
                #[cfg(feature = "measure")]
                pub $field: $ty,
                $(#[$fattr])*
                #[cfg(not(feature = "measure"))]
                pub(crate) $field: $ty,
            )*
        }
    };
    (
        $(#[$sattr:meta])*
        measure struct $name:ident { $( $(#[$fattr:meta])* $field:ident : $ty:ty ),* $(,)? }
    ) => {
        #[cfg(feature = "measure")]
        $(#[$sattr])*
        pub struct $name { $( $(#[$fattr])* pub $field: $ty, )* }
        #[cfg(not(feature = "measure"))]
        $(#[$sattr])*
        pub(crate) struct $name { $( $(#[$fattr])* pub(crate) $field: $ty, )* }
    };
}

pub mod algebra;
pub mod dynamics;
#[cfg(feature = "measure")]
pub mod measure;
pub mod model;
mod real;

pub use real::Real;
pub mod geometry;
pub mod pipeline;
pub mod scene;
pub mod transcendental;
