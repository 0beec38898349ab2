//! Scenes as data: a JSON file format (serde), its validation (every problem reported with
//! its location, never a panic), the built-in scenes, and building a [`World`] from a scene.
//!
//! See `docs/physics/scenes-contacts-stacking.md` for the format with an example. Frames: `z` up by convention
//! (gravity defaults to `[0, 0, -9.81]`), positions of body centres (= centres of mass) in
//! world coordinates (m), `rotation` a rotation vector (axis × angle, rad), velocities in world
//! coordinates (m/s, rad/s).

mod build;
#[cfg(feature = "measure")]
pub mod builtin;
#[cfg(all(test, not(feature = "measure")))]
mod builtin;
mod error;
mod format;
#[cfg(feature = "measure")]
pub mod hard;
mod validate;

pub use error::{Problem, SceneError};
measure_use!(format::{
    ArticulatedDesc, BodyDesc, BodyKindDesc, DampingDesc, DriveDesc, JointDesc, JointLimitsDesc,
    JointMotorDesc, LinkShapeDesc, MaterialDesc, MotorDesc, PartShapeDesc, ShapeDesc,
    SolverDesc, TrajectoryDesc,
});
pub use format::SceneFile;
pub use validate::limits;

#[allow(unused_imports)]
use crate::pipeline::World;
