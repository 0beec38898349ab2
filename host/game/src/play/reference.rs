//! The reference match: one seed, the Home rods on a fixed script, the computer as
//! Away, played to a few goals. Its goals (to the millisecond) and the ball's final
//! state (to the bit) are what every build that claims cross-target determinism must
//! agree on: a desktop build with the `enhanced-determinism` feature and the browser's
//! wasm build (which always has it) play it alike. The determinism of replays, carried
//! from one machine to another.
//!
//! The script uses no transcendental function: a triangle-wave slide per rod and a
//! periodic kick (wind up, strike, return), piecewise linear in time.

use super::{Match, MatchConfig, MatchError};
use crate::input::paddles::{InputHealth, RodInputs, RodState};
use crate::rules::{Event, RulesConfig};
use crate::side::Side;
use crate::table::Table;
use serde::{Deserialize, Serialize};

/// The seed of the reference match.
pub const REFERENCE_SEED: u64 = 7;
/// Goals that end the reference match.
pub const REFERENCE_GOALS: u32 = 2;
/// Longest reference match, ms of match time: one that has not ended by then ends
/// there (its outcome then has fewer goals, and is compared all the same).
pub const REFERENCE_MAX_MS: u64 = 120_000;

/// Period of a rod's slide, ms (the rod's index adds [`SLIDE_PERIOD_STEP_MS`]).
const SLIDE_PERIOD_MS: u64 = 1_700;
const SLIDE_PERIOD_STEP_MS: u64 = 230;
/// Period of a rod's kick, ms; each rod's kick is offset by a quarter of a period per
/// rod index.
const KICK_PERIOD_MS: u64 = 1_100;
/// The kick: wind up to `−WIND_UP_RAD` over `WIND_UP_MS`, strike to `+STRIKE_RAD` over
/// `STRIKE_MS`, back to upright over `RETURN_MS`, then hang.
const WIND_UP_MS: u64 = 150;
const STRIKE_MS: u64 = 40;
const RETURN_MS: u64 = 200;
const WIND_UP_RAD: f64 = 0.9;
const STRIKE_RAD: f64 = 1.2;

/// A goal of the reference match.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReferenceGoal {
    /// Match time, ms.
    pub t_ms: u64,
    /// The team that scored.
    pub side: Side,
}

/// What the reference match did.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReferenceOutcome {
    /// The seed it was played with.
    pub seed: u64,
    /// Its goals, in order.
    pub goals: Vec<ReferenceGoal>,
    /// The final score, `[home, away]`.
    pub score: [u32; 2],
    /// Match time at the end, ms.
    pub time_ms: u64,
    /// The ball's final position (world frame, m) as the hexadecimal bits of each `f64`
    /// (bits, so that a comparison is exact and survives JSON in a browser).
    pub ball_position_bits: [String; 3],
    /// The ball's final velocity (world frame, m/s), as bits.
    pub ball_velocity_bits: [String; 3],
}

/// A triangle wave in `[−1, 1]` of period `period_ms` at `t_ms`, and its slope per ms.
fn triangle(t_ms: u64, period_ms: u64) -> (f64, f64) {
    let phase = (t_ms % period_ms) as f64 / period_ms as f64;
    let slope = 4.0 / period_ms as f64;
    if phase < 0.5 {
        (4.0 * phase - 1.0, slope)
    } else {
        (3.0 - 4.0 * phase, -slope)
    }
}

/// The kick's angle (rad) and angular velocity (rad/ms) `t` ms into a kick period.
fn kick(t: u64) -> (f64, f64) {
    let lerp = |a: f64, b: f64, t: u64, span: u64| {
        (a + (b - a) * t as f64 / span as f64, (b - a) / span as f64)
    };
    if t < WIND_UP_MS {
        lerp(0.0, -WIND_UP_RAD, t, WIND_UP_MS)
    } else if t < WIND_UP_MS + STRIKE_MS {
        lerp(-WIND_UP_RAD, STRIKE_RAD, t - WIND_UP_MS, STRIKE_MS)
    } else if t < WIND_UP_MS + STRIKE_MS + RETURN_MS {
        lerp(STRIKE_RAD, 0.0, t - WIND_UP_MS - STRIKE_MS, RETURN_MS)
    } else {
        (0.0, 0.0)
    }
}

/// The scripted input at match time `t_ms`: every rod of `table` slides on its
/// triangle wave over its whole travel and kicks once a period (the Away rods' input
/// is ignored by a match where the computer plays them).
pub fn scripted_inputs(table: &Table, t_ms: u64) -> RodInputs {
    let rods = table
        .rods
        .iter()
        .enumerate()
        .map(|(i, rod)| {
            let i = i as u64;
            let (s, ds) = triangle(t_ms, SLIDE_PERIOD_MS + i * SLIDE_PERIOD_STEP_MS);
            let offset = i * KICK_PERIOD_MS / 4;
            let (a, da) = kick((t_ms + offset) % KICK_PERIOD_MS);
            let half = rod.half_travel_m();
            RodState {
                slide_m: s * half,
                angle_rad: a,
                slide_velocity_m_per_s: ds * half * 1e3,
                angular_velocity_rad_per_s: da * 1e3,
                present: true,
            }
        })
        .collect();
    RodInputs {
        rods,
        health: InputHealth::Live,
        time_ms: t_ms,
        lost_reports: 0,
    }
}

/// The hexadecimal bits of each component.
fn bits(v: [f64; 3]) -> [String; 3] {
    v.map(|x| format!("{:016x}", x.to_bits()))
}

/// Plays the reference match on `table` with `seed` to `goals` goals (or until
/// [`REFERENCE_MAX_MS`]): Home on [`scripted_inputs`], Away the computer.
pub fn play_reference(
    table: &Table,
    seed: u64,
    goals: u32,
) -> Result<ReferenceOutcome, MatchError> {
    let mut config = MatchConfig::player_vs_computer(table.clone(), seed);
    config.rules = RulesConfig {
        goals_to_win: goals,
        ..RulesConfig::default()
    };
    config.record_inputs = false;
    let mut m = Match::new(config)?;
    let mut scored = Vec::new();
    while !m.is_over() && m.time_ms() < REFERENCE_MAX_MS {
        let inputs = scripted_inputs(table, m.time_ms());
        for e in m.step(&inputs) {
            if let Event::Goal { side, .. } = e.event {
                scored.push(ReferenceGoal { t_ms: e.t_ms, side });
            }
        }
    }
    let ball = m.arena().ball();
    Ok(ReferenceOutcome {
        seed,
        goals: scored,
        score: m.score(),
        time_ms: m.time_ms(),
        ball_position_bits: bits(ball.position),
        ball_velocity_bits: bits(ball.velocity),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_script_stays_within_the_travel_and_its_velocities_are_its_slopes() {
        let table = Table::standard();
        for t in 0..5_000 {
            let a = scripted_inputs(&table, t);
            let b = scripted_inputs(&table, t + 1);
            for (i, rod) in table.rods.iter().enumerate() {
                let half = rod.half_travel_m();
                assert!(a.rods[i].slide_m.abs() <= half + 1e-12, "rod {i} t {t}");
                assert!(a.rods[i].angle_rad.abs() <= STRIKE_RAD + 1e-12);
                // Within a linear piece the stated velocity is the change over 1 ms.
                let ds = (b.rods[i].slide_m - a.rods[i].slide_m) * 1e3;
                let da = (b.rods[i].angle_rad - a.rods[i].angle_rad) * 1e3;
                let fits = |stated: f64, seen: f64| (stated - seen).abs() < 1e-6;
                let corner = !fits(a.rods[i].slide_velocity_m_per_s, ds)
                    || !fits(a.rods[i].angular_velocity_rad_per_s, da);
                if corner {
                    // Only where a piece ends: the next ms has another slope.
                    let c = scripted_inputs(&table, t + 2);
                    let ds2 = (c.rods[i].slide_m - b.rods[i].slide_m) * 1e3;
                    let da2 = (c.rods[i].angle_rad - b.rods[i].angle_rad) * 1e3;
                    assert!(
                        fits(b.rods[i].slide_velocity_m_per_s, ds2)
                            || fits(b.rods[i].angular_velocity_rad_per_s, da2),
                        "rod {i} t {t}: velocities are not the script's slopes"
                    );
                }
            }
        }
    }

    #[test]
    fn the_bits_are_the_values() {
        let b = bits([1.0, -0.5, 0.0]);
        assert_eq!(b[0], "3ff0000000000000");
        assert_eq!(b[1], "bfe0000000000000");
        assert_eq!(b[2], "0000000000000000");
    }
}
