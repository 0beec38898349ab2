//! The settings of a world's solver: [`SolverSettings`], each with a physical meaning, and
//! [`SolverVariants`], the engine's internal optimizations and the alternative forms of its
//! solver, every one on (or at its tuned value) by default. The variants are reachable from
//! outside the crate only with the `variants` feature, for the benchmarks and equivalence
//! tests that switch them (`vphys bench`, `tests/lean_contacts.rs`, …).

use super::resting_substeps;
use super::{Effect, Effects};
use crate::dynamics::solver::ContactStiffness;
use crate::geometry::V3;

/// Solver and collision settings (SI units), each with a physical meaning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// Substeps per step.
    pub substeps: usize,
    /// Contact stiffness (Hz); capped at a quarter of the substep rate (Box2D v3's
    /// cap; `SolverVariants::contact_hertz_cap`).
    pub contact_hertz: f64,
    /// Contact damping ratio (–).
    pub contact_damping_ratio: f64,
    /// Stiffness (Hz) of the position correction of joints solved one after another: those
    /// that close a loop among moving bodies. A forest of joints is solved exactly, as one
    /// system, and corrects as stiffly as the substep allows (a quarter of its rate).
    pub joint_hertz: f64,
    /// Damping ratio (–) of the joints solved one after another.
    pub joint_damping_ratio: f64,
    /// Contacts are kept up to this separation (m) — speculative distance.
    pub speculative_distance: f64,
    /// Largest push-out speed (m/s).
    pub max_push_velocity: f64,
    /// Approach speed below which restitution is not applied (m/s).
    pub restitution_threshold: f64,
    /// Linear damping rate (1/s), with the `damping` effect.
    pub linear_damping: f64,
    /// Angular damping rate (1/s), with the `damping` effect.
    pub angular_damping: f64,
}

/// The engine's internal optimizations and the alternative forms of its solver, each on (or
/// at its tuned value) by default: what a benchmark or an equivalence test switches, never a
/// scene. `World::variants_mut` (feature `variants`) reaches them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverVariants {
    /// Largest contact stiffness as a fraction of the substep rate (–); Box2D v3's quarter.
    /// Stiffer contacts sink less but make stacks lean (`docs/physics/scenes-contacts-stacking.md`, settings sweep).
    pub contact_hertz_cap: f64,
    /// Stiffness of a contact between two moving bodies of equal mass, as a multiple of
    /// `contact_hertz` (–), within the same cap; it falls to `contact_hertz` at a mass ratio of
    /// 10 (`ContactStiffness`). 1.5 holds a tower of 40 equal boxes within 1 mm for 20 s at
    /// the default step (120 Hz lets it lean 12 cm), while a 1 g box under 1 kg keeps the
    /// 120 Hz it needs.
    pub even_mass_stiffening: f64,
    /// Relax (solve without position bias) after every substep, as Box2D v3 does (default).
    /// When false, only after the last substep: `substeps + 1` passes instead of
    /// `2 × substeps` (measured: towers-1120 5.6 → 3.7 ms/step, same sink, lateral drift
    /// 2.6 → 1.1 mm), but the push-out velocity of the intermediate substeps stays in the
    /// bodies: a box dropped 8.5 m onto a tower bounces off it by more than a metre
    /// (`tests/gating.rs::a_falling_box_wakes_a_sleeping_tower` fails), so it is off.
    pub relax_each_substep: bool,
    /// Soft contacts (Box2D soft step: springs of `contact_hertz`) when true; rigid contacts
    /// with a position bias of `contact_bias_rate` when false (soft is the default).
    pub soft_contacts: bool,
    /// Position error to push-out speed (1/s) of rigid contacts.
    pub(crate) contact_bias_rate: f64,
    /// Let a world whose free bodies all rest take a half, a third, a quarter or a sixth of
    /// `substeps` (the fewest that hold) when its contacts, at the stiffness of those fewer
    /// substeps, hold it within 5 mm of sink and 1 mm of lean, and no body stands alone on
    /// another (a column keeps `substeps`: it would rock on its single contact)
    /// (`pipeline/resting_substeps.rs`; default). Off, every step takes `substeps`, as a sweep
    /// over them needs.
    pub fewer_substeps_at_rest: bool,
    /// Solve the contacts four at a time (`ContactBatches`: graph colouring, one constraint
    /// per lane); false solves them one by one in manifold order (the same rows, another
    /// Gauss–Seidel order).
    pub batch_contacts: bool,
    /// From a step's second substep on, warm start the contacts by adding back each body's
    /// change of velocity from the contacts over the substep before, where only contacts
    /// change the free bodies' velocities in the solve (no joints or articulated trees; the
    /// semi-implicit Euler integrators): the same impulses up to rounding, for a pass over
    /// the bodies instead of one over the contacts (`pipeline/warm_start_replay.rs`; default).
    pub replay_warm_start: bool,
    /// Hold back the sink of loaded contacts between free bodies: each step, a share of a
    /// contact's overlap beyond the slop (the step over a quarter second) is added to the
    /// overlap it is solved as if it had, so a resting stack stands at its slop whatever the
    /// contacts' stiffness (`pipeline/sink_hold.rs`; default). Off, a soft contact settles at
    /// the overlap its load asks, `F / (m ω²)`.
    pub hold_sink: bool,
    /// Keep the broad phase's pairs while every body's box stays within 5 cm of where the
    /// grid was built, taking from them the pairs whose boxes overlap now
    /// (`geometry/broad_phase.rs`; default). Off, the grid is built every step: the same
    /// pairs.
    pub keep_broad_phase_pairs: bool,
    /// A world at rest that keeps its decision on fewer substeps prepares the contact
    /// constraints it solves four at a time straight into their lanes, without keeping each
    /// whole (default): the same bits, without writing some 1.6 kB per contact. Off, every
    /// constraint is kept.
    pub lean_resting_contacts: bool,
}

impl SolverSettings {
    /// The factors `(linear, angular)` (–) the `damping` effect scales the velocities by over
    /// a substep of `h` (s): `1 / (1 + h c)` for each damping rate `c`.
    pub(crate) fn damping_factors(&self, h: f64) -> (f64, f64) {
        (
            1.0 / (1.0 + h * self.linear_damping),
            1.0 / (1.0 + h * self.angular_damping),
        )
    }
}

impl SolverVariants {
    /// The contacts' stiffness of `settings` on substeps of `h` (s): `contact_hertz` within
    /// the cap, `even_mass_stiffening` times that between equal masses, twice it against a
    /// body that does not move.
    pub(crate) fn contact_stiffness(&self, settings: &SolverSettings, h: f64) -> ContactStiffness {
        let cap = self.contact_hertz_cap * (1.0 / h);
        let hz = settings.contact_hertz.min(cap);
        ContactStiffness {
            hertz: hz,
            even_hertz: (self.even_mass_stiffening * hz).min(cap).max(hz),
            static_hertz: 2.0 * hz,
            damping_ratio: settings.contact_damping_ratio,
            substep: h,
        }
    }

    /// The contacts' stiffness of `settings` on substeps of `h` (s) in a step of `dt` (s):
    /// [`Self::contact_stiffness`], except that substeps longer than the step's own (a world
    /// at rest on fewer, `pipeline/resting_substeps.rs`) keep a contact against a body that
    /// does not move within [`resting_substeps::RESTING_STATIC_CAP`] of their rate.
    pub(crate) fn stiffness_on(
        &self,
        settings: &SolverSettings,
        h: f64,
        dt: f64,
    ) -> ContactStiffness {
        let mut k = self.contact_stiffness(settings, h);
        if h > 1.5 * dt / settings.substeps as f64 {
            k.static_hertz = k.static_hertz.min(resting_substeps::RESTING_STATIC_CAP / h);
        }
        k
    }

    /// The unit vector against `gravity` (m/s², world) where the contacts hold their sink
    /// (soft contacts under declared gravity, [`Self::hold_sink`]; `pipeline/sink_hold.rs`),
    /// `None` where they do not.
    pub(crate) fn hold_up(&self, effects: &Effects, gravity: &V3) -> Option<V3> {
        let g = gravity.norm();
        (self.hold_sink && self.soft_contacts && effects.has(Effect::Gravity) && g > 0.0)
            .then(|| -gravity / g)
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            substeps: 12,
            contact_hertz: 120.0,
            contact_damping_ratio: 10.0,
            joint_hertz: 60.0,
            joint_damping_ratio: 5.0,
            speculative_distance: 0.02,
            max_push_velocity: 3.0,
            restitution_threshold: 0.5,
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }
}

impl Default for SolverVariants {
    fn default() -> Self {
        Self {
            contact_hertz_cap: 0.25,
            even_mass_stiffening: 1.5,
            relax_each_substep: true,
            soft_contacts: true,
            contact_bias_rate: 20.0,
            fewer_substeps_at_rest: true,
            batch_contacts: true,
            replay_warm_start: true,
            hold_sink: true,
            keep_broad_phase_pairs: true,
            lean_resting_contacts: true,
        }
    }
}
