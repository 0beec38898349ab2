//! The computer opponent on geometric scenarios.

use space_foosball::ai::{crossing_y, desired_pose, targets, AiLimits, RodTarget};
use space_foosball::rules::BallState;
use space_foosball::{Side, Table};

const R: f64 = 0.0175;

fn ball(x: f64, y: f64, vx: f64, vy: f64) -> BallState {
    BallState {
        position: [x, y, R],
        velocity: [vx, vy, 0.0],
    }
}

/// Runs the AI on one rod for `ms` steps with the ball fixed; returns the final pose.
fn settle(table: &Table, rod: usize, b: &BallState, ms: usize) -> RodTarget {
    let mut pose = RodTarget::default();
    for _ in 0..ms {
        pose = targets(table, &[rod], b, &[pose], &AiLimits::default(), 1e-3)[0];
    }
    pose
}

#[test]
fn crossing_point_reflects_off_the_side_walls() {
    assert_eq!(crossing_y(0.0, 0.0, -1.0, 0.0, -0.5, 0.3), Some(0.0));
    let y = crossing_y(0.0, 0.1, -1.0, 0.5, -0.5, 0.3).unwrap();
    // Free path 0.1 + 0.25 = 0.35 → reflected at 0.3 → 0.25.
    assert!((y - 0.25).abs() < 1e-12, "{y}");
    let y = crossing_y(0.0, 0.0, -1.0, -2.0, -0.5, 0.3).unwrap();
    // Free −1.0: −0.3 wall, back to +0.3 at −0.9, then to 0.2.
    assert!((y - 0.2).abs() < 1e-12, "{y}");
    assert_eq!(
        crossing_y(0.0, 0.0, 1.0, 0.0, -0.5, 0.3),
        None,
        "moving away"
    );
}

#[test]
fn goalkeeper_blocks_the_shot_line() {
    let t = Table::standard();
    // Away shoots from (0.2, 0.1) towards the Home goal, angled.
    let shot = ball(0.2, 0.1, -2.0, -0.3);
    let y_cross = 0.1 - 0.3 * (0.725 / 2.0);
    let pose = settle(&t, 0, &shot, 300);
    let keeper_y = t.rods[0].man_positions(pose.slide_m)[0];
    assert!((keeper_y - y_cross).abs() < 1e-9, "{keeper_y} vs {y_cross}");
    // His body covers where the ball crosses; tracking the ball's current y would not.
    let half = t.character_of(0).half_width_m();
    assert!((0.1 - y_cross).abs() > half + R);
    // Feet down to block.
    assert!(pose.angle_rad.abs() < 1e-9);
    // The Home defence blocks too, with the nearer of its two men.
    let pose = settle(&t, 1, &shot, 300);
    let ys = t.rods[1].man_positions(pose.slide_m);
    let y_def = 0.1 - 0.3 * (0.575 / 2.0);
    assert!(
        ys.iter().any(|y| (y - y_def).abs() < 1e-9),
        "{ys:?} vs {y_def}"
    );
}

#[test]
fn attack_shoots_when_the_ball_is_in_reach_in_front_of_a_man() {
    let t = Table::standard();
    let rod = 5; // home attack at x = 0.225, men at −0.208, 0, 0.208
    let in_front = ball(0.225 + 0.03, 0.2, 0.0, 0.0);
    let first = desired_pose(&t, rod, &in_front, RodTarget::default());
    assert!(
        first.angle_rad < 0.0,
        "Home spins with negative ω: {first:?}"
    );
    let pose = settle(&t, rod, &in_front, 50);
    // Spinning at the limit the whole time: 40 rad/s for 50 ms = −2 rad.
    assert!((pose.angle_rad + 2.0).abs() < 1e-9, "{pose:?}");
    // The shooter lined up with the ball.
    let ys = t.rods[rod].man_positions(pose.slide_m);
    assert!(ys.iter().any(|y| (y - 0.2).abs() < 1e-9), "{ys:?}");
    // Out of reach in front: no shot, feet down, tracking.
    let far = ball(0.225 + 0.2, 0.2, 0.0, 0.0);
    let pose = settle(&t, rod, &far, 300);
    assert!(pose.angle_rad.abs() < 1e-9);
    // Behind the rod (between it and its own goal): men lifted to let shots through.
    let behind = ball(0.225 - 0.2, 0.0, 0.0, 0.0);
    let pose = settle(&t, rod, &behind, 300);
    assert!(
        (pose.angle_rad + std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{pose:?}"
    );
}

#[test]
fn away_team_is_mirrored() {
    let t = Table::standard();
    let rod = 2; // away attack at x = −0.225, attacking −x
    assert_eq!(t.rods[rod].team, Side::Away);
    let in_front = ball(-0.225 - 0.03, 0.0, 0.0, 0.0);
    let d = desired_pose(&t, rod, &in_front, RodTarget::default());
    assert!(d.angle_rad > 0.0, "{d:?}");
    // A ball rolling past just behind the Away attack does not make it shoot: its men
    // lift (feet horizontal, +π/2 for Away) and stay there instead of spinning.
    let behind_away = ball(-0.225 + 0.03, 0.0, 0.5, 0.0);
    let pose = settle(&t, rod, &behind_away, 300);
    assert!(
        (pose.angle_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{pose:?}"
    );
}

#[test]
fn a_slow_ball_that_no_rod_would_play_is_reached_for() {
    use space_foosball::ai::{REACH_BACK_FORWARD_SHARE, STRIKE_ZONE};
    let t = Table::standard();
    let spin = |rod: usize, b: &BallState| settle(&t, rod, b, 100).angle_rad;
    // Home attack (x = 0.225, attacking +x: forward spin is negative).
    let reach = t.reach_x_m(5);
    // In front, just beyond the strike zone: a slow ball is shot, a fast one left.
    let x = 0.225 + 0.5 * (STRIKE_ZONE[1] + 1.0) * reach;
    assert!(spin(5, &ball(x, 0.0, 0.1, 0.0)) < -1.0);
    assert!(spin(5, &ball(x, 0.0, 1.0, 0.0)).abs() < 1e-9);
    // Still, just behind the axis, and no Home rod behind has it in its strike zone:
    // spun forward (the foot comes round and meets it from behind).
    let close = 0.5 * REACH_BACK_FORWARD_SHARE * reach;
    assert!(spin(5, &ball(0.225 - close, 0.0, 0.0, 0.0)) < -1.0);
    // Still and far behind: kicked backward, towards the own rods.
    let far = 0.5 * (REACH_BACK_FORWARD_SHARE + 1.0) * reach;
    assert!(spin(5, &ball(0.225 - far, 0.0, 0.0, 0.0)) > 1.0);
    // The goalkeeper never kicks backward (his own goal): forward there too.
    let keeper_reach = t.reach_x_m(0);
    let b = ball(-0.525 - 0.8 * keeper_reach, 0.0, 0.0, 0.0);
    assert!(spin(0, &b) < -1.0);
}

#[test]
fn midfield_tracks_with_the_nearest_man_and_respects_limits() {
    let t = Table::paper();
    let b = ball(0.3, -0.25, 0.0, 0.0);
    let limits = AiLimits::default();
    let mut pose = RodTarget {
        slide_m: 0.0,
        angle_rad: 13.0,
    };
    for _ in 0..500 {
        let next = targets(&t, &[3], &b, &[pose], &limits, 1e-3)[0];
        assert!((next.slide_m - pose.slide_m).abs() <= 1.5e-3 + 1e-15);
        assert!((next.angle_rad - pose.angle_rad).abs() <= 40e-3 + 1e-12);
        assert!(next.slide_m.abs() <= t.rods[3].half_travel_m());
        pose = next;
    }
    let ys = t.rods[3].man_positions(pose.slide_m);
    assert!(ys.iter().any(|y| (y + 0.25).abs() < 1e-9), "{ys:?}");
    // Rest angle: the nearest whole turn (13 rad → 4π), turns not unwound.
    assert!((pose.angle_rad - 2.0 * std::f64::consts::TAU).abs() < 1e-9);
    // Deterministic.
    let again = targets(&t, &[3], &b, &[pose], &limits, 1e-3);
    assert_eq!(again, targets(&t, &[3], &b, &[pose], &limits, 1e-3));
}
