//! Collision detection: shapes, broad phase, narrow phase (contact manifolds), continuous
//! collision.
//!
//! * [`shape`] — the five shapes, their bounding boxes and mass properties.
//! * [`broad_phase`] — a uniform-grid broad phase (half-spaces tested against every body).
//! * [`narrow_phase`] — pair dispatch and persistent manifolds (warm-start data matched by
//!   feature position).
//! * [`box_box`] — separating-axis test with face clipping (up to 4 points).
//! * [`primitives`] — sphere, capsule, cylinder and half-space pairs.
//!
//! Frames: everything here is in world coordinates unless a name says `local`. A contact
//! normal points from body A to body B; a separation is negative when the shapes overlap (m).

pub mod box_box;
pub mod broad_phase;
pub mod contact;
pub mod narrow_phase;
pub mod primitives;
pub mod shape;

pub use broad_phase::BroadPhase;
pub use contact::{ContactPoint, Manifold, MAX_MANIFOLD_POINTS};
pub use narrow_phase::NarrowPhase;
pub use shape::{Aabb, Shape};

/// 3-vector, f64 (m, m/s, …).
pub type V3 = nalgebra::Vector3<f64>;
/// 3×3 matrix, f64.
pub type M3 = nalgebra::Matrix3<f64>;
