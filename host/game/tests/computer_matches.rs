//! The computer against itself: 20 matches at different seeds, every step checked.
//!
//! Each match must end with a winner within a match-time limit; at every 1 ms step the
//! ball is finite, inside the table (field or goal box), not inside any wall, man, rod,
//! field or cover by more than [`MAX_OVERLAP_M`] (the engine's soft contacts allow a
//! little), and its path over the step does not cross a wall; while the ball is in
//! play it is never slow in one place, or slow and out of every man's reach, for longer
//! than the rules allow (checked independently of the rules' own bookkeeping).
//!
//! The full set — 20 matches to 5 goals on the standard table (seeds 0–19, in tests of 5
//! seeds that run in parallel) and 10 on the paper table — runs in the release profile
//! (`scripts/test-all` runs it):
//!
//! ```sh
//! SPACE_FOOSBALL_FULL_MATCHES=1 cargo test -p space-foosball --release --test computer_matches
//! ```
//!
//! Without the variable (`cargo test`, dev profile) a short set: the first seed of each
//! group of five and one paper match, to 1 goal (a match to 1 goal lasts 10–90 s of match
//! time) — the full set plays each of these matches from the same start, so the short set
//! only keeps a quick check in the everyday test command.

use space_foosball::arena::BodyRole;
use space_foosball::play::{idle_inputs, Match, MatchConfig};
use space_foosball::rules::{Phase, RulesConfig};
use space_foosball::Table;

/// Largest overlap of the ball with any solid at the end of a step, m. The rods are
/// driven by the hand's force- and torque-limited servos and stop on the ball, so a
/// squeezed ball (a foot pressing it into the cloth, a wall or another man) overlaps only
/// by the soft contact's give under the hand's force; a pass through a man or a wall
/// needs far more (the centre crossing the solid).
const MAX_OVERLAP_M: f64 = 0.002;
/// Longest match, ms of match time (a match that does not end is a failure).
const MAX_MATCH_MS: u64 = 1_200_000;

fn full() -> bool {
    std::env::var_os("SPACE_FOOSBALL_FULL_MATCHES").is_some()
}

/// What one match did.
#[derive(Debug)]
#[allow(dead_code)] // printed with {:?}
struct Played {
    score: [u32; 2],
    time_ms: u64,
    deepest_overlap_m: f64,
    deepest_with: BodyRole,
    longest_still_ms: u64,
    longest_dead_ms: u64,
}

fn play(table: &Table, seed: u64, goals: u32) -> Played {
    let mut config = MatchConfig::computer_vs_computer(table.clone(), seed);
    config.rules = RulesConfig {
        goals_to_win: goals,
        ..RulesConfig::default()
    };
    let rules = config.rules;
    let mut m = Match::new(config).unwrap();
    let inputs = idle_inputs(table);
    let mut deepest = (f64::INFINITY, BodyRole::Field);
    let mut previous = m.arena().ball().position;
    // (since, where) the ball has been slow within the stuck radius of one place.
    let mut still: Option<(u64, [f64; 3])> = None;
    let mut dead_since: Option<u64> = None;
    let (mut longest_still_ms, mut longest_dead_ms) = (0, 0);
    while !m.is_over() {
        assert!(
            m.time_ms() < MAX_MATCH_MS,
            "seed {seed}: no winner after {MAX_MATCH_MS} ms"
        );
        let phase_before = m.phase();
        m.step(&inputs);
        let t = m.time_ms();
        let arena = m.arena();
        let ball = arena.ball();
        assert!(ball.is_finite(), "seed {seed} t {t}: {ball:?}");
        assert!(
            arena.ball_in_bounds(0.002),
            "seed {seed} t {t}: out of the table {ball:?}"
        );
        let (gap, with) = arena.ball_clearance();
        assert!(
            gap > -MAX_OVERLAP_M,
            "seed {seed} t {t}: ball {:.1} mm inside {with:?} at {:?}",
            -gap * 1e3,
            ball.position
        );
        if gap < deepest.0 {
            deepest = (gap, with);
        }
        // The path over the step must not pass through a wall (walls stand still, so
        // the straight segment is checked at 2 mm intervals).
        let p = ball.position;
        let travel = (0..3)
            .map(|k| (p[k] - previous[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let samples = (travel / 0.002).ceil() as usize;
        for s in 1..samples {
            let f = s as f64 / samples as f64;
            let q = [
                previous[0] + (p[0] - previous[0]) * f,
                previous[1] + (p[1] - previous[1]) * f,
                previous[2] + (p[2] - previous[2]) * f,
            ];
            let (g, w) = arena.clearance_at(q);
            if w == BodyRole::Wall {
                assert!(
                    g > -MAX_OVERLAP_M - 1e-9,
                    "seed {seed} t {t}: path through {w:?} at {q:?}"
                );
            }
        }
        previous = p;
        // Independent dead/stuck bookkeeping while the ball is in play (a serve or a
        // goal resets it).
        if phase_before == Phase::InPlay && m.phase() == Phase::InPlay {
            let slow = ball.speed() < rules.slow_speed_m_per_s;
            if slow {
                match still {
                    Some((since, at))
                        if ((p[0] - at[0]).powi(2) + (p[1] - at[1]).powi(2)).sqrt()
                            <= rules.stuck_radius_m =>
                    {
                        longest_still_ms = longest_still_ms.max(t - since);
                    }
                    _ => still = Some((t, p)),
                }
                if !table.any_rod_can_reach(p[0], p[1]) {
                    let since = *dead_since.get_or_insert(t);
                    longest_dead_ms = longest_dead_ms.max(t - since);
                } else {
                    dead_since = None;
                }
            } else {
                still = None;
                dead_since = None;
            }
        } else {
            still = None;
            dead_since = None;
        }
    }
    Played {
        score: m.score(),
        time_ms: m.time_ms(),
        deepest_overlap_m: -deepest.0,
        deepest_with: deepest.1,
        longest_still_ms,
        longest_dead_ms,
    }
}

fn check_seeds(table: &Table, seeds: std::ops::Range<u64>) {
    let goals = if full() { 5 } else { 1 };
    let rules = RulesConfig::default();
    let seeds: Vec<u64> = if full() {
        seeds.collect()
    } else {
        seeds.take(1).collect()
    };
    for seed in seeds {
        let p = play(table, seed, goals);
        eprintln!("{} seed {seed}: {p:?}", table.name);
        assert_eq!(
            p.score.iter().copied().max(),
            Some(goals),
            "seed {seed}: {p:?}"
        );
        assert!(p.score[0] != p.score[1]);
        // Within the rules' limits (+1 ms: the re-serve decision comes on the step the
        // limit is reached).
        assert!(
            p.longest_still_ms <= rules.stuck_ms + 1,
            "seed {seed}: {p:?}"
        );
        assert!(
            p.longest_dead_ms <= rules.dead_ball_ms + 1,
            "seed {seed}: {p:?}"
        );
    }
}

#[test]
fn seeds_0_to_4_finish_with_a_winner_and_no_tunnelling() {
    check_seeds(&Table::standard(), 0..5);
}

#[test]
fn seeds_5_to_9_finish_with_a_winner_and_no_tunnelling() {
    check_seeds(&Table::standard(), 5..10);
}

#[test]
fn seeds_10_to_14_finish_with_a_winner_and_no_tunnelling() {
    check_seeds(&Table::standard(), 10..15);
}

#[test]
fn seeds_15_to_19_finish_with_a_winner_and_no_tunnelling() {
    check_seeds(&Table::standard(), 15..20);
}

#[test]
fn paper_table_matches_finish_too() {
    // Short run: 1 seed; full run: 10.
    let n = if full() { 10 } else { 1 };
    check_seeds(&Table::paper(), 100..100 + n);
}
