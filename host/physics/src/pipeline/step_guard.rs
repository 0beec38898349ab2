//! The step's guard: what `World::step` checks before it steps, the snapshot it keeps, and
//! the check of the state it produced.
//!
//! * **Before** the step: `dt` (finite, `0 < dt ≤ 1 s`), gravity (finite, each component
//!   within ±1e6 m/s²), the solver settings (finite, ≥ 0, at least one substep); the bodies
//!   added since the last check (so the cost per step is O(new bodies)): a dynamic body's
//!   mass, inverse mass, principal inertia and inverse inertia finite and positive, every
//!   body's shape of finite, positive size (a half-space: a finite, non-zero normal); and,
//!   while the snapshot is taken, every body's pose and velocity finite and not huge
//!   ([`MAX_COORD_M`], [`MAX_SPEED_M_S`], [`MAX_ANGULAR_SPEED_RAD_S`]), every tree's `q`,
//!   `q̇`, `τ` likewise. A failed check steps nothing and returns the error.
//! * **After** the step: every body's position, rotation, velocity and angular velocity and
//!   every tree's `q` and `q̇` finite. Otherwise (and when the step itself returned an
//!   error) the world is put back as it was before the step: the bodies' poses,
//!   velocities, sleep state and boxes, the trees' `q` and `q̇`, the joints' accumulated
//!   impulses and the time. The contact warm-start cache is **cleared** rather than kept
//!   (it is as large as the contacts and would cost a copy every step): the next step finds
//!   the same contacts and solves them from zero impulses. The counters describe the failed
//!   step.
//!
//! A step that can only advance the clock (sleeping on, every body asleep, no kinematic body
//! moving, no tree, no body added) checks only the kinematic and fixed bodies' state, the
//! others' having passed when they last moved, and takes no snapshot: the all-asleep step
//! costs a pass over the bodies' flags.
//!
//! A property of a body that already passed (mass, inertia, shape) changed later through
//! the public fields is not checked again; if it makes the state non-finite, the check
//! after the step catches it.

use crate::dynamics::solver::FreeJoint;
use crate::geometry::{Aabb, M3, V3};

/// Largest position coordinate a step accepts (m): a million kilometres, far beyond any
/// scene, far below where `x²` overflows.
pub(crate) const MAX_COORD_M: f64 = 1e9;
/// Largest speed a step accepts (m/s).
pub(crate) const MAX_SPEED_M_S: f64 = 1e6;
/// Largest angular speed a step accepts (rad/s).
pub(crate) const MAX_ANGULAR_SPEED_RAD_S: f64 = 1e6;
/// Largest gravity component a step accepts (m/s²).
pub(super) const MAX_GRAVITY_M_S2: f64 = 1e6;
/// Longest step (s).
pub(super) const MAX_DT_S: f64 = 1.0;
/// Largest entry of a tree's `q`, `q̇` (m, rad, m/s, rad/s) and `τ` (N, N·m) a step accepts.
pub(super) const MAX_TREE_VALUE: f64 = 1e9;

/// The snapshot and the count of bodies already checked.
#[derive(Clone, Default)]
pub(crate) struct StepGuard {
    /// Bodies `0 .. checked` passed the checks of their fixed properties.
    pub(super) checked: usize,
    pub(super) pos: Vec<V3>,
    pub(super) rot: Vec<M3>,
    pub(super) vel: Vec<V3>,
    pub(super) omega: Vec<V3>,
    pub(super) awake: Vec<bool>,
    pub(super) sleep_time: Vec<f64>,
    pub(super) aabb: Vec<Aabb>,
    /// Every tree's `q` then `q̇`, one after the other.
    pub(super) trees: Vec<f64>,
    pub(super) joints: Vec<FreeJoint>,
    pub(super) time: f64,
    /// Whether the step in progress can only advance the clock (no snapshot taken).
    pub(super) clock_only: bool,
}

impl StepGuard {
    /// Checks every body's fixed properties again before the next step (after a removal
    /// moved a body to another index).
    pub(super) fn recheck_all(&mut self) {
        self.checked = 0;
    }
}

pub(super) fn finite3(v: &V3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// `x ≤ max`, false for NaN.
pub(super) fn at_most(x: f64, max: f64) -> bool {
    x <= max
}

/// Largest absolute component (NaN when one is NaN).
pub(super) fn max_abs(v: &V3) -> f64 {
    if finite3(v) {
        v.x.abs().max(v.y.abs()).max(v.z.abs())
    } else if v.iter().any(|x| x.is_nan()) {
        f64::NAN
    } else {
        f64::INFINITY
    }
}
