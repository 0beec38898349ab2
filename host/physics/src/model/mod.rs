//! Articulated models: joints (one type per file behind the [`Joint`] trait), bodies, trees,
//! and the JSON description shared with the peer (Pinocchio) scripts.
//!
//! Frames: every body `i` has a frame (its *body frame*). Its joint connects it to the parent
//! body `λ(i)` (or to the fixed world frame for a root): the joint frame is fixed in the parent
//! at `placement = M_i` (pose in the parent's body frame), and the body frame sits at
//! `f_{λ(i),i} = M_i · X_J(q_i)` where `X_J = e^{S q}` is the joint's motion. At `q = 0` the
//! body frame coincides with the joint frame, so the joint's screw axes `S` are expressed in
//! the parent-fixed joint frame (equivalently in the body frame). The body's inertia is given
//! in its body frame.

mod body;
#[cfg(feature = "measure")]
pub mod builders;
#[cfg(all(test, not(feature = "measure")))]
mod builders;
pub mod description;
mod error;
mod joint_description;
pub mod joints;
mod tree;

pub use body::Body;
pub use error::ModelError;
pub use joints::{Ball, Cylindrical, Fixed, Free, Joint, Prismatic, Revolute, Universal};
pub use tree::ArticulatedTree;
