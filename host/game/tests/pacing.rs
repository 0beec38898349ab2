//! Pacing of computer-against-computer matches: the ball keeps moving.
//!
//! Twenty matches to five goals (seeds 0–19, standard table): the median time between
//! goals (from the kickoff or the previous goal, ms of match time) must be at most
//! [`MAX_MEDIAN_GOAL_GAP_MS`], and the dead-ball and out-of-play re-serves at most
//! [`MAX_RESERVES_PER_MATCH`] per match on average. Every re-serve is printed with where
//! the ball was and why (`--nocapture`).
//!
//! Twenty full matches take about 5 minutes in release on two loaded cores, too long
//! for every run: the test plays them with `SPACE_FOOSBALL_FULL_MATCHES` set (as the
//! full run of `computer_matches.rs` does) and otherwise says how to run it and passes.
//!
//! ```sh
//! SPACE_FOOSBALL_FULL_MATCHES=1 cargo test -p space-foosball --release --test pacing -- --nocapture
//! ```
//!
//! Measured with that command on the standard table: median goal gap 8.3 s and 1.10
//! re-serves per match (10 balls out of every man's reach, 12 stuck in reach) with its
//! 240 mm corner ramps; 9.9 s and 3.55 re-serves per match (50 out of reach, 21 stuck)
//! with the 50 mm ramps before.

use space_foosball::play::{idle_inputs, Match, MatchConfig};
use space_foosball::rules::{Event, Phase, RulesConfig, ServeReason};
use space_foosball::Table;

/// The longest median time between goals, ms: a goal every 45 s of play at most.
const MAX_MEDIAN_GOAL_GAP_MS: u64 = 45_000;
/// Most re-serves (dead or out-of-play balls) per match on average.
const MAX_RESERVES_PER_MATCH: f64 = 3.0;
/// A match that does not end within this is a failure, ms.
const MAX_MATCH_MS: u64 = 1_200_000;

/// Why a ball was re-served, as seen from outside the rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Why {
    /// Slow and out of every man's reach.
    OutOfReach,
    /// Slow in one place (reachable).
    Stuck,
    /// Moving but at one rod too long.
    Possession,
    /// Left the table.
    OutOfPlay,
}

#[derive(Debug)]
struct Reserve {
    t_ms: u64,
    why: Why,
    at: [f64; 3],
    speed: f64,
    /// The last man to touch the ball before: `(ms before the re-serve, rod)`.
    last_kick: Option<(u64, usize)>,
    /// The ball's velocity when it last entered the place where it died, m/s.
    entered_at: Option<[f64; 3]>,
}

#[derive(Debug)]
struct Played {
    seed: u64,
    goal_gaps_ms: Vec<u64>,
    reserves: Vec<Reserve>,
    time_ms: u64,
}

fn play(table: &Table, seed: u64) -> Played {
    let mut config = MatchConfig::computer_vs_computer(table.clone(), seed);
    config.record_inputs = false;
    config.rules = RulesConfig {
        goals_to_win: 5,
        ..RulesConfig::default()
    };
    let rules = config.rules;
    let mut m = Match::new(config).unwrap();
    let inputs = idle_inputs(table);
    let mut last_goal_ms = 0;
    let mut goal_gaps_ms = Vec::new();
    let mut reserves = Vec::new();
    let mut last_kick: Option<(u64, usize)> = None;
    let mut entered: Option<[f64; 3]> = None;
    let mut reachable_before = true;
    while !m.is_over() {
        assert!(m.time_ms() < MAX_MATCH_MS, "seed {seed}: no winner");
        let before = m.arena().ball();
        let events = m.step(&inputs);
        for e in &events {
            match e.event {
                Event::Goal { .. } => {
                    goal_gaps_ms.push(e.t_ms - last_goal_ms);
                    last_goal_ms = e.t_ms;
                }
                Event::Kick { rod, .. } => last_kick = Some((e.t_ms, rod)),
                _ => {}
            }
        }
        let now = m.arena().ball();
        let reachable = table.any_rod_can_reach(now.position[0], now.position[1]);
        if reachable_before && !reachable {
            entered = Some(now.velocity);
        }
        reachable_before = reachable;
        if let Phase::AwaitingServe { reason, .. } = m.phase() {
            let just_now = matches!(reason, ServeReason::DeadBall | ServeReason::OutOfPlay)
                && reserves
                    .last()
                    .is_none_or(|r: &Reserve| r.t_ms + rules.serve_pause_ms < m.time_ms());
            if just_now {
                let [x, y, _] = before.position;
                let speed = before.speed();
                let why = if reason == ServeReason::OutOfPlay {
                    Why::OutOfPlay
                } else if speed >= rules.slow_speed_m_per_s {
                    Why::Possession
                } else if !table.any_rod_can_reach(x, y) {
                    Why::OutOfReach
                } else {
                    Why::Stuck
                };
                reserves.push(Reserve {
                    t_ms: m.time_ms(),
                    why,
                    at: before.position,
                    speed,
                    last_kick: last_kick.map(|(t, rod)| (m.time_ms() - t, rod)),
                    entered_at: (why == Why::OutOfReach).then_some(entered).flatten(),
                });
            }
        }
    }
    Played {
        seed,
        goal_gaps_ms,
        reserves,
        time_ms: m.time_ms(),
    }
}

#[test]
fn twenty_matches_to_five_goals_keep_the_ball_moving() {
    if std::env::var_os("SPACE_FOOSBALL_FULL_MATCHES").is_none() {
        eprintln!(
            "pacing: skipped (20 matches to 5 goals); run with SPACE_FOOSBALL_FULL_MATCHES=1 \
             cargo test -p space-foosball --release --test pacing -- --nocapture"
        );
        return;
    }
    let table = Table::standard();
    let seeds: Vec<u64> = (0..20).collect();
    // Two threads: CI has two cores.
    let (a, b) = seeds.split_at(seeds.len() / 2);
    let played: Vec<Played> = std::thread::scope(|s| {
        let table = &table;
        let run = move |seeds: &[u64]| {
            seeds
                .iter()
                .map(|&seed| play(table, seed))
                .collect::<Vec<_>>()
        };
        let ha = s.spawn(move || run(a));
        let hb = s.spawn(move || run(b));
        let mut v = ha.join().unwrap();
        v.extend(hb.join().unwrap());
        v
    });
    let mut gaps: Vec<u64> = Vec::new();
    let mut reserves = 0usize;
    for p in &played {
        eprintln!(
            "seed {}: {} s, goal gaps {:?} s, {} re-serves",
            p.seed,
            p.time_ms / 1000,
            p.goal_gaps_ms.iter().map(|g| g / 1000).collect::<Vec<_>>(),
            p.reserves.len()
        );
        for r in &p.reserves {
            eprintln!(
                "    t {:7} ms {:?} at ({:+.3}, {:+.3}, {:.3}) m, {:.3} m/s, last kick {:?}, \
                 entered at {:?} m/s",
                r.t_ms, r.why, r.at[0], r.at[1], r.at[2], r.speed, r.last_kick, r.entered_at
            );
        }
        gaps.extend(&p.goal_gaps_ms);
        reserves += p.reserves.len();
    }
    gaps.sort_unstable();
    let median_ms = gaps[gaps.len() / 2];
    let per_match = reserves as f64 / played.len() as f64;
    eprintln!(
        "{} matches: median goal gap {:.1} s, {per_match:.2} re-serves per match",
        played.len(),
        median_ms as f64 * 1e-3
    );
    assert!(
        median_ms <= MAX_MEDIAN_GOAL_GAP_MS,
        "median goal gap {median_ms} ms"
    );
    assert!(
        per_match <= MAX_RESERVES_PER_MATCH,
        "{per_match:.2} re-serves per match"
    );
}
