//! Effect gating, proven from the step counters.

use virtual_physics::pipeline::{Effect, Stage};
use virtual_physics::scene::builtin::{ball_roll, ball_wall, towers};
use virtual_physics::scene::SceneFile;

mod scene_order;
use scene_order::*;

fn stages(s: &SceneFile, steps: usize) -> Vec<Stage> {
    let mut w = s.build().unwrap();
    let mut all = Vec::new();
    for _ in 0..steps {
        w.step().unwrap();
        all.extend(w.counters().stages());
    }
    all
}

#[test]
fn no_broad_phase_without_contacts() {
    let mut s = towers(2, 2, 5);
    s.effects = vec![Effect::Gravity];
    let mut w = s.build().unwrap();
    assert!(!w.has_broad_phase());
    for _ in 0..10 {
        w.step().unwrap();
        let c = w.counters();
        assert!(
            !c.ran(Stage::BroadPhase) && !c.ran(Stage::NarrowPhase) && !c.ran(Stage::ContactSolve)
        );
        assert_eq!((c.broad_phase_tests, c.pairs_tested, c.contacts), (0, 0, 0));
        assert!(c.ran(Stage::Gravity) && c.ran(Stage::Integrate));
    }
    // Free fall: the boxes pass through the ground.
    assert!(body_at(&w, 1).position().z < 0.5 - 0.5 * 9.81 * 0.02);
    // With contacts the same scene builds a broad phase and finds the contacts.
    s.effects.push(Effect::Contacts);
    let mut w = s.build().unwrap();
    w.step().unwrap();
    assert!(w.counters().ran(Stage::BroadPhase) && w.counters().contacts >= 4 * 20);
}

#[test]
fn no_articulated_solve_without_articulated_bodies() {
    let s = towers(1, 1, 3);
    assert!(!stages(&s, 5).contains(&Stage::Articulated));
    let mut w = s.build().unwrap();
    w.step().unwrap();
    assert_eq!(w.counters().articulated_solves, 0);

    // A scene with a tree runs ABA once per tree per substep.
    let model = virtual_physics::model::builders::chain(3);
    let text = format!(
        r#"{{"effects": ["gravity", "articulated"], "articulated": [{{"model": {}, "qd": [1, 0, 0]}}]}}"#,
        model.to_json()
    );
    let s = SceneFile::from_json(&text).unwrap();
    let mut w = s.build().unwrap();
    let e0 = w.energy();
    for _ in 0..60 {
        w.step().unwrap();
        assert!(
            w.counters().ran(Stage::Articulated)
                && w.counters().articulated_solves == w.settings().substeps
        );
        assert!(!w.counters().ran(Stage::BroadPhase));
    }
    // Semi-implicit Euler on a pendulum chain: energy stays close.
    let e1 = w.energy();
    assert!((e1 - e0).abs() < 0.02 * e0.abs().max(1.0), "{e0} → {e1}");
}

#[test]
fn no_restitution_pass_without_restitution() {
    let mut s = ball_wall(1.0 / 60.0);
    let mut w = s.build().unwrap();
    let mut ran = false;
    for _ in 0..6 {
        w.step().unwrap();
        ran |= w.counters().ran(Stage::Restitution);
    }
    assert!(ran, "the scene with restitution runs the pass");
    s.effects.retain(|e| *e != Effect::Restitution);
    let mut w = s.build().unwrap();
    for _ in 0..6 {
        w.step().unwrap();
        assert!(!w.counters().ran(Stage::Restitution));
        assert_eq!(w.counters().restitution_constraints, 0);
    }
    // No bounce: the ball stops at the wall.
    assert!(
        body_at(&w, 0).linear_velocity().x.abs() < 0.5,
        "vx = {}",
        body_at(&w, 0).linear_velocity().x
    );
}

#[test]
fn rolling_resistance_and_sleeping_only_when_declared() {
    let s = ball_roll();
    let st = stages(&s, 3);
    assert!(st.contains(&Stage::RollingResistance) && !st.contains(&Stage::Islands));
    let mut s2 = towers(1, 1, 2);
    s2.effects.push(Effect::Sleeping);
    let st = stages(&s2, 3);
    assert!(st.contains(&Stage::Islands) && !st.contains(&Stage::RollingResistance));
    assert!(!st.contains(&Stage::Gyroscopic) && !st.contains(&Stage::Damping));
}

#[test]
fn counters_count_pairs_contacts_and_iterations() {
    let s = towers(2, 1, 3);
    let mut w = s.build().unwrap();
    w.step().unwrap();
    let c = w.counters();
    // Each tower: ground–box and two box–box manifolds of 4 points.
    assert_eq!(c.manifolds, 6);
    assert_eq!(c.contacts, 24);
    assert_eq!(c.pairs_tested, 6);
    assert_eq!(c.substeps, w.settings().substeps);
    assert_eq!(c.solver_iterations, 2 * w.settings().substeps);
    assert_eq!(c.awake_bodies, 6);
}

#[test]
fn sleeping_towers_sleep_and_skip_work() {
    let mut s = towers(2, 2, 5);
    s.effects.push(Effect::Sleeping);
    let mut w = s.build().unwrap();
    for _ in 0..120 {
        w.step().unwrap();
    }
    let c = w.counters();
    assert_eq!(c.awake_bodies, 0, "all towers should be asleep after 2 s");
    assert_eq!(c.pairs_tested, 0);
    assert!(!c.ran(Stage::ContactSolve));
}

#[test]
fn a_falling_box_wakes_a_sleeping_tower() {
    let mut s = towers(1, 1, 3);
    s.effects.push(Effect::Sleeping);
    s.bodies
        .push(virtual_physics::scene::builtin::unit_cube([0.0, 0.0, 12.0]));
    let mut w = s.build().unwrap();
    let mut slept = false;
    let mut woke = false;
    for _ in 0..240 {
        w.step().unwrap();
        let tower_awake = (1..4).filter(|&i| body_at(&w, i).is_awake()).count();
        if tower_awake == 0 {
            slept = true;
        } else if slept {
            woke = true;
        }
    }
    assert!(slept && woke, "slept {slept} woke {woke}");
    // The dropped box ends on top of the tower.
    assert!(
        (body_at(&w, 4).position().z - 3.5).abs() < 0.02,
        "z = {}",
        body_at(&w, 4).position().z
    );
}
