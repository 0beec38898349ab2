//! Kicks, against physics: the hand's servo drives the rod, the ball leaves by the foot's
//! impact alone. A kicked ball's speed grows with the rod's spin, and never exceeds what
//! the hand's torque limit can give: `(1 + e) · reach · ω_max`, with `ω_max = √(2 τ Δθ / I)`
//! the fastest spin the hand's torque `τ` reaches over the wind-up `Δθ` on the rod's
//! inertia `I` (and `e` the table's restitution).

use space_foosball::ai::RodTarget;
use space_foosball::arena::{Arena, ArenaSettings};
use space_foosball::rules::ContactWith;
use space_foosball::Table;
use std::f64::consts::{FRAC_PI_2, PI};

/// Home attack: x = 0.225, a man at y = 0; Home shoots towards +x with negative spin.
const ROD: usize = 5;

fn lifted(table: &Table) -> Vec<RodTarget> {
    vec![
        RodTarget {
            slide_m: 0.0,
            angle_rad: FRAC_PI_2,
        };
        table.rods.len()
    ]
}

/// Drives [`ROD`] through `motion(k)` (slide, angle) for `steps` ms; returns the ball's
/// velocity when it leaves the man's last contact (or at the end).
fn shoot(
    a: &mut Arena,
    targets: &mut [RodTarget],
    steps: usize,
    motion: impl Fn(usize) -> (f64, f64),
) -> [f64; 3] {
    let mut last_kick = None;
    for k in 0..steps {
        let (s, th) = motion(k);
        targets[ROD] = RodTarget {
            slide_m: s,
            angle_rad: th,
        };
        a.set_rod_targets(targets);
        let step = a.step();
        if step
            .contacts
            .iter()
            .any(|c| c.with == (ContactWith::Man { rod: ROD }))
        {
            last_kick = Some(k);
        }
        if last_kick.is_some_and(|l| k > l + 20) {
            break;
        }
    }
    a.ball().velocity
}

fn speed(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The ball at rest in front of the man, the foot wound back by `wind_up` rad, then the
/// hand's target spins forward at `spin` rad/s: the ball's speed after the kick.
fn kick(table: &Table, settings: ArenaSettings, spin: f64, wind_up: f64) -> f64 {
    let r = table.ball.radius_m();
    let mut a = Arena::with_settings(table, settings).unwrap();
    let mut targets = lifted(table);
    targets[ROD].angle_rad = wind_up;
    a.set_rod_targets(&targets);
    for _ in 0..300 {
        a.step();
    }
    a.place_ball([table.rods[ROD].x_m + 0.02, 0.0, r], [0.0; 3]);
    let v = shoot(&mut a, &mut targets, 600, |k| {
        (0.0, (wind_up - spin * 1e-3 * (k + 1) as f64).max(-PI))
    });
    speed(v)
}

#[test]
fn a_kicked_balls_speed_grows_with_spin_up_to_the_hands_torque() {
    let table = Table::standard();
    let settings = ArenaSettings::default();
    let wind_up = 1.2;
    let spins = [10.0, 20.0, 40.0, 80.0];
    let speeds: Vec<f64> = spins
        .iter()
        .map(|&w| kick(&table, settings, w, wind_up))
        .collect();
    for w in speeds.windows(2) {
        assert!(
            w[1] > w[0],
            "faster spin, faster ball: {speeds:?} at {spins:?}"
        );
    }
    // The hand's torque bounds the spin the rod reaches over the wind-up (the foot meets
    // the ball about at the bottom of its swing), and so the kick.
    let (_, inertia) = space_foosball::arena::rods::rod_mass_and_axial_inertia(&table, ROD);
    let reach = table.character_of(ROD).foot_reach_m;
    let e = table.ball.restitution;
    for torque in [settings.hand_torque_n_m, 0.1 * settings.hand_torque_n_m] {
        let w_max = (2.0 * torque * (wind_up + 0.3) / inertia).sqrt();
        let fastest = kick(
            &table,
            ArenaSettings {
                hand_torque_n_m: torque,
                ..settings
            },
            1000.0,
            wind_up,
        );
        assert!(
            fastest <= (1.0 + e) * reach * w_max,
            "{fastest} m/s with {torque} N·m: at most {} m/s",
            (1.0 + e) * reach * w_max
        );
    }
}
