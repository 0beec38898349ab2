//! Hard stacks at the default solver settings: the scene states only its physics (bodies,
//! masses, friction, gravity and the game's 1/60 s step), never substeps, stiffness or an
//! integrator.
//!
//! * A leaning stack of 25 unit boxes, each shifted 3 cm over the one below: statically
//!   stable (the centre of mass of the boxes above any box lies 12.5 cm inside its top face),
//!   so it must stand: no box moves more than 2 cm in 20 s (reduced run: 5 s). Its lower
//!   contacts carry their load outside their middle third, so soft contacts at the step's
//!   substep would tilt it over; its island takes extra substeps (`island_substeps.rs`),
//!   which a straight tower of the same boxes never does.
//! * A unit box 500 times heavier than the boxes of a 10-layer pyramid, dropped 0.5 m onto
//!   its top: no box sinks more than 5 cm into the ground, and after 3 s every body moves at
//!   less than 1 m/s (every point of it). The reduced run goes through the impact (0.75 s)
//!   and checks the sinking only.
//!
//! The default run is reduced; the full lengths run with `VPHYS_FULL_HARD_CASES=1` (use
//! `--release`), as the hard-case battery does:
//!
//!     VPHYS_FULL_HARD_CASES=1 cargo test -p virtual-physics --release --test hard_stacks

use virtual_physics::dynamics::BodyKind;
use virtual_physics::geometry::Shape;
use virtual_physics::pipeline::World;
use virtual_physics::scene::builtin::{pyramid, towers, unit_cube};
use virtual_physics::scene::BodyKindDesc;

mod run_length;
mod scene_order;
use run_length::length;
use scene_order::*;

/// Panics on a NaN or infinite pose or velocity.
fn assert_finite(w: &World, case: &str) {
    for (i, b) in w.bodies().enumerate() {
        let ok = [b.position(), b.linear_velocity(), b.angular_velocity()]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()));
        assert!(ok, "{case}: body {i} is not finite at t = {}", w.time());
    }
}

/// Depth (m) of the lowest corner of a box body below the ground plane `z = 0` (0 if above).
fn ground_penetration(w: &World) -> f64 {
    let mut deepest: f64 = 0.0;
    for b in w.bodies() {
        if let Shape::Cuboid { half } = *b.shape() {
            let r = b.rotation();
            // Lowest corner: each axis's contribution to z taken with the sign that lowers it.
            let reach: f64 = (0..3).map(|k| (r[(2, k)] * half[k]).abs()).sum();
            deepest = deepest.max(reach - b.position().z);
        }
    }
    deepest
}

/// Fastest point of any dynamic body (m/s): `|v| + |ω| ρ`, `ρ` the bounding radius.
fn fastest_point(w: &World) -> f64 {
    w.bodies()
        .filter(|b| b.kind() == BodyKind::Dynamic)
        .map(|b| {
            b.linear_velocity().norm() + b.angular_velocity().norm() * b.shape().bounding_radius()
        })
        .fold(0.0, f64::max)
}

/// Boxes shifted along x by this much (m) per layer in the leaning stack.
const LEAN_PER_LAYER: f64 = 0.03;

/// A stack of `n` unit boxes on the ground, each shifted `lean` (m) along x over the one below,
/// stepped at `dt` (s).
fn stack_at(n: usize, lean: f64, dt: f64) -> World {
    let mut s = towers(1, 1, 0);
    for k in 0..n {
        s.bodies
            .push(unit_cube([k as f64 * lean, 0.0, 0.5 + k as f64]));
    }
    s.dt = dt;
    s.build().unwrap()
}

/// The same at the scenes' 1/60 s.
fn stack(n: usize, lean: f64) -> World {
    stack_at(n, lean, 1.0 / 60.0)
}

/// The largest move (m) of any body from its start over `steps` steps of `w`, and the most
/// substeps and stiffened bodies the islands took in any step.
fn largest_move(w: &mut World, steps: usize) -> (f64, usize, usize) {
    let start = positions(w);
    let (mut worst, mut substeps, mut stiffened): (f64, usize, usize) = (0.0, 0, 0);
    for _ in 0..steps {
        w.step().unwrap();
        for (b, p0) in w.bodies().zip(&start) {
            worst = worst.max((b.position() - p0).norm());
        }
        substeps = substeps.max(w.counters().fine_substeps);
        stiffened = stiffened.max(w.counters().fine_bodies);
    }
    (worst, substeps, stiffened)
}

#[test]
fn a_leaning_stack_of_25_boxes_stands() {
    let n = 25;
    // Statics: the boxes above box k (k ≥ 0) have their centre of mass (n − k) / 2 layers'
    // shift beyond box k's centre, which must lie inside its half width of 0.5 m.
    let overhang = (n as f64) / 2.0 * LEAN_PER_LAYER;
    assert!(overhang < 0.5 - 0.1, "not statically stable with margin");
    let mut w = stack(n, LEAN_PER_LAYER);
    let (worst, extra, _) = largest_move(&mut w, length(300, 1200));
    eprintln!("leaning stack, 1/60 s: largest move {worst:.4} m, island substeps {extra}");
    assert_finite(&w, "leaning stack");
    assert!(worst <= 0.02, "a box moved {worst} m");
    assert!(
        extra > 12,
        "the stack's island took no extra substeps ({extra})"
    );
}

#[test]
fn a_leaning_stack_stands_at_1_ms_on_stiffer_contacts_alone() {
    // At the game's 1 ms the step's contacts are far below the stiffness cap: the island's
    // contacts stiffen without extra substeps.
    let mut w = stack_at(25, LEAN_PER_LAYER, 1e-3);
    let (worst, extra, stiffened) = largest_move(&mut w, length(2000, 20_000));
    eprintln!("leaning stack, 1 ms: largest move {worst:.4} m, island substeps {extra}");
    assert_finite(&w, "leaning stack at 1 ms");
    assert!(worst <= 0.02, "a box moved {worst} m");
    assert_eq!(extra, 0, "extra substeps at 1 ms");
    assert_eq!(stiffened, 25, "the stack's contacts were not stiffened");
}

#[test]
fn a_leaning_stack_pushed_by_a_moving_kinematic_body_keeps_the_steps_substeps() {
    // A kinematic box sliding slowly against the bottom box: its motion is integrated at the
    // step's substeps, so the island it touches takes them too.
    let n = 25;
    let mut s = towers(1, 1, 0);
    for k in 0..n {
        s.bodies
            .push(unit_cube([k as f64 * LEAN_PER_LAYER, 0.0, 0.5 + k as f64]));
    }
    let mut pusher = unit_cube([-1.0, 0.0, 0.5]);
    pusher.kind = BodyKindDesc::Kinematic;
    pusher.velocity = [0.001, 0.0, 0.0];
    s.bodies.push(pusher);
    let mut w = s.build().unwrap();
    for _ in 0..length(60, 120) {
        w.step().unwrap();
        assert_eq!(w.counters().fine_substeps, 0, "at t = {} s", w.time());
    }
    // Without the pusher the same stack takes them (a_leaning_stack_of_25_boxes_stands).
}

#[test]
fn a_leaning_stack_struck_takes_the_steps_substeps_while_it_moves() {
    // The leaning stack takes extra substeps at rest (a_leaning_stack_of_25_boxes_stands).
    // Its top box struck sideways at 1 m/s, the island is in motion, faster than a fall
    // through the speculative distance (2 cm at the defaults, √(2 g d) = 0.63 m/s): no column
    // of it stands under a static load, and it takes the step's substeps.
    let mut w = stack(25, LEAN_PER_LAYER);
    for _ in 0..120 {
        w.step().unwrap();
    }
    assert!(
        w.counters().fine_substeps > 12,
        "the stack at rest took no extra substeps"
    );
    let top = w.body_handles().last().unwrap();
    w.body_mut(top)
        .unwrap()
        .set_linear_velocity(nalgebra::Vector3::new(0.0, 1.0, 0.0));
    w.step().unwrap();
    assert_eq!(w.counters().fine_substeps, 0, "extra substeps in motion");
}

#[test]
fn a_straight_stack_takes_no_extra_substeps() {
    // The same boxes without the lean: every contact is loaded across its whole face.
    let mut w = stack(25, 0.0);
    for _ in 0..length(120, 300) {
        w.step().unwrap();
        assert_eq!(w.counters().fine_substeps, 0, "at t = {} s", w.time());
    }
}

#[test]
fn a_heavy_box_dropped_on_a_pyramid_is_carried() {
    let layers = 10;
    let ratio = 500.0;
    let mut s = pyramid(layers);
    let top = 0.5 + (layers - 1) as f64;
    let mut heavy = unit_cube([0.0, 0.0, top + 1.0 + 0.5]);
    heavy.mass = Some(ratio * 1.0);
    s.bodies.push(heavy);
    let mut w = s.build().unwrap();
    let mut deepest: f64 = 0.0;
    // 3 s at 1/60 s; the reduced run ends 0.4 s after the impact (the fall takes 0.32 s).
    let steps = length(45, 180);
    for _ in 0..steps {
        w.step().unwrap();
        deepest = deepest.max(ground_penetration(&w));
    }
    assert_finite(&w, "heavy box on a pyramid");
    // The heavy box is carried: it rests above the pyramid's top layer.
    let heavy_z = body_at(&w, w.body_count() - 1).position().z;
    assert!(heavy_z > top, "the heavy box sank to z = {heavy_z} m");
    assert!(deepest <= 0.05, "a box sank {deepest} m into the ground");
    if steps < 180 {
        return;
    }
    let fastest = fastest_point(&w);
    eprintln!(
        "heavy box on a pyramid: ground penetration {:.4} m, fastest point {fastest:.3} m/s after 3 s",
        deepest
    );
    assert!(
        fastest < 1.0,
        "a point still moves at {fastest} m/s after 3 s"
    );
}
