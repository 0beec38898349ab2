//! The goal mouth at one world step per millisecond: a fast ball that passes beside a post
//! keeps its speed, one aimed at the post bounces off it, and in 1000 random shots no step
//! whose straight swept ball touches nothing changes the ball's motion (the scene:
//! `goal_mouth_scene`).

mod goal_mouth_scene;

use goal_mouth_scene::*;
use virtual_physics::algebra::Vec3;
use virtual_physics::pipeline::SolverSettings;
use virtual_physics::scene::SceneFile;

/// Distance (m) from `x` to the box `[min, max]` (0 inside).
fn box_distance(x: &Vec3, w: &Wall) -> f64 {
    let c = (w.min + w.max) * 0.5;
    let h = (w.max - w.min) * 0.5;
    ((x - c).abs() - h).sup(&Vec3::zeros()).norm()
}

/// Closest approach (m) of the ball's centre on the segment `p + s d`, `s ∈ [0, 1]`, to the
/// field and every wall: the distance to a convex set is convex along a line, so a golden
/// section search finds its minimum (to 1e-13 of the segment).
fn closest_approach(p: &Vec3, d: &Vec3) -> (f64, &'static str) {
    let mut best = (p.z.min(p.z + d.z), "field");
    for w in walls() {
        let f = |s: f64| box_distance(&(p + d * s), &w);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (0.0, 1.0);
        while hi - lo > 1e-13 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if f(x1) < f(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        let m = f(0.0).min(f(1.0)).min(f(0.5 * (lo + hi)));
        if m < best.0 {
            best = (m, w.name);
        }
    }
    best
}

#[test]
fn a_ball_at_15_m_s_one_millimetre_beside_the_post_goes_in_at_full_speed() {
    for side in [1.0, -1.0] {
        let y = side * (GW - R - 1e-3);
        let v0 = Vec3::new(15.0, 0.0, 0.0);
        let mut w = scene(Vec3::new(HL - 0.1, y, 0.5 * GH), v0, true);
        // Until the ball is wholly behind the goal line, short of the goal's back wall.
        while ball(&w).0.x < HL + R + 0.01 {
            w.step().unwrap();
            let (p, v) = ball(&w);
            assert!(
                (v - v0).norm() <= 1e-9 * v0.norm(),
                "side {side}: at x = {:.4} m the velocity is {v:?} (was {v0:?})",
                p.x
            );
            assert!(w.time() < 0.05, "the ball did not reach the goal");
        }
        assert!((ball(&w).0.y - y).abs() < 1e-12);
    }
}

#[test]
fn a_ball_aimed_at_the_post_bounces_off_it() {
    // Into the face beside the mouth, 5 mm from the post's edge: straight back with the
    // pair's restitution 0.8 (no friction, so the tangential velocity stays zero).
    let mut w = scene(
        Vec3::new(HL - 0.1, GW + 0.005, 0.5 * GH),
        Vec3::x() * 15.0,
        false,
    );
    let mut deepest: f64 = 0.0;
    while w.time() < 0.02 {
        w.step().unwrap();
        deepest = deepest.max(ball(&w).0.x + R - HL);
    }
    let (_, v) = ball(&w);
    assert!(deepest < 1e-3, "the ball went {deepest} m into the post");
    assert!((v.x + 0.8 * 15.0).abs() < 0.01 * 15.0, "bounced at {v:?}");
    assert!(v.y.abs() < 1e-6 && v.z.abs() < 1e-6, "bounced at {v:?}");

    // Onto the post's edge itself, the centre R/2 inside the mouth: the impact normal
    // leans 30° off the goal line, n = (−cos 30°, −sin 30°, 0), and the ball leaves along
    // v − (1 + e)(v·n) n.
    let v0 = Vec3::x() * 15.0;
    let mut w = scene(Vec3::new(HL - 0.1, GW - 0.5 * R, 0.5 * GH), v0, false);
    while w.time() < 0.02 {
        w.step().unwrap();
    }
    let (p, v) = ball(&w);
    let n = Vec3::new(-(0.75f64).sqrt(), -0.5, 0.0);
    let expect = v0 - n * (1.8 * v0.dot(&n));
    assert!(
        (v - expect).norm() < 0.01 * v0.norm(),
        "left the edge at {v:?}, expected {expect:?}"
    );
    assert!(p.x < HL, "the ball is at {p:?}");
}

/// SplitMix64: a seeded generator for the shots.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

#[test]
fn a_thousand_random_shots_are_stopped_only_by_what_they_touch() {
    let mut rng = Rng(0x005e_ed0f_90a1);
    let (mut free_steps, mut near_misses, mut touches) = (0, 0, 0);
    let substeps = SolverSettings::default().substeps as f64;
    for shot in 0..1000 {
        // From 6–16 cm in front of the goal line, across the mouth and the posts, at
        // 2–15 m/s, up to ±0.35 rad across and a little up or down.
        let p0 = Vec3::new(
            HL - rng.range(0.06, 0.16),
            rng.range(-GW - 0.03, GW + 0.03),
            rng.range(R + 0.005, GH - R - 0.005),
        );
        let (speed, yaw, pitch) = (
            rng.range(2.0, 15.0),
            rng.range(-0.35, 0.35),
            rng.range(-0.05, 0.05),
        );
        let v0 = Vec3::new(
            yaw.cos() * pitch.cos(),
            yaw.sin() * pitch.cos(),
            pitch.sin(),
        ) * speed;
        let mut w = scene(p0, v0, true);
        for step in 0..60 {
            let (p, v) = ball(&w);
            // A spinning ball's centre follows the screw of T ← T·Exp(hV) in each substep
            // h, off the straight line by at most ½ |v| |ω| h dt over the step.
            let omega = w
                .body(w.body_named("ball").unwrap())
                .unwrap()
                .angular_velocity();
            let screw = 0.5 * v.norm() * omega.norm() * (DT / substeps) * DT;
            let (gap, near) = closest_approach(&p, &(v * DT));
            w.step().unwrap();
            let (p1, v1) = ball(&w);
            if gap > R + screw + 1e-7 {
                // The straight swept ball touches nothing within the step.
                free_steps += 1;
                if gap < R + 0.02 {
                    near_misses += 1;
                }
                assert!(
                    (v1 - v).norm() <= 1e-9 * v.norm(),
                    "shot {shot} step {step}: {:.3} mm clear of {near}, the velocity went \
                     from {v:?} to {v1:?}",
                    (gap - R) * 1e3
                );
                assert!(
                    (p1 - (p + v * DT)).norm() <= screw + 1e-12,
                    "shot {shot} step {step}: {:.3} mm clear of {near}, moved {:?} instead of {:?}",
                    (gap - R) * 1e3,
                    p1 - p,
                    v * DT
                );
            } else {
                touches += 1;
            }
            if p1.x > HL + GD || p1.x < HL - 0.2 {
                break;
            }
        }
    }
    eprintln!("{free_steps} free steps, {near_misses} within 20 mm of a wall, {touches} touching");
    // The shots exercise what the test is about: steps passing within the speculative
    // distance (20 mm) of a post without touching it, and real impacts.
    assert!(near_misses > 1000, "only {near_misses} near misses");
    assert!(touches > 200, "only {touches} impacts");
    assert!(free_steps > 10_000, "only {free_steps} free steps");
}

#[test]
fn a_ball_between_two_close_walls_keeps_both_contacts_of_its_step() {
    // Walls 2 mm from the ball on each side, 15 m/s, elastic: within the first step the
    // ball hits the right wall, then (reflected) the left one. The left wall's contact is
    // found through the first impact; a straight sweep alone would drop it.
    let gap = 0.002;
    let wall = |name: &str, x: f64| {
        format!(
            r#"{{"name": "{name}", "kind": "fixed", "shape": {{"type": "box", "half_extents": [0.01, 0.1, 0.1]}}, "position": [{x}, 0, 0], "material": "bouncy"}}"#
        )
    };
    let json = format!(
        r#"{{"name": "two walls", "dt": {DT}, "effects": ["contacts", "restitution", "continuous_collision"],
            "materials": [{{"name": "bouncy", "friction": 0.0, "restitution": 1.0}}],
            "bodies": [{}, {},
              {{"name": "ball", "shape": {{"type": "sphere", "radius": {R}}}, "mass": {MASS},
                "velocity": [15, 0, 0], "material": "bouncy"}}]}}"#,
        wall("left", -(R + gap + 0.01)),
        wall("right", R + gap + 0.01)
    );
    let mut w = SceneFile::from_json(&json).unwrap().build().unwrap();
    w.step().unwrap();
    let handle = |name: &str| w.body_named(name).unwrap();
    let (l, r, b) = (handle("left"), handle("right"), handle("ball"));
    let touching = |wall| {
        w.contacts()
            .any(|c| (c.a, c.b) == (wall, b) || (c.a, c.b) == (b, wall))
    };
    assert!(touching(r) && touching(l));
    // Over 100 steps the ball stays between the walls, overlapping neither by more than
    // 1 mm, and keeps bouncing (elastic walls, no friction).
    for _ in 0..100 {
        w.step().unwrap();
        let (p, v) = ball(&w);
        assert!(p.x.abs() <= gap + 1e-3, "the ball is at x = {} m", p.x);
        assert!(v.x.abs() > 1.0, "the ball stopped: {v:?}");
    }
}
