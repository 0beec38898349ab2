//! `towers-1120` and `pyramid-1240` stand for 10 s at 1/60 s: no box moves more than 1 cm
//! horizontally, no top sinks more than 1 cm, no NaN.
//!
//! The default run uses reduced scenes (2 × 2 towers of 20; a 5-layer pyramid) with the same
//! boxes, heights, ground, friction and step; `VPHYS_FULL_STACKS=1` runs the full 1120 and
//! 1240-box scenes (about a minute in the debug profile, a few seconds with `--release`).
use virtual_physics::algebra::Vec3;
use virtual_physics::pipeline::Effect;
use virtual_physics::scene::builtin::{pyramid, towers};
use virtual_physics::scene::SceneFile;

use virtual_physics::dynamics::BodyKind;

mod scene_order;
use scene_order::*;

fn full() -> bool {
    std::env::var("VPHYS_FULL_STACKS").is_ok_and(|v| v == "1")
}

/// (largest horizontal move, largest sink of any box, m) over 600 steps.
fn stand(s: SceneFile) -> (f64, f64) {
    let mut w = s.build().unwrap();
    let start: Vec<Vec3> = positions(&w);
    let mut horiz: f64 = 0.0;
    let mut sink: f64 = 0.0;
    for _ in 0..600 {
        w.step().unwrap();
        for (i, (b, p0)) in w.bodies().zip(&start).enumerate() {
            if b.kind() != BodyKind::Dynamic {
                continue;
            }
            let p = b.position();
            assert!(p.iter().all(|x| x.is_finite()), "NaN at body {i}");
            let d = p - p0;
            horiz = horiz.max((d.x * d.x + d.y * d.y).sqrt());
            sink = sink.max(-d.z);
        }
    }
    (horiz, sink)
}

#[test]
fn towers_stand_10_s() {
    for sleeping in [false, true] {
        let mut s = if full() {
            towers(8, 7, 20)
        } else {
            towers(2, 2, 20)
        };
        if sleeping {
            s.effects.push(Effect::Sleeping);
        }
        let (h, sink) = stand(s);
        assert!(
            h < 0.01,
            "sleeping {sleeping}: a box moved {h} m horizontally"
        );
        assert!(sink < 0.01, "sleeping {sleeping}: a box sank {sink} m");
    }
}

#[test]
fn pyramid_stands_10_s() {
    let s = if full() { pyramid(15) } else { pyramid(5) };
    let (h, sink) = stand(s);
    assert!(h < 0.01, "a box moved {h} m horizontally");
    assert!(sink < 0.01, "a box sank {sink} m");
}

#[test]
fn the_stand_test_can_fail_soft_contacts_sink() {
    // With the soft-step defaults of Box2D v3 (4 substeps, 30 Hz contacts, the sink not held)
    // a 20-box tower sinks several centimetres: the test above measures something real.
    let s = towers(1, 1, 20);
    let mut w = s.build().unwrap();
    w.settings_mut().substeps = 4;
    w.settings_mut().contact_hertz = 30.0;
    w.variants_mut().hold_sink = false;
    let z0 = body_at(&w, 20).position().z;
    for _ in 0..120 {
        w.step().unwrap();
    }
    assert!(z0 - body_at(&w, 20).position().z > 0.05);
}
