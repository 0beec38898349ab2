//! What collision detection reads of the bodies: a borrowed view, one entry per body, so that
//! the collision layer depends on no body container of the dynamics layer.

use super::{Aabb, Shape, M3, V3};

/// The bodies as collision detection sees them (world frame), all slices of one length.
#[derive(Clone, Copy, Debug)]
pub struct CollisionBodies<'a> {
    /// Shape of each body, in its body frame.
    pub shape: &'a [Shape],
    /// Rotation, world from body.
    pub rot: &'a [M3],
    /// Body origin (the centre of mass), world (m).
    pub pos: &'a [V3],
    /// Bounding box grown by the contact margin, world (m).
    pub aabb: &'a [Aabb],
    /// Whether the body is simulated this step (dynamic and not sleeping).
    pub awake: &'a [bool],
    /// Whether contacts move the body (dynamic bodies and tree links); pairs of two bodies
    /// that contacts do not move are never reported.
    pub responds: &'a [bool],
}

impl CollisionBodies<'_> {
    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.shape.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.shape.is_empty()
    }
}
