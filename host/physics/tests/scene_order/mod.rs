//! Test access to a world's bodies and trees by their order in the scene (storage order:
//! these tests remove nothing, so it is the order the scene or the test inserted them in).
#![allow(dead_code)]

use virtual_physics::pipeline::World;

/// Body `i` in storage order.
pub fn body_at(w: &World, i: usize) -> virtual_physics::pipeline::BodyRef<'_> {
    w.bodies().nth(i).expect("a body of the scene")
}

/// Body `i` in storage order, to set its state.
pub fn body_at_mut(w: &mut World, i: usize) -> virtual_physics::pipeline::BodyMut<'_> {
    let h = w.body_handles().nth(i).expect("a body of the scene");
    w.body_mut(h).expect("a live body")
}

/// Every body's centre of mass (m, world), in storage order.
pub fn positions(w: &World) -> Vec<virtual_physics::algebra::Vec3> {
    w.bodies().map(|b| b.position()).collect()
}

/// Tree `k` in insertion order.
pub fn tree_at(w: &World, k: usize) -> &virtual_physics::pipeline::ArticulatedSystem {
    let h = w.tree_handles().nth(k).expect("a tree of the scene");
    w.tree(h).expect("a tree")
}

/// Tree `k` in insertion order, to set its state.
pub fn tree_at_mut(w: &mut World, k: usize) -> &mut virtual_physics::pipeline::ArticulatedSystem {
    let h = w.tree_handles().nth(k).expect("a tree of the scene");
    w.tree_mut(h).expect("a tree")
}
