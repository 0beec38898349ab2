//! A horizontal arm on a hinge about `y`, shared by the drive tests.
#![allow(dead_code)]

use virtual_physics::algebra::{Inertia, Sym3, Vec3, SE3};
use virtual_physics::model::{ArticulatedTree, Revolute};

/// Gravity (m/s²).
pub const G: f64 = 9.81;

/// A horizontal arm about `y` at `placement`: 1 kg at 0.4 m (plus a small rotational
/// inertia), gravity along −z. Returns the tree and gravity's torque about the hinge at
/// `q = 0`, `m g 0.4 = 3.924 N·m`.
pub fn arm(placement: SE3<f64>) -> (ArticulatedTree<f64>, f64) {
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let inertia = Inertia::from_com(
        1.0,
        Vec3::new(0.4, 0.0, 0.0),
        Sym3::diagonal(&Vec3::repeat(1e-3)),
    );
    tree.add_body("arm", None, placement, Revolute::new(Vec3::y()), inertia)
        .unwrap();
    (tree, 1.0 * G * 0.4)
}
