//! The world's bodies through handles: inserting, removing, reading and setting them.

use super::World;
use crate::pipeline::BodyHandle;

impl World {
    /// Number of bodies (free, kinematic, fixed, and the proxies of tree links).
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Every body's handle, in storage order (insertion order until a body is removed).
    pub fn body_handles(&self) -> impl ExactSizeIterator<Item = BodyHandle> + '_ {
        (0..self.bodies.len()).map(|i| self.body_slots.handle(i))
    }
}
