//! The table as a physics world: placement of the men, rods driven with bumpers, the
//! ball at rest, bouncing, kicked, entering the goal, never through a wall.

use space_foosball::ai::RodTarget;
use space_foosball::arena::{Arena, ArenaSettings};
use space_foosball::rules::ContactWith;
use space_foosball::Table;
use std::f64::consts::FRAC_PI_2;
use virtual_physics::algebra::Vec3;

fn lifted(table: &Table) -> Vec<RodTarget> {
    table
        .rods
        .iter()
        .map(|_| RodTarget {
            slide_m: 0.0,
            angle_rad: FRAC_PI_2,
        })
        .collect()
}

fn settle(a: &mut Arena, targets: &[RodTarget], ms: usize) {
    a.set_rod_targets(targets);
    for _ in 0..ms {
        a.step();
    }
}

/// The signed distance (m) from world point `p` to rod `rod`'s link (bar and men).
fn rod_distance(a: &Arena, rod: usize, p: Vec3) -> f64 {
    let body = a.world().body(a.rod_body(rod).unwrap()).unwrap();
    let local = body.rotation().tr_mul(&(p - body.position()));
    body.shape().signed_distance(&local)
}

#[test]
fn men_stand_where_the_table_kinematics_put_them() {
    let table = Table::standard();
    let mut a = Arena::new(&table).unwrap();
    let mut targets = vec![RodTarget::default(); table.rods.len()];
    targets[0] = RodTarget {
        slide_m: 0.05,
        angle_rad: 0.3,
    };
    settle(&mut a, &targets, 300);
    let pose = a.rod_poses()[0];
    // The servo holds the pose against the men's weight: its static error is the gravity
    // torque over the servo's stiffness, well under a milliradian.
    assert!((pose.slide_m - 0.05).abs() < 1e-4, "{pose:?}");
    assert!((pose.angle_rad - 0.3).abs() < 2e-3, "{pose:?}");
    // The keeper's rounded sole: its lowest point along the leg is the table's foot.
    let th = pose.angle_rad;
    let (fx, fz) = table.foot_xz(0, th);
    let foot = Vec3::new(fx, pose.slide_m, fz);
    let down = Vec3::new(-th.sin(), 0.0, -th.cos());
    assert!(rod_distance(&a, 0, foot).abs() < 1e-9, "sole at the foot");
    assert!(
        rod_distance(&a, 0, foot + down * 1e-3) > 0.9e-3,
        "nothing below"
    );
    assert!(
        rod_distance(&a, 0, foot - down * 1e-3) < 0.0,
        "the leg above"
    );
}

#[test]
fn rods_stop_at_the_ends_of_their_travel() {
    let table = Table::standard();
    let mut a = Arena::new(&table).unwrap();
    let half = table.rods[3].half_travel_m();
    let mut targets = vec![RodTarget::default(); table.rods.len()];
    targets[3].slide_m = 0.5; // far beyond the stop
    a.set_rod_targets(&targets);
    let mut last = 0.0;
    for _ in 0..400 {
        a.step();
        last = a.rod_poses()[3].slide_m;
        // The limit is a speculative row: the rod never passes the stop.
        assert!(last <= half + 1e-4, "{last} beyond {half}");
    }
    assert!((last - half).abs() < 1e-3, "{last}");
    // Pushed on into the stop, the hand's servo holds it there at rest.
    assert!(a.rod_velocities()[3][0].abs() < 1e-3);
}

#[test]
fn a_ball_at_rest_stays_at_rest() {
    let table = Table::standard();
    let mut a = Arena::new(&table).unwrap();
    let r = table.ball.radius_m();
    a.place_ball([0.0, 0.2, r], [0.0; 3]);
    for _ in 0..2000 {
        a.step();
    }
    let b = a.ball();
    assert!(
        (b.position[0]).abs() < 1e-4 && (b.position[1] - 0.2).abs() < 1e-4,
        "{b:?}"
    );
    assert!((b.position[2] - r).abs() < 5e-4, "{b:?}");
    assert!(b.speed() < 1e-3);
}

#[test]
fn the_ball_rolls_bounces_off_walls_and_never_passes_them() {
    let table = Table::standard();
    let r = table.ball.radius_m();
    let mut a = Arena::new(&table).unwrap();
    settle(&mut a, &lifted(&table), 100);
    // 3 m/s straight at the side wall, between the rods.
    a.place_ball([0.15, 0.2, r], [0.0, 3.0, 0.0]);
    a.set_ball_spin([0.0, 0.0, 0.0]);
    let mut hit = None;
    for _ in 0..200 {
        let s = a.step();
        if let Some(c) = s.contacts.iter().find(|c| c.with == ContactWith::Wall) {
            hit.get_or_insert(c.normal_speed_m_per_s);
        }
    }
    let hit = hit.expect("the ball reaches the wall");
    assert!(hit > 2.5 && hit < 3.1, "{hit}");
    let vy = a.ball().velocity[1];
    // Back off the wall at about the table's restitution (0.8) of the approach speed
    // (less what the cloth took while rolling).
    assert!(vy < -0.6 * hit && vy > -0.85 * hit, "{vy} after {hit}");
    // Hard shots (15 m/s) at every wall and corner stay inside the table.
    for (i, dir) in [
        [1.0, 0.0],
        [-1.0, 0.0],
        [0.0, 1.0],
        [0.0, -1.0],
        [0.7, 0.7],
        [-0.6, 0.8],
        [0.95, -0.3],
        [-0.9, -0.45],
    ]
    .iter()
    .enumerate()
    {
        let mut a = Arena::new(&table).unwrap();
        settle(&mut a, &lifted(&table), 100);
        let y = 0.25 * if i % 2 == 0 { 1.0 } else { -1.0 };
        a.place_ball([0.0, y, r], [15.0 * dir[0], 15.0 * dir[1], 0.0]);
        for t in 0..400 {
            a.step();
            assert!(
                a.ball_in_bounds(0.002),
                "shot {dir:?} step {t}: {:?}",
                a.ball()
            );
            let (gap, with) = a.ball_clearance();
            assert!(gap > -0.002, "shot {dir:?} step {t}: {gap} into {with:?}");
        }
    }
}

/// A 15 m/s shot (a hard shot) 3 mm inside the post, at one world step per millisecond:
/// into the goal.
#[test]
fn a_fast_ball_enters_the_goal_beside_the_post() {
    let table = Table::standard();
    let line = 0.5 * table.field.length_m + table.ball.radius_m();
    let r = table.ball.radius_m();
    let mut a = Arena::new(&table).unwrap();
    settle(&mut a, &lifted(&table), 100);
    let y = -(0.5 * table.goal.width_m - r - 0.003);
    a.place_ball([0.45, y, r], [15.0, 0.0, 0.0]);
    let mut deepest = f64::NEG_INFINITY;
    for _ in 0..30 {
        a.step();
        deepest = deepest.max(a.ball().position[0]);
    }
    assert!(deepest > line, "fully over the line: {deepest} vs {line}");
}

#[test]
fn a_spun_rod_kicks_the_ball_from_its_foot() {
    let table = Table::standard();
    let r = table.ball.radius_m();
    let rod = 5; // Home attack, x = 0.225, men at y = −0.208, 0, 0.208
    let mut a = Arena::new(&table).unwrap();
    let mut targets = lifted(&table);
    targets[rod] = RodTarget {
        slide_m: 0.0,
        angle_rad: 1.2, // foot back, up
    };
    settle(&mut a, &targets, 300);
    // The ball at rest just in front of the middle man.
    a.place_ball([0.225 + 0.02, 0.0, r], [0.0; 3]);
    let spin = 30.0;
    let mut kick = None;
    let mut foot_speed = 0.0;
    for k in 0..120 {
        targets[rod].angle_rad = 1.2 - spin * 1e-3 * (k + 1) as f64;
        a.set_rod_targets(&targets);
        let w = a.rod_velocities()[rod][1];
        let s = a.step();
        if let Some(c) = s
            .contacts
            .iter()
            .find(|c| c.with == (ContactWith::Man { rod }))
        {
            if kick.is_none() {
                kick = Some(c.normal_speed_m_per_s);
                foot_speed = -w * table.character_of(rod).foot_reach_m;
            }
        }
    }
    let kick = kick.expect("the foot hits the ball");
    let foot = table.character_of(rod).foot_reach_m * spin;
    // The servo tracks the hand: the foot arrives at the hand's speed.
    assert!(
        (foot_speed - foot).abs() < 0.15 * foot,
        "foot {foot_speed} m/s, hand {foot} m/s"
    );
    // An impact at the foot's speed with restitution e gives the ball at most
    // (1 + e) × the foot's speed (a foot of infinite effective mass).
    let e = table.ball.restitution;
    assert!(
        kick > 0.5 * foot && kick < (1.0 + e) * foot * 1.05,
        "kick {kick} vs foot {foot}"
    );
    let v = a.ball().velocity;
    // Forward (+x), not flying off sideways.
    assert!(
        v[0] > 0.5 * foot && v[0] < (1.0 + e) * foot * 1.05,
        "{v:?} foot {foot}"
    );
    assert!(v[1].abs() < 0.2 * v[0], "{v:?}");
}

#[test]
fn bad_settings_are_errors() {
    let table = Table::standard();
    for s in [
        ArenaSettings {
            substeps: 0,
            ..ArenaSettings::default()
        },
        ArenaSettings {
            field_restitution: 1.5,
            ..ArenaSettings::default()
        },
        ArenaSettings {
            hand_torque_n_m: f64::NAN,
            ..ArenaSettings::default()
        },
        ArenaSettings {
            hand_force_n: -1.0,
            ..ArenaSettings::default()
        },
    ] {
        let e = Arena::with_settings(&table, s).err().expect("rejected");
        assert!(e.to_string().contains("must be"), "{e}");
    }
}
