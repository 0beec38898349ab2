//! A rigid body of an articulated tree.

use super::Joint;
use crate::algebra::{Inertia, SE3};
use crate::Real;

/// A rigid body with the joint that connects it to its parent.
#[derive(Clone, Debug)]
pub struct Body<T: Real> {
    /// Name (for messages and the JSON description).
    pub name: String,
    /// Index of the parent body; `None`: attached to the fixed world frame.
    pub parent: Option<usize>,
    /// `M_i`: pose of the joint frame in the parent's body frame (or the world frame).
    pub placement: SE3<T>,
    /// The joint to the parent.
    pub(crate) joint: Box<dyn Joint<T>>,
    /// Inertia in the body frame.
    pub inertia: Inertia<T>,
    /// Offset of this joint's coordinates in the configuration vector `q`.
    pub(crate) q_offset: usize,
    /// Offset of this joint's velocity coordinates in `q̇`, `q̈`, `τ`.
    pub(crate) v_offset: usize,
    /// `joint.nq()`, cached (the recursions ask for it per body and per pass).
    pub(crate) nq: usize,
    /// `joint.nv()`, cached.
    pub(crate) nv: usize,
}

impl<T: Real> Body<T> {
    /// Number of configuration coordinates of the joint.
    #[inline]
    pub(crate) fn nq(&self) -> usize {
        self.nq
    }

    /// Degrees of freedom of the joint.
    #[inline]
    pub(crate) fn nv(&self) -> usize {
        self.nv
    }
}
