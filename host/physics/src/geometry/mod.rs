//! Collision detection: shapes, broad phase, narrow phase (contact manifolds), continuous
//! collision.
//!
//! Public: [`Shape`] — the five primitive shapes, their bounding boxes and mass properties;
//! [`Compound`] — several posed primitives with their materials as one shape; [`Material`] —
//! surface properties (friction, restitution, rolling resistance). With the `measure` feature
//! (for `vphys`, the tests and the peers' comparisons), also collision as pure functions of
//! posed shapes: `collide` (any pair into a `Manifold`), `box_box` (separating-axis test with
//! face clipping, up to 4 points) and `sphere_cast` (the time of impact of a sphere swept
//! along a line).
//!
//! Crate-internal: `broad_phase` (a uniform grid; half-spaces tested against every body),
//! `narrow_phase` (pair dispatch and persistent manifolds, warm-start data matched by feature
//! position), `manifold_refresh` (a resting pair's manifold moved with its bodies instead of
//! collided again), `primitives` (sphere, capsule, cylinder and half-space pairs), `toi`.
//!
//! Frames: everything here is in world coordinates unless a name says `local`. A contact
//! normal points from body A to body B; a separation is negative when the shapes overlap (m).

mod box_box;
mod broad_phase;
mod collision_bodies;
mod compound;
mod contact;
mod manifold_refresh;
mod material;
mod narrow_phase;
mod posed_part;
pub(crate) mod primitives;
mod shape;
mod toi;

measure_use!(box_box::{box_box, BoxPose});
pub(crate) use broad_phase::BroadPhase;
pub(crate) use collision_bodies::CollisionBodies;
pub use compound::{Compound, CompoundError, CompoundMass, Part, PartDesc};
pub(crate) use contact::MAX_MANIFOLD_POINTS;
measure_use!(contact::{ContactPoint, Manifold});
pub(crate) use manifold_refresh::PairPose;
pub use material::Material;
measure_use!(narrow_phase::collide);
pub(crate) use narrow_phase::{BodyMotion, NarrowPhase};
pub(crate) use shape::Aabb;
pub use shape::Shape;
measure_use!(toi::{sphere_cast, Impact});

/// 3-vector, f64 (m, m/s, …).
pub(crate) type V3 = nalgebra::Vector3<f64>;
/// 3×3 matrix, f64.
pub(crate) type M3 = nalgebra::Matrix3<f64>;
