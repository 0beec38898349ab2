//! The hard cases at the engine's defaults (`virtual_physics::measure::hard`, `vphys hard`):
//! each scene states only its step, gravity and effects, and each figure must hold its
//! bound. No test here sets a solver or integrator setting.
//!
//! Every case runs at full length in the default run (the longest: 100 dominoes, 1500
//! steps of 100 boxes; and the 500 kg cube on 385 boxes, 180 steps).

use virtual_physics::measure::hard::{self, HardCase};

/// Runs the table's cases and the variants whose names start with `kind`, prints each
/// figure, and fails naming every figure out of its bound.
fn holds(kind: &str) {
    let cases: Vec<HardCase> = hard::cases()
        .into_iter()
        .chain(hard::variants())
        .filter(|c| c.name.starts_with(kind))
        .collect();
    assert!(!cases.is_empty(), "no hard case named {kind}…");
    let mut failures = Vec::new();
    for case in &cases {
        let outcome = hard::run(case).unwrap_or_else(|e| panic!("{}: {e}", case.name));
        for f in &outcome.figures {
            println!(
                "{}: {} = {:.3e} {} (bound {:.3e})",
                outcome.name, f.what, f.value, f.unit, f.bound
            );
            if !f.holds() {
                failures.push(format!(
                    "{}: {} {:e} > {:e}",
                    outcome.name, f.what, f.value, f.bound
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A 35 mm ball at 30 to 120 m/s in closed boxes of 5 mm walls, at 1/60 s: every bounce
/// found within its step, so the ball follows the exact path (each axis reflected with the
/// restitution at its walls) to 1 µm, never leaves the box and never gains energy.
#[test]
fn a_fast_ball_in_a_closed_box_follows_the_exact_path_bounce_by_bounce() {
    holds("ball-in-box");
}

/// Touching spheres with restitution 1 pass the impulse along: the last one leaves at the
/// struck speed and the others stay (3, 5 and 8 spheres).
#[test]
fn a_newtons_cradle_passes_the_impulse_along_the_row() {
    holds("newtons-cradle");
}

/// Rows of dominoes (1 m and 48 mm tall) fall to the last one, and every lying domino rests
/// on the ground within 5 mm of its half-thickness.
#[test]
fn dominoes_fall_to_the_last_and_lie_at_their_half_thickness() {
    holds("dominoes");
}

/// A 500 kg cube dropped 2 m onto a 10-layer pyramid of 1 kg cubes (and 100 kg onto 6
/// layers): no contact deeper than 5 cm, and everything slower than 1 m/s 3 s later.
#[test]
fn a_heavy_cube_dropped_on_a_pyramid_of_light_ones_comes_to_rest_on_it() {
    holds("heavy-on-pyramid");
}

/// An arm of four revolute links (0.3 m, 1 kg capsules) dropped across 0.2 m stairs, and
/// one of three: no link ends a step more than 2 mm inside a step of the stairs.
#[test]
fn a_falling_arm_stops_on_the_stairs_within_two_millimetres() {
    holds("arm-on-stairs");
}

/// Stacks of unit cubes of 1 kg and 1000 kg, heavy on light, light between heavy and
/// alternating, stand 10 s: no contact deeper than 5 mm, no cube moves 1 cm.
#[test]
fn stacks_of_one_to_a_thousand_masses_stand() {
    holds("stack-");
}
