//! The contacts' warm start replayed per body (`pipeline/warm_start_replay.rs`) applies the
//! impulses the contacts' own warm start applies, and only where nothing else in the solve
//! changes the bodies' velocities.

use virtual_physics::algebra::Vec3;
use virtual_physics::geometry::Shape;
use virtual_physics::model::Ball;
use virtual_physics::pipeline::{BodyBuilder, Effect, Effects, JointBuilder, World};
use virtual_physics::scene::builtin::pyramid;

/// The pyramid with sleeping off, its warm start replayed or not.
fn pyramid_world(replay: bool) -> World {
    let mut s = pyramid(5);
    s.effects.retain(|e| *e != Effect::Sleeping);
    let mut w = s.build().unwrap();
    w.variants_mut().replay_warm_start = replay;
    w
}

/// The largest difference of any body's velocity (m/s or rad/s) and position (m).
fn largest_differences(a: &World, b: &World) -> (f64, f64) {
    a.bodies()
        .zip(b.bodies())
        .fold((0.0, 0.0), |(v, p), (x, y)| {
            let dv = (x.linear_velocity() - y.linear_velocity())
                .norm()
                .max((x.angular_velocity() - y.angular_velocity()).norm());
            let dp = (x.position() - y.position()).norm();
            (v.max(dv), p.max(dp))
        })
}

/// Every body's position and velocities after `steps` steps, the last of them in contact.
fn state_after(w: &mut World, steps: usize) -> Vec<(Vec3, Vec3, Vec3)> {
    for _ in 0..steps {
        w.step().unwrap();
    }
    assert!(w.counters().contacts > 0);
    w.bodies()
        .map(|b| (b.position(), b.linear_velocity(), b.angular_velocity()))
        .collect()
}

/// Over a step of 12 substeps of the pyramid settling under gravity (speeds up to `g dt`,
/// 0.16 m/s), the replay and the contacts' own warm start apply the same impulses: the
/// velocities differ by rounding alone. A few thousand operations on each velocity, each
/// rounding 1e-16 of it, stay far below 1e-12 m/s; one impulse missing or applied twice
/// would differ by about `g h` = 0.014 m/s.
#[test]
fn the_replay_applies_the_contacts_own_warm_start() {
    let (mut replayed, mut own) = (pyramid_world(true), pyramid_world(false));
    for step in 0..3 {
        replayed.step().unwrap();
        own.step().unwrap();
        assert!(replayed.counters().contacts > 0);
        let (dv, dp) = largest_differences(&replayed, &own);
        assert!(dv <= 1e-12 && dp <= 1e-12, "step {step}: {dv} m/s, {dp} m");
    }
}

/// A chain of balls on ball joints, released tilted over the ground: the joints change the bodies' velocities in the solve
/// too, so the world keeps the contacts' own warm start, and the setting changes no bit.
#[test]
fn a_world_with_joints_keeps_the_contacts_own_warm_start() {
    let run = |replay: bool| {
        let effects = Effects::of(&[
            Effect::Gravity,
            Effect::Contacts,
            Effect::Friction,
            Effect::Joints,
        ]);
        let mut w = World::builder(effects)
            .gravity(Vec3::new(0.0, 0.0, -9.81))
            .build();
        w.variants_mut().replay_warm_start = replay;
        w.insert_body(BodyBuilder::fixed(Shape::HalfSpace { normal: Vec3::z() }));
        let mut prev = None;
        for k in 0..6 {
            let b = w.insert_body(
                BodyBuilder::dynamic(Shape::Sphere { radius: 0.05 })
                    .mass(1.0 + k as f64)
                    .position(Vec3::new(0.1 * k as f64, 0.0, 0.06 + 0.01 * k as f64)),
            );
            if let Some(a) = prev {
                let anchor = Vec3::new(0.1 * k as f64 - 0.05, 0.0, 0.055 + 0.01 * k as f64);
                w.insert_joint(JointBuilder::new(&Ball, a, b).anchor(anchor))
                    .unwrap();
            }
            prev = Some(b);
        }
        // At 1 ms, 0.3 s: the chain lands end first and rolls over the ground.
        state_after(&mut w, 300)
    };
    assert_eq!(run(true), run(false));
}

/// The spinning top's tip follows the turn of its round part within the step, so its contact's
/// rows change from substep to substep: the world keeps the contacts' own warm start (replayed,
/// the top gains energy and falls), and the setting changes no bit.
#[test]
fn a_contact_that_follows_a_turn_keeps_its_own_warm_start() {
    let path = format!("{}/scenes/spinning-top.json", env!("CARGO_MANIFEST_DIR"));
    let scene = virtual_physics::scene::SceneFile::from_path(&path).unwrap();
    let run = |replay: bool| {
        let mut w = scene.build().unwrap();
        w.variants_mut().replay_warm_start = replay;
        state_after(&mut w, 60)
    };
    assert_eq!(run(true), run(false));
}
