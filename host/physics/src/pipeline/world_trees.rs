//! The world's articulated trees through handles, and how their links meet the bodies.

use super::world::World;
use crate::algebra::SE3;
use crate::geometry::V3;
use crate::pipeline::ArticulatedSystem;
use crate::pipeline::{BodyHandle, LinkHandle, TreeHandle};

impl World {
    /// Inserts an articulated tree; it takes the world's integrator. Each link that carries
    /// shapes ([`ArticulatedSystem::with_link_shape`]) gets a proxy body (kinematic, named
    /// after the link, posed from the tree), through which it touches the other bodies:
    /// [`World::link_body`] names it.
    pub fn insert_tree(&mut self, system: ArticulatedSystem) -> TreeHandle {
        self.add_articulated(system);
        TreeHandle((self.articulated.len() - 1) as u32)
    }

    /// Number of trees.
    pub fn tree_count(&self) -> usize {
        self.articulated.len()
    }

    /// Every tree's handle, in insertion order.
    pub fn tree_handles(&self) -> impl ExactSizeIterator<Item = TreeHandle> {
        (0..self.articulated.len() as u32).map(TreeHandle)
    }

    /// The tree `h` (its state: `q()`, `qd()`, `tau()`, drives, energy).
    pub fn tree(&self, h: TreeHandle) -> Option<&ArticulatedSystem> {
        self.articulated.get(h.index())
    }

    /// The tree `h`, to set its state, joint forces or drive targets.
    pub fn tree_mut(&mut self, h: TreeHandle) -> Option<&mut ArticulatedSystem> {
        self.articulated.get_mut(h.index())
    }

    /// World pose of link `l` at the tree's current configuration.
    pub fn link_pose(&self, l: LinkHandle) -> Option<SE3<f64>> {
        let t = self.tree(l.tree)?;
        t.link_poses().get(l.link as usize).copied()
    }

    /// Angular velocity (rad/s, world) and velocity of the link frame's origin (m/s, world)
    /// of link `l`.
    pub fn link_velocity(&self, l: LinkHandle) -> Option<(V3, V3)> {
        let t = self.tree(l.tree)?;
        let poses = t.link_poses();
        t.link_velocities(&poses).get(l.link as usize).copied()
    }

    /// The proxy body through which link `l` touches other bodies (links with shapes only).
    pub fn link_body(&self, l: LinkHandle) -> Option<BodyHandle> {
        let i = self.proxies.iter().position(|p| {
            p.is_some_and(|p| p.tree == l.tree.index() && p.link == l.link as usize)
        })?;
        Some(self.body_slots.handle(i))
    }

    /// The tree link that body `b` stands for, if it is a link's proxy.
    pub fn link_of(&self, b: BodyHandle) -> Option<LinkHandle> {
        let i = self.body_slots.index(b)?;
        let p = (*self.proxies.get(i)?)?;
        Some(TreeHandle(p.tree as u32).link(p.link))
    }
}
