//! Collision detection: shapes, broad phase, narrow phase (contact manifolds), continuous
//! collision.
//!
//! * [`shape`] — the five primitive shapes and compounds, their bounding boxes and mass
//!   properties; [`Compound`] — several posed primitives with their materials as one shape.
//! * [`Material`] — surface properties (friction, restitution, rolling resistance).
//! * [`broad_phase`] — a uniform-grid broad phase (half-spaces tested against every body).
//! * [`narrow_phase`] — pair dispatch and persistent manifolds (warm-start data matched by
//!   feature position); `manifold_refresh` — a resting pair's manifold moved with its bodies
//!   instead of collided again.
//! * [`box_box`] — separating-axis test with face clipping (up to 4 points).
//! * [`primitives`] — sphere, capsule, cylinder and half-space pairs.
//! * [`toi`] — the time of impact of a sphere swept along a line (continuous collision).
//!
//! Frames: everything here is in world coordinates unless a name says `local`. A contact
//! normal points from body A to body B; a separation is negative when the shapes overlap (m).

pub mod box_box;
pub mod broad_phase;
mod collision_bodies;
mod compound;
pub mod contact;
mod manifold_refresh;
mod material;
pub mod narrow_phase;
mod posed_part;
pub mod primitives;
pub mod shape;
pub mod toi;

pub use broad_phase::BroadPhase;
pub use collision_bodies::CollisionBodies;
pub use compound::{Compound, CompoundError, CompoundMass, Part, PartDesc};
pub use contact::{ContactPoint, Manifold, MAX_MANIFOLD_POINTS};
pub use manifold_refresh::PairPose;
pub use material::Material;
pub use narrow_phase::{BodyMotion, NarrowPhase};
pub use shape::{Aabb, Shape};
pub use toi::{sphere_cast, Impact};

/// 3-vector, f64 (m, m/s, …).
pub type V3 = nalgebra::Vector3<f64>;
/// 3×3 matrix, f64.
pub type M3 = nalgebra::Matrix3<f64>;
