//! The step pipeline, assembled from the scene's declared effects.
//!
//! * [`Effects`] — the effect set a scene declares.
//! * `StepCounters` (public with the `measure` feature) — what the last step did (stages run, pairs tested, contacts, iterations).
//! * `integrator` — the five free-body integrators (semi-implicit Euler with `T ← T·Exp(hV)` by
//!   default), selectable per scene.
//! * `pose_lanes` — the default pose stage `T ← T·Exp(hV)`, four bodies at a time.
//! * `islands` — contact/joint islands and sleeping.
//! * [`ArticulatedSystem`] — articulated trees stepped by part 1's ABA.
//! * [`World`] — the world and its step.
//! * handles ([`BodyHandle`], [`JointHandle`], [`TreeHandle`], [`LinkHandle`]) — stable names
//!   for what the world holds, valid across inserting and removing other bodies.

mod articulated;
mod body_builder;
mod counters;
mod drives;
mod effects;
mod handles;
mod integrator;
mod inverse_mass;
mod islands;
mod pose_lanes;
mod tree_contacts;
mod union_find;
mod world;
mod world_bodies;
mod world_builder;
mod world_contacts;
pub(crate) mod world_joints;
mod world_state;
mod world_trees;
// The step's stages beside the world (each an `impl World` block or its own state).
mod ccd;
mod impacts;
pub(crate) mod island_substeps;
mod link_proxies;
mod resting_substeps;
mod settings;
pub(crate) mod sink_hold;
mod step;
mod step_guard;
mod step_parts;
mod substep_plan;
mod warm_start_replay;
mod world_guard;

pub use articulated::ArticulatedSystem;
pub use body_builder::{BodyBuilder, DEFAULT_DENSITY};
measure_use!(counters::{Stage, StepCounters});
pub use drives::{DriveKind, Motor, Trajectory};
pub use effects::{Effect, Effects};
pub use handles::{BodyHandle, JointHandle, LinkHandle, TreeHandle};
pub use integrator::IntegratorKind;
pub(crate) use integrator::{FreeForces, FreeIntegrator};
pub use settings::SolverSettings;
#[cfg(feature = "variants")]
pub use settings::SolverVariants;
pub use step::MAX_CONTACT_PAIRS_PER_BODY;
pub use world::World;
pub use world_bodies::{BodyMut, BodyRef};
pub use world_builder::WorldBuilder;
pub use world_contacts::Contact;
pub use world_joints::{
    FreeJointKind, JointBuilder, JointError, JointKindError, JointMut, JointRef,
};
