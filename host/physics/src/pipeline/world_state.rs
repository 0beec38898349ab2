//! The world's clock, gravity, effects, settings and counters.

use super::world::World;
use crate::geometry::V3;
#[cfg(feature = "measure")]
use crate::pipeline::StepCounters;
use crate::pipeline::{Effects, SolverSettings};

impl World {
    /// The step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Sets the step (s); checked (positive, finite, at most 1 s) by the next step.
    pub fn set_dt(&mut self, dt: f64) {
        self.dt = dt;
    }

    /// Simulated time since the world was built (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Gravity (m/s², world); applied only with the `gravity` effect.
    pub fn gravity(&self) -> V3 {
        self.gravity
    }

    /// Sets gravity (m/s², world).
    pub fn set_gravity(&mut self, g: V3) {
        self.gravity = g;
    }

    /// The declared effects (fixed when the world is built: the stages are built from them).
    pub fn effects(&self) -> Effects {
        self.effects
    }

    /// Solver and collision settings.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Solver and collision settings, to change between steps (checked by the next step).
    pub fn settings_mut(&mut self) -> &mut SolverSettings {
        &mut self.settings
    }

    /// The solver's internal optimizations and alternative forms (feature `variants`), for
    /// benchmarks and equivalence tests: each is on by default.
    #[cfg(feature = "variants")]
    pub fn variants(&self) -> &super::SolverVariants {
        &self.variants
    }

    /// The same, to change between steps (checked by the next step).
    #[cfg(feature = "variants")]
    pub fn variants_mut(&mut self) -> &mut super::SolverVariants {
        &mut self.variants
    }

    /// What the last step did: stages run, pairs tested, contacts, iterations.
    #[cfg(feature = "measure")]
    pub fn counters(&self) -> &StepCounters {
        &self.counters
    }
}
