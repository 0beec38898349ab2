//! Describing an empty world: [`WorldBuilder`].

use crate::dynamics::BodySet;
use crate::geometry::V3;
use crate::pipeline::{Effects, IntegratorKind, SolverSettings, World};

/// An empty [`World`] to fill with [`World::insert_body`], [`World::insert_tree`] and joints.
/// Start from [`World::builder`].
#[derive(Clone, Debug)]
pub struct WorldBuilder {
    effects: Effects,
    dt: f64,
    gravity: V3,
    settings: SolverSettings,
    integrator: IntegratorKind,
}

impl World {
    /// A world that simulates exactly the `effects` declared (the stages of the others are
    /// never built): by default at 1 kHz (the paper's rate), gravity 9.81 m/s² along −z, the
    /// default solver settings and integrator.
    pub fn builder(effects: Effects) -> WorldBuilder {
        WorldBuilder {
            effects,
            dt: 1e-3,
            gravity: V3::new(0.0, 0.0, -9.81),
            settings: SolverSettings::default(),
            integrator: IntegratorKind::default(),
        }
    }
}

impl WorldBuilder {
    /// The step (s).
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// Gravity (m/s², world).
    pub fn gravity(mut self, g: V3) -> Self {
        self.gravity = g;
        self
    }

    /// Solver and collision settings.
    pub fn settings(mut self, s: SolverSettings) -> Self {
        self.settings = s;
        self
    }

    /// The integrator of the free bodies and of the trees.
    pub fn integrator(mut self, kind: IntegratorKind) -> Self {
        self.integrator = kind;
        self
    }

    /// The empty world.
    pub fn build(self) -> World {
        let mut w = World::new(
            BodySet::default(),
            self.effects,
            self.dt,
            self.gravity,
            self.settings,
        );
        w.set_integrator(self.integrator);
        w
    }
}
