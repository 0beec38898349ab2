//! The table as a physics world: placement of the men, rods driven with bumpers, the
//! ball at rest, bouncing, kicked, entering the goal, never through a wall.

use space_foosball::ai::RodTarget;
use space_foosball::arena::{Arena, ArenaSettings, BodyRole};
use space_foosball::rules::ContactWith;
use space_foosball::Table;
use std::f64::consts::FRAC_PI_2;
use virtual_physics::geometry::{Shape, V3};

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

#[test]
fn men_stand_where_the_table_kinematics_put_them() {
    let table = Table::standard();
    let mut a = Arena::new(&table).unwrap();
    let mut targets = vec![RodTarget::default(); table.rods.len()];
    targets[0] = RodTarget {
        slide_m: 0.05,
        angle_rad: 0.3,
    };
    settle(&mut a, &targets, 200);
    assert_eq!(a.rod_poses()[0], targets[0]);
    let w = a.world();
    let b = &w.bodies;
    // The keeper's rounded sole: its lowest point along the leg is the table's foot.
    let sole = (0..b.len())
        .find(|&i| a.roles()[i] == BodyRole::Man(0) && matches!(b.shape[i], Shape::Capsule { .. }))
        .unwrap();
    let Shape::Capsule { radius, .. } = b.shape[sole] else {
        unreachable!()
    };
    // The capsule lies along the rod (table y) and the leg points along −(R e_z) of the
    // man frame: at angle θ that is (−sin θ, 0, −cos θ)… the foot direction.
    let down = V3::new(-(0.3f64).sin(), 0.0, -(0.3f64).cos());
    let p = b.pos[sole] + down * radius;
    let (fx, fz) = table.foot_xz(0, 0.3);
    assert!(
        (p.x - fx).abs() < 1e-9 && (p.z - fz).abs() < 1e-9,
        "{p:?} vs {fx} {fz}"
    );
    assert!((p.y - 0.05).abs() < 1e-9);
    assert!(
        (b.rot[sole].column(2) - V3::y()).norm() < 1e-9,
        "capsule along the rod"
    );
}

#[test]
fn rods_stop_softly_at_the_ends_of_their_travel() {
    let table = Table::standard();
    let mut a = Arena::new(&table).unwrap();
    let half = table.rods[3].half_travel_m();
    let mut targets = vec![RodTarget::default(); table.rods.len()];
    targets[3].slide_m = 0.5; // far beyond the stop
    a.set_rod_targets(&targets);
    let mut last = 0.0;
    let mut speeds = Vec::new();
    for _ in 0..200 {
        a.step();
        let s = a.rod_poses()[3].slide_m;
        assert!(s <= half, "{s} beyond {half}");
        speeds.push((s - last) / 1e-3);
        last = s;
    }
    assert!((last - half).abs() < 1e-6, "{last}");
    let max = ArenaSettings::default().max_slide_speed_m_per_s;
    // Full speed across the travel, then slowing in the bumper before the stop.
    assert!((speeds[2] - max).abs() < 1e-9, "{:?}", &speeds[..4]);
    let at_stop = speeds.iter().rposition(|v| *v > 0.1).unwrap();
    assert!(
        speeds[at_stop] < 0.5 * max,
        "{:?}",
        &speeds[at_stop - 3..=at_stop]
    );
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
    // Shots at 20 m/s (the cap) at every wall and corner stay inside the table.
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
        a.place_ball([0.0, y, r], [20.0 * dir[0], 20.0 * dir[1], 0.0]);
        for t in 0..400 {
            a.step();
            assert!(
                a.ball_in_bounds(0.002),
                "shot {dir:?} step {t}: {:?}",
                a.ball()
            );
            let (gap, with) = a.ball_clearance();
            assert!(gap > -0.008, "shot {dir:?} step {t}: {gap} into {with:?}");
        }
    }
}

/// A 20 m/s shot 3 mm inside the post: into the goal. With one 1 ms world step the
/// speculative contact with the post's corner bounced it back out (see
/// `ArenaSettings::world_steps`); the check that this test can fail.
fn post_shot(settings: ArenaSettings) -> f64 {
    let table = Table::standard();
    let r = table.ball.radius_m();
    let mut a = Arena::with_settings(&table, settings).unwrap();
    settle(&mut a, &lifted(&table), 100);
    let y = -(0.5 * table.goal.width_m - r - 0.003);
    a.place_ball([0.45, y, r], [20.0, 0.0, 0.0]);
    let mut deepest = f64::NEG_INFINITY;
    for _ in 0..30 {
        a.step();
        deepest = deepest.max(a.ball().position[0]);
    }
    deepest
}

#[test]
fn a_fast_ball_enters_the_goal_beside_the_post() {
    let table = Table::standard();
    let line = 0.5 * table.field.length_m + table.ball.radius_m();
    let x = post_shot(ArenaSettings::default());
    assert!(x > line, "fully over the line: {x} vs {line}");
    let coarse = ArenaSettings {
        world_steps: 1,
        substeps: 2,
        ..ArenaSettings::default()
    };
    let x = post_shot(coarse);
    assert!(x < line, "one 1 ms world step bounces it off the post: {x}");
}

#[test]
fn a_spun_rod_kicks_the_ball_with_the_speed_of_its_foot() {
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
    for k in 0..120 {
        targets[rod].angle_rad = 1.2 - spin * 1e-3 * (k + 1) as f64;
        a.set_rod_targets(&targets);
        let s = a.step();
        if let Some(c) = s
            .contacts
            .iter()
            .find(|c| c.with == (ContactWith::Man { rod }))
        {
            kick.get_or_insert(c.normal_speed_m_per_s);
        }
    }
    let foot = table.character_of(rod).foot_reach_m * spin;
    let kick = kick.expect("the foot hits the ball");
    assert!(
        kick > 0.7 * foot && kick < 1.05 * foot,
        "kick {kick} vs foot {foot}"
    );
    let v = a.ball().velocity;
    // Forward (+x), faster than the foot (restitution), not flying off sideways.
    assert!(v[0] > foot && v[0] < 2.0 * foot, "{v:?} foot {foot}");
    assert!(v[1].abs() < 0.2 * v[0], "{v:?}");
}

#[test]
fn bad_settings_are_errors() {
    let table = Table::standard();
    for s in [
        ArenaSettings {
            world_steps: 0,
            ..ArenaSettings::default()
        },
        ArenaSettings {
            field_restitution: 1.5,
            ..ArenaSettings::default()
        },
        ArenaSettings {
            max_ball_speed_m_per_s: f64::NAN,
            ..ArenaSettings::default()
        },
    ] {
        let e = Arena::with_settings(&table, s).err().expect("rejected");
        assert!(e.to_string().contains("must be"), "{e}");
    }
}
