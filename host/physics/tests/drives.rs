//! Motors, limits and prescribed motion on tree coordinates, checked against statics and
//! kinematics.

use virtual_physics::algebra::{Inertia, Sym3, Vec3, SE3};
use virtual_physics::model::{ArticulatedTree, Prismatic};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::{Effect, Effects, Motor, World};

mod hinged_arm;
mod scene_order;
use scene_order::*;

const G: f64 = 9.81;

fn world(dt: f64) -> World {
    World::builder(Effects::of(&[Effect::Gravity, Effect::Articulated]))
        .dt(dt)
        .gravity(Vec3::new(0.0, 0.0, -G))
        .build()
}

/// The arm at the origin (see `hinged_arm`).
fn arm() -> (ArticulatedTree<f64>, f64) {
    hinged_arm::arm(SE3::identity())
}

fn servo(max_force: f64) -> Motor {
    Motor {
        target_position: Some(0.0),
        target_velocity: 0.0,
        stiffness: 1e4,
        damping: 50.0,
        max_force,
    }
}

#[test]
fn a_torque_limited_position_motor_holds_a_load_below_its_limit() {
    let (tree, load) = arm();
    let sys = ArticulatedSystem::new(tree, vec![0.0], vec![0.0]).with_motor(0, servo(1.5 * load));
    let mut w = world(1e-3);
    w.insert_tree(sys);
    for _ in 0..2000 {
        w.step().expect("finite");
    }
    let a = tree_at(&w, 0);
    // Static deflection τ / k = 3.9e-4 rad; it must not sag further.
    assert!(a.q()[0].abs() < 1e-3, "arm angle {} rad", a.q()[0]);
    assert!(
        a.qd()[0].abs() < 1e-4,
        "arm still moving at {} rad/s",
        a.qd()[0]
    );
    // The motor carries the load: its torque balances gravity's (about y, gravity pulls
    // the arm's +x end down, a positive rotation about y).
    let tau = a.drive_force(0, w.dt());
    assert!(
        ((tau.abs() - load) / load).abs() < 0.01,
        "motor {tau} N·m, load {load} N·m"
    );
}

#[test]
fn a_torque_limited_position_motor_slips_above_its_limit() {
    let (tree, load) = arm();
    let max = 0.5 * load;
    let sys = ArticulatedSystem::new(tree, vec![0.0], vec![0.0]).with_motor(0, servo(max));
    let mut w = world(1e-3);
    w.insert_tree(sys);
    for _ in 0..300 {
        w.step().expect("finite");
    }
    let a = tree_at(&w, 0);
    assert!(
        a.q()[0] > 0.3,
        "the arm should have fallen: {} rad",
        a.q()[0]
    );
    let tau = a.drive_force(0, w.dt());
    assert!(
        ((tau.abs() - max) / max).abs() < 1e-9,
        "saturated motor {tau} N·m, limit {max}"
    );
}

/// A 2 kg slider on a vertical prismatic joint falls 0.5 m onto its lower limit at 0: it
/// stops there, never more than 1 mm past it, at 1 kHz and at 60 Hz.
#[test]
fn a_prismatic_limit_stops_the_joint_at_the_limit() {
    for dt in [1e-3, 1.0 / 60.0] {
        let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
        let inertia = Inertia::from_com(2.0, Vec3::zeros(), Sym3::diagonal(&Vec3::repeat(0.01)));
        tree.add_body(
            "slider",
            None,
            SE3::identity(),
            Prismatic::new(Vec3::z()),
            inertia,
        )
        .unwrap();
        let sys = ArticulatedSystem::new(tree, vec![0.5], vec![0.0]).with_limits(0, 0.0, 1.0);
        let mut w = world(dt);
        w.insert_tree(sys);
        let steps = (2.0 / dt) as usize;
        for _ in 0..steps {
            w.step().expect("finite");
            let q = tree_at(&w, 0).q()[0];
            assert!(q > -1e-3, "at dt {dt}: {q} m past the limit");
        }
        let a = tree_at(&w, 0);
        assert!(
            a.q()[0].abs() < 1e-3 && a.qd()[0].abs() < 1e-3,
            "at dt {dt}: q {} q̇ {}",
            a.q()[0],
            a.qd()[0]
        );
        // Resting on the limit, the limit carries the weight.
        let f = a.drive_force(0, dt);
        assert!(
            ((f - 2.0 * G) / (2.0 * G)).abs() < 0.01,
            "at dt {dt}: limit force {f} N"
        );
    }
}
