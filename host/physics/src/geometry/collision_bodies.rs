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
    /// How far beyond the speculative distance each body's contacts are kept (m): its travel
    /// over the step where that is more than half the speculative distance (a fast body,
    /// without continuous collision), else 0. Empty: 0 for every body.
    pub travel: &'a [f64],
}

impl CollisionBodies<'_> {
    /// Number of bodies.
    pub(crate) fn len(&self) -> usize {
        self.shape.len()
    }

    /// [`Self::travel`] of body `i` (m).
    pub(crate) fn travel(&self, i: usize) -> f64 {
        self.travel.get(i).copied().unwrap_or(0.0)
    }
}
