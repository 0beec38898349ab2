//! Hanging chains under a kinematic root on a sinusoid (0.2 m, 2 Hz, along x), 10 s at
//! 1 kHz at the default integrator: the root follows its trajectory to 1e-9 m, nothing goes
//! non-finite, and the energy stays below what the driver can physically put in.
//!
//! The root is a prescribed prismatic coordinate, so the tree steps on its own with the
//! linearly implicit step, the trajectory taken as a given coordinate change (hybrid
//! dynamics). The bound: the whole chain lifted to the root's height, and moving at ten times
//! the root's top speed — a whip that took in more than that would have had energy from
//! nowhere.
//!
//! Lengths: the 20-link chain runs its 10 s in every test run; the 100- and 500-link chains
//! run 10 s with `VPHYS_FULL_HARD_CASES=1` (the test command's release step) and 0.5 s
//! otherwise.

use std::f64::consts::PI;
use virtual_physics::algebra::{Inertia, Sym3, Vec3, SE3};
use virtual_physics::model::{ArticulatedTree, Prismatic, Revolute};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::{Effect, Effects, Motor, Trajectory, World};

mod hinged_arm;
mod run_length;
mod scene_order;
use run_length::length;
use scene_order::*;

const G: f64 = 9.81;
const DT: f64 = 1e-3;

/// `n` links of 10 g and 2 cm (rods with their centre of mass at mid-length), hinged about
/// `y`, under a 0.1 kg carriage on a prismatic root along `x` that follows 0.2 m at 2 Hz;
/// `steps` steps of 1 ms, with a [`servo_arm`] beside it in the same world when `with_servo`.
/// Returns the largest energy taken in (J) and the world.
fn shaken_chain(n: usize, steps: usize, with_servo: bool) -> (f64, World) {
    let (len, m) = (0.02, 0.01);
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let carriage = Inertia::from_com(0.1, Vec3::zeros(), Sym3::diagonal(&Vec3::repeat(1e-4)));
    tree.add_body(
        "root",
        None,
        SE3::identity(),
        Prismatic::new(Vec3::x()),
        carriage,
    )
    .unwrap();
    let link = Inertia::from_com(
        m,
        Vec3::new(0.0, 0.0, -0.5 * len),
        Sym3::diagonal(&Vec3::repeat(1e-7)),
    );
    for k in 0..n {
        let placement = if k == 0 {
            SE3::identity()
        } else {
            SE3::from_translation(Vec3::new(0.0, 0.0, -len))
        };
        tree.add_body(
            format!("link{k}"),
            Some(k),
            placement,
            Revolute::new(Vec3::y()),
            link,
        )
        .unwrap();
    }
    let nv = tree.nv();
    let (amp, freq) = (0.2, 2.0);
    let traj = Trajectory::Sinusoid {
        offset: 0.0,
        amplitude: amp,
        frequency: freq,
        phase: 0.0,
    };
    let sys =
        ArticulatedSystem::new(tree, vec![0.0; nv], vec![0.0; nv]).with_prescribed(0, traj.clone());
    let mut w = world();
    w.insert_tree(sys);
    if with_servo {
        w.insert_tree(servo_arm());
    }
    let e0 = w.energy();
    let servo_energy = if with_servo {
        tree_at(&w, 1).energy()
    } else {
        0.0
    };
    let total_mass = n as f64 * m;
    let v_root = 2.0 * PI * freq * amp;
    let bound = total_mass * G * n as f64 * len + 0.5 * total_mass * (10.0 * v_root).powi(2);
    let mut highest: f64 = 0.0;
    for step in 1..=steps {
        let t = step as f64 * DT;
        if let Err(e) = w.step() {
            panic!("{n} links: the step at {t} s failed: {e}");
        }
        let root = tree_at(&w, 0).q()[0];
        assert!(
            (root - traj.at(t)).abs() < 1e-9,
            "{n} links: root at {root} m, trajectory {} m",
            traj.at(t)
        );
        if step % 50 == 0 {
            let servo_now = if with_servo {
                tree_at(&w, 1).energy()
            } else {
                0.0
            };
            let e = w.energy() - e0 - (servo_now - servo_energy);
            assert!(
                e.is_finite() && e < bound,
                "{n} links: energy {e} J at {t} s (bound {bound} J)"
            );
            assert!(
                tree_at(&w, 0).qd().iter().all(|v| v.is_finite()),
                "{n} links: velocity not finite at {t} s"
            );
            highest = highest.max(e);
        }
    }
    eprintln!(
        "{n} links, {:.1} s: largest energy taken in {highest:.3} J (bound {bound:.1} J)",
        steps as f64 * DT
    );
    (highest, w)
}

fn world() -> World {
    World::builder(Effects::of(&[Effect::Gravity, Effect::Articulated]))
        .dt(DT)
        .gravity(Vec3::new(0.0, 0.0, -G))
        .build()
}

/// A 1 kg arm at 0.4 m on a hinge about `y`, held by a servo toward 0.5 rad (stiffness
/// 200 N·m/rad, damping 20 N·m·s/rad, 10 N·m): a tree stepped inside the constraint solve.
fn servo_arm() -> ArticulatedSystem {
    let (tree, _) = hinged_arm::arm(SE3::from_translation(Vec3::new(5.0, 0.0, 0.0)));
    let motor = Motor {
        target_position: Some(0.5),
        target_velocity: 0.0,
        stiffness: 200.0,
        damping: 20.0,
        max_force: 10.0,
    };
    ArticulatedSystem::new(tree, vec![0.0], vec![0.0]).with_motor(0, motor)
}

#[test]
fn a_kinematic_root_on_a_sinusoid_drives_a_hanging_chain_of_20_links() {
    let (taken, _) = shaken_chain(20, 10_000, false);
    assert!(taken > 0.0, "the driver put energy in");
}

#[test]
fn a_kinematic_root_on_a_sinusoid_drives_a_hanging_chain_of_100_links() {
    let (taken, _) = shaken_chain(100, length(500, 10_000), false);
    assert!(taken > 0.0, "the driver put energy in");
}

#[test]
fn a_kinematic_root_on_a_sinusoid_drives_a_hanging_chain_of_500_links() {
    let (taken, _) = shaken_chain(500, length(500, 10_000), false);
    assert!(taken > 0.0, "the driver put energy in");
}

/// A tree with prescribed motion only steps on its own while a servo-driven tree in the same
/// world steps inside the constraint solve: each keeps its own drive (the root on its
/// trajectory, the arm settling where its servo holds it against gravity).
#[test]
fn a_shaken_chain_and_a_servo_driven_arm_share_a_world() {
    let (taken, w) = shaken_chain(20, 2_000, true);
    assert!(taken > 0.0, "the driver put energy in");
    // Equilibrium of the arm: 200 (0.5 − q) + m g 0.4 cos q = 0.
    let f = |q: f64| 200.0 * (0.5 - q) + 1.0 * G * 0.4 * q.cos();
    let (mut lo, mut hi) = (0.5, 0.6);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let q = tree_at(&w, 1).q()[0];
    assert!(
        (q - lo).abs() < 1e-3,
        "the arm rests at {q} rad, its servo's equilibrium is {lo} rad"
    );
}
