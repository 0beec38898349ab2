//! Pins, against physics: a ball squeezed by a man at the hand's full force stays where it
//! is pinned for 2 s, overlapping nothing by more than [`MAX_OVERLAP_M`] at any step.
//!
//! Whether a pin holds is a question of friction alone. A ball held by two contacts (the
//! foot and the cloth, the foot and a wall) is a two-force body: at rest, the two contact
//! forces act along the chord between the contact points. On a sphere that chord makes
//! half the angle `α` between the two contact normals with each of them, so the pin holds
//! exactly when `tan(α / 2) ≤ μ` at both contacts, whatever the hand's force — and slips
//! (the ball squirts out) when the foot meets it further from the top than that. The tests
//! check both sides of that bound, the rod's angle against the geometry of the rounded
//! sole on the ball, and the servo pressing at the hand's limit while the target keeps
//! going.

mod pin;

use pin::{distance, lifted, pin_friction, Sole};
use space_foosball::ai::RodTarget;
use space_foosball::arena::{Arena, ArenaSettings};
use space_foosball::Table;

/// Largest overlap of the ball with any solid at any step of a pin, m.
const MAX_OVERLAP_M: f64 = 0.001;
/// How long a pin is held, ms.
const HOLD_MS: usize = 2000;
/// How fast the hand lowers a man onto the ball, rad/s (the foot at 0.1 m/s: a player
/// setting the pin, not kicking).
const LOWER_RAD_PER_S: f64 = 1.0;

/// Home attack (x = 0.225, a man at y = 0); Home's midfield and Away's midfield (x = ∓0.075,
/// a man at y = 0 on each); Home defence (x = −0.375, men at y = ±0.119).
const ATTACK: usize = 5;
const HOME_MIDFIELD: usize = 3;
const AWAY_MIDFIELD: usize = 4;
const DEFENCE: usize = 1;

/// What a pin did.
#[derive(Debug)]
struct Held {
    /// Deepest overlap of the ball with any solid over the whole run, m.
    deepest_m: f64,
    /// Farthest the ball moved from where it was pinned, over the hold, m.
    moved_m: f64,
    /// The ball's speed at the end, m/s.
    final_speed: f64,
    /// How far the ball ended from where it lay before the setup, m.
    displaced_m: f64,
}

/// Steps `a` with the targets `motion(k)` for `setup_ms` ms, takes the ball's position as
/// the pinned one, then holds the last targets for [`HOLD_MS`], every step checked;
/// `each` sees every step of the hold.
fn pin(
    a: &mut Arena,
    setup_ms: usize,
    mut motion: impl FnMut(usize) -> Vec<RodTarget>,
    mut each: impl FnMut(&Arena),
) -> Held {
    let mut deepest: f64 = 0.0;
    let mut track = |a: &Arena| {
        let (gap, _) = a.ball_clearance();
        deepest = deepest.max(-gap);
        assert!(a.ball().is_finite(), "{:?}", a.ball());
    };
    let start = a.ball().position;
    for k in 0..setup_ms {
        a.set_rod_targets(&motion(k));
        a.step();
        track(a);
    }
    let pinned = a.ball().position;
    let mut moved: f64 = 0.0;
    for _ in 0..HOLD_MS {
        a.step();
        track(a);
        moved = moved.max(distance(a.ball().position, pinned));
        each(a);
    }
    Held {
        deepest_m: deepest,
        moved_m: moved,
        final_speed: a.ball().speed(),
        displaced_m: distance(a.ball().position, start),
    }
}

/// The attack's middle man lowered onto a ball resting in front of the rod so that the foot
/// meets it `alpha` from its top; the hand's target goes on down past the ball.
fn lower_onto_resting_ball(table: &Table, alpha: f64, mut each: impl FnMut(&Arena)) -> Held {
    let r = table.ball.radius_m();
    let sole = Sole::of(table, ATTACK);
    let dx = sole.ball_offset_for(table, alpha);
    let mut a = Arena::new(table).unwrap();
    let mut targets = lifted(table);
    targets[ATTACK].angle_rad = -1.5;
    a.set_rod_targets(&targets);
    for _ in 0..300 {
        a.step();
    }
    a.place_ball([table.rods[ATTACK].x_m + dx, 0.0, r], [0.0; 3]);
    // Down at the hand's pace, to 0.5 rad past the touching angle, then held there.
    let stop = sole.touching_angle(dx, r - table.field.rod_height_m) + 0.5;
    let steps = ((stop + 1.5) / (LOWER_RAD_PER_S * 1e-3)).ceil() as usize;
    pin(
        &mut a,
        steps + 200,
        |k| {
            targets[ATTACK].angle_rad = (-1.5 + LOWER_RAD_PER_S * 1e-3 * k as f64).min(stop);
            targets.clone()
        },
        &mut each,
    )
}

#[test]
fn a_man_lowered_onto_a_resting_ball_pins_it_against_the_cloth() {
    let table = Table::standard();
    let mu = pin_friction(&table);
    let limit = 2.0 * mu.atan();
    let sole = Sole::of(&table, ATTACK);
    let torque = ArenaSettings::default().hand_torque_n_m;
    let x_rod = table.rods[ATTACK].x_m;
    let h = table.field.rod_height_m;
    // On the top, and either side of it within the friction bound.
    for alpha in [0.0, 0.6 * limit, -0.6 * limit] {
        let mut worst_angle_error: f64 = 0.0;
        let mut weakest_torque = f64::INFINITY;
        let held = lower_onto_resting_ball(&table, alpha, |a| {
            // The rod stops where the sole meets the ball as it now lies: within the angle
            // a millimetre of overlap along the contact normal makes.
            let b = a.ball().position;
            let th = a.rod_poses()[ATTACK].angle_rad;
            let (dx, dz) = (b[0] - x_rod, b[2] - h);
            let touch = sole.touching_angle(dx, dz);
            let (cx, cz) = sole.centre(touch);
            let normal = [(dx - cx) / sole.touch_m, (dz - cz) / sole.touch_m];
            // The sole's axis moves along (−cos θ, sin θ) · circle per radian.
            let along = (-touch.cos() * normal[0] + touch.sin() * normal[1]).abs();
            let tolerance = MAX_OVERLAP_M / (sole.circle_m * along);
            worst_angle_error = worst_angle_error.max((th - touch).abs() / tolerance);
            weakest_torque = weakest_torque.min(a.rod_drive_forces(ATTACK)[1]);
        });
        let what = format!("alpha {:.1}°: {held:?}", alpha.to_degrees());
        eprintln!("pin on the cloth, {what}");
        assert!(held.deepest_m <= MAX_OVERLAP_M, "{what}");
        assert!(held.moved_m <= MAX_OVERLAP_M, "no creep: {what}");
        assert!(held.final_speed < 1e-3, "{what}");
        assert!(
            worst_angle_error <= 1.0,
            "the rod stops on the ball: {worst_angle_error} of the tolerance, {what}"
        );
        // The servo presses at the hand's torque limit all along: the ball, not the
        // target, stops the rod.
        assert!(
            weakest_torque > 0.99 * torque,
            "{weakest_torque} N·m, {what}"
        );
    }
    // Beyond the bound the ball squirts out from under the foot, as friction says.
    let held = lower_onto_resting_ball(&table, 1.5 * limit, |_| {});
    assert!(
        held.displaced_m > 0.01,
        "a foot meeting the ball {:.0}° from its top cannot pin it (μ = {mu}): {held:?}",
        (1.5 * limit).to_degrees()
    );
}

#[test]
fn a_ball_pinned_against_the_side_wall_by_a_mans_foot_stays() {
    // On the standard table no man reaches the side walls (the dead-ball rule re-serves
    // balls there), so this table widens the Home defence's travel to 0.38 m: its outer
    // man's foot then reaches y = 0.318 m, past a ball resting against the wall at 0.3325.
    let mut table = Table::standard();
    table.rods[DEFENCE].travel_m = 0.38;
    table.validate().unwrap();
    let r = table.ball.radius_m();
    let wall_y = 0.5 * table.field.width_m;
    let mut a = Arena::new(&table).unwrap();
    let mut targets = lifted(&table);
    targets[DEFENCE].angle_rad = 0.0;
    a.set_rod_targets(&targets);
    for _ in 0..300 {
        a.step();
    }
    a.place_ball([table.rods[DEFENCE].x_m, wall_y - r, r], [0.0; 3]);
    let force = ArenaSettings::default().hand_force_n;
    let mut weakest = f64::INFINITY;
    // The hand pushes the rod towards the wall at 0.1 m/s and on, beyond its stop: the
    // foot's side presses the ball into the wall (opposite normals: it holds at any μ).
    let held = pin(
        &mut a,
        2500,
        |k| {
            targets[DEFENCE].slide_m = 1e-4 * k as f64;
            targets.clone()
        },
        |a| weakest = weakest.min(a.rod_drive_forces(DEFENCE)[0]),
    );
    assert!(held.deepest_m <= MAX_OVERLAP_M, "{held:?}");
    assert!(held.moved_m <= MAX_OVERLAP_M, "{held:?}");
    assert!(held.final_speed < 1e-3, "{held:?}");
    // Squeezed at the hand's full force (the target is beyond the ball).
    eprintln!("pin against the wall: {held:?}");
    assert!(weakest > 0.99 * force, "{weakest} N, {held:?}");
}

#[test]
fn a_ball_pinned_between_two_men_stays() {
    // The two midfields' middle men come down on a ball halfway between their rods, each
    // foot meeting it on its near side of the top (within the friction bound), each hand
    // pressing at its full torque.
    let table = Table::standard();
    let r = table.ball.radius_m();
    let x = 0.5 * (table.rods[HOME_MIDFIELD].x_m + table.rods[AWAY_MIDFIELD].x_m);
    let sole = Sole::of(&table, HOME_MIDFIELD);
    let half_gap = x - table.rods[HOME_MIDFIELD].x_m;
    let touch = sole.touching_angle(half_gap, r - table.field.rod_height_m);
    let (cx, cz) = sole.centre(touch);
    let alpha = (cx - half_gap).atan2(cz - (r - table.field.rod_height_m));
    assert!(
        (alpha.abs() * 0.5).tan() <= pin_friction(&table),
        "the table puts the ball within both feet's friction bound: α = {alpha}"
    );
    let mut a = Arena::new(&table).unwrap();
    let mut targets = lifted(&table);
    targets[HOME_MIDFIELD].angle_rad = -1.5;
    targets[AWAY_MIDFIELD].angle_rad = 1.5; // Away's foot in front of its rod: towards −x
    a.set_rod_targets(&targets);
    for _ in 0..300 {
        a.step();
    }
    a.place_ball([x, 0.0, r], [0.0; 3]);
    let stop = touch + 0.5;
    let steps = ((stop + 1.5) / (LOWER_RAD_PER_S * 1e-3)).ceil() as usize;
    let torque = ArenaSettings::default().hand_torque_n_m;
    let mut weakest = f64::INFINITY;
    let held = pin(
        &mut a,
        steps + 200,
        |k| {
            let th = (-1.5 + LOWER_RAD_PER_S * 1e-3 * k as f64).min(stop);
            targets[HOME_MIDFIELD].angle_rad = th;
            targets[AWAY_MIDFIELD].angle_rad = -th;
            targets.clone()
        },
        |a| {
            weakest = weakest
                .min(a.rod_drive_forces(HOME_MIDFIELD)[1])
                .min(-a.rod_drive_forces(AWAY_MIDFIELD)[1]);
        },
    );
    assert!(held.deepest_m <= MAX_OVERLAP_M, "{held:?}");
    assert!(held.moved_m <= MAX_OVERLAP_M, "{held:?}");
    assert!(held.final_speed < 1e-3, "{held:?}");
    eprintln!("pin between two men: {held:?}");
    assert!(weakest > 0.99 * torque, "{weakest} N·m, {held:?}");
}
