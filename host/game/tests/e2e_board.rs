//! End to end: the emulated board (lockstep, 1 ms per report) runs a scripted motion,
//! its reports go through calibration into a match whose rods are all played from the
//! board, and the physics and the rules decide what happens.
//!
//! Each scenario runs twice with the same seed: first with every rod lifted out of the
//! way (to learn where and when the served ball passes — the match is deterministic),
//! then with a script that plays the ball at that time and place. Both teams are
//! `Player`s, so no computer moves anything.

use board_link::Board;
use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::BoardInput;
use space_foosball::play::{KickHaptics, Match, MatchConfig, RodController};
use space_foosball::rules::{BallState, Event, RulesConfig, TimedEvent};
use space_foosball::{Side, Table};
use std::f64::consts::FRAC_PI_2;

/// Counting starts after the sensors' self-test; the script holds still until then.
const SETTLE_S: f64 = 1.0;
/// Time to lift the rods once counting runs.
const LIFT_S: f64 = 0.3;
/// The kickoff comes late enough for the rods to be lifted.
const SERVE_PAUSE_MS: u64 = 1500;
/// A serve that rolls past the attack rods but stops before the goalkeeper, m/s.
const SLOW_SERVE: f64 = 0.5;
/// Spin speed of a scripted kick, rad/s.
const KICK_SPIN: f64 = 30.0;

fn rules(first_serve: Side, serve_speed_m_per_s: f64) -> RulesConfig {
    RulesConfig {
        goals_to_win: 1,
        first_serve,
        serve_pause_ms: SERVE_PAUSE_MS,
        // Fast enough to roll past the rod (rolling resistance stops a 0.3 m/s serve
        // within about 0.1 m).
        serve_speed_m_per_s,
        ..RulesConfig::default()
    }
}

/// One rod's script: rest until counting runs, move to `pose` (table frame), then the
/// given extra segments (JSON).
struct RodScript {
    port: usize,
    /// Table-frame pose to move to after settling: slide m, angle rad.
    pose: [f64; 2],
    /// Further segments (JSON objects), paddle frame.
    more: Vec<String>,
}

fn script(table: &Table, rods: &[RodScript]) -> MotionScript {
    let tracks: Vec<String> = rods
        .iter()
        .map(|r| {
            let rod = table.rods.iter().find(|x| x.port == r.port).unwrap();
            // Paddle frame = table frame × handle sign.
            let s = rod.handle_sign();
            let mut segs = vec![
                format!(r#"{{"hold":{{"duration_s":{SETTLE_S}}}}}"#),
                format!(
                    r#"{{"move_to":{{"duration_s":{LIFT_S},"axial_m":{},"angle_rad":{}}}}}"#,
                    s * r.pose[0],
                    s * r.pose[1]
                ),
            ];
            segs.extend(r.more.iter().cloned());
            format!(r#"{{"rod":{},"segments":[{}]}}"#, r.port, segs.join(","))
        })
        .collect();
    MotionScript::from_json(&format!(r#"{{"rods":[{}]}}"#, tracks.join(","))).unwrap()
}

/// What a scripted run produced.
struct Run {
    events: Vec<TimedEvent>,
    balls: Vec<BallState>,
    m: Match,
    /// Haptic pulses the board received: `(paddle, strength)`.
    pulses: Vec<(usize, u8)>,
}

/// Runs a match with every rod played from the board following `motion`, for `ms`
/// steps or until it is over, sending the kicks' haptic pulses back to the board.
fn run(table: &Table, seed: u64, rules: RulesConfig, motion: MotionScript, ms: u64) -> Run {
    let board =
        InProcessBoard::with_motion(BoardConfig::default(), Box::new(motion), Pacing::Lockstep)
            .unwrap();
    let mut input = BoardInput::new(board, table, Calibration::default());
    let mut config = MatchConfig::computer_vs_computer(table.clone(), seed);
    config.rules = rules;
    config.controllers = [RodController::Player; 2];
    let mut haptics = KickHaptics::new(table, config.controllers);
    let mut m = Match::new(config).unwrap();
    let mut events = Vec::new();
    let mut balls = Vec::new();
    for _ in 0..ms {
        let inputs = input.poll(1);
        let step = m.step(&inputs);
        for report in haptics.reports(&step) {
            input.board_mut().send(&report).unwrap();
        }
        events.extend(step);
        balls.push(m.arena().ball());
        if m.is_over() {
            break;
        }
    }
    let pulses = input
        .board_mut()
        .emulated()
        .haptic_events()
        .iter()
        .filter(|h| h.duration_ms > 0)
        .map(|h| (h.paddle, h.strength))
        .collect();
    Run {
        events,
        balls,
        m,
        pulses,
    }
}

/// Every rod lifted (feet horizontal, pointing back), except those in `except`.
fn lifted(table: &Table, except: &[usize]) -> Vec<RodScript> {
    table
        .rods
        .iter()
        .enumerate()
        .filter(|(i, _)| !except.contains(i))
        .map(|(_, r)| RodScript {
            port: r.port,
            pose: [0.0, r.team.attack_dir() * FRAC_PI_2],
            more: vec![],
        })
        .collect()
}

/// When (step index) and where the ball first gets `ahead_m` in front of rod `rod`.
fn first_in_front(table: &Table, balls: &[BallState], rod: usize, ahead_m: f64) -> (usize, f64) {
    let r = &table.rods[rod];
    let d = r.team.attack_dir();
    balls
        .iter()
        .position(|b| (b.position[0] - r.x_m) * d >= ahead_m)
        .map(|i| (i, balls[i].position[1]))
        .expect("the served ball reaches the rod")
}

/// A kick by rod `rod` timed for the ball to be in front of it at step `hit`: lifted
/// back until then, the man nearest `y` lined up, then a spin forward through the
/// bottom of the swing to a follow-through.
fn kick(table: &Table, rod: usize, hit: usize, y: f64) -> RodScript {
    let r = &table.rods[rod];
    let d = r.team.attack_dir();
    let s = r.handle_sign();
    let slide = r.nearest_man(y, 0.0).slide_m;
    // The foot comes down from "lifted back" (d·π/2) through 0 at `hit`.
    let swing_s = FRAC_PI_2 / KICK_SPIN;
    let start_s = hit as f64 * 1e-3 - swing_s - SETTLE_S - LIFT_S;
    assert!(start_s > 0.05, "the kick starts after the lift");
    RodScript {
        port: r.port,
        pose: [slide, d * FRAC_PI_2],
        more: vec![
            format!(r#"{{"hold":{{"duration_s":{start_s}}}}}"#),
            format!(
                r#"{{"velocity":{{"duration_s":{},"angle_rad_per_s":{}}}}}"#,
                2.0 * swing_s,
                -d * s * KICK_SPIN
            ),
        ],
    }
}

fn goals(events: &[TimedEvent]) -> Vec<Side> {
    events
        .iter()
        .filter_map(|e| match e.event {
            Event::Goal { side, .. } => Some(side),
            _ => None,
        })
        .collect()
}

fn kicks_by(events: &[TimedEvent], rod: usize) -> Vec<(u64, f64)> {
    events
        .iter()
        .filter_map(|e| match e.event {
            Event::Kick { rod: r, speed } if r == rod => Some((e.t_ms, speed)),
            _ => None,
        })
        .collect()
}

#[test]
fn the_scripted_attack_spins_and_scores_a_goal_the_rules_count() {
    let table = Table::standard();
    let attack = 5; // Home attack, x = 0.225, port 5
                    // Pass 1: everything lifted; the ball is served towards the Away half (+x). The scenario
                    // needs a serve that does not score by itself and passes the attack inside the goal
                    // mouth's width (less a ball diameter, so that a straight kick clears the posts): the
                    // first such seed is used.
    let clear = 0.5 * table.goal.width_m - table.ball.diameter_m;
    let (seed, probe, hit, y) = (1..=20)
        .find_map(|seed| {
            let probe = run(
                &table,
                seed,
                rules(Side::Away, 1.0),
                script(&table, &lifted(&table, &[])),
                4000,
            );
            let (hit, y) = first_in_front(&table, &probe.balls, attack, 0.02);
            (y.abs() < clear && goals(&probe.events).is_empty()).then_some((seed, probe, hit, y))
        })
        .expect("a serve passes the attack within the goal mouth");
    assert!(
        goals(&probe.events).is_empty(),
        "the serve alone does not score"
    );
    assert!(probe.pulses.is_empty(), "no kick, no pulse");
    // Pass 2: the attack kicks the ball when it is in front of it.
    let mut rods = lifted(&table, &[attack]);
    rods.push(kick(&table, attack, hit, y));
    let Run {
        events, m, pulses, ..
    } = run(
        &table,
        seed,
        rules(Side::Away, 1.0),
        script(&table, &rods),
        6000,
    );
    let kicks = kicks_by(&events, attack);
    assert!(!kicks.is_empty(), "the attack kicked: {events:?}");
    // A real kick: about the foot's speed (reach · ω ≈ 2.9 m/s), more with the bounce.
    let hardest = kicks.iter().map(|k| k.1).fold(0.0, f64::max);
    assert!(hardest > 2.0, "kick speed {hardest}");
    assert_eq!(goals(&events), vec![Side::Home], "{events:?}");
    assert_eq!(m.score(), [1, 0]);
    assert!(m.is_over());
    let last = events.last().unwrap();
    assert_eq!(last.event, Event::MatchOver { score: [1, 0] });
    // The goal came after the kick.
    let goal_t = events
        .iter()
        .find(|e| matches!(e.event, Event::Goal { .. }))
        .unwrap()
        .t_ms;
    assert!(goal_t > kicks[0].0);
    // The kick was felt: the board pulsed the attack's paddle as hard as the kick feel maps
    // the hardest kick's speed.
    let port = table.rods[attack].port;
    let felt = board_link::haptics::KickFeel::DEFAULT
        .pulse(hardest as f32)
        .expect("a kick above the feel's threshold")
        .strength;
    assert!(
        pulses
            .iter()
            .any(|&(p, strength)| p == port && strength == felt),
        "{pulses:?}, expected strength {felt}"
    );
}

#[test]
fn the_goalkeeper_blocks_a_shot_that_would_score_without_him() {
    let table = Table::standard();
    let shooter = 2; // Away attack, x = −0.225, shoots towards −x
    let keeper = 0; // Home goalkeeper, x = −0.525
    let seed = 5;
    let probe = run(
        &table,
        seed,
        rules(Side::Home, SLOW_SERVE),
        script(&table, &lifted(&table, &[])),
        4000,
    );
    assert!(goals(&probe.events).is_empty());
    let (hit, y) = first_in_front(&table, &probe.balls, shooter, 0.02);
    // Without the keeper (lifted): the shot scores for Away.
    let mut rods = lifted(&table, &[shooter]);
    rods.push(kick(&table, shooter, hit, y));
    let open = run(
        &table,
        seed,
        rules(Side::Home, SLOW_SERVE),
        script(&table, &rods),
        6000,
    )
    .events;
    assert!(!kicks_by(&open, shooter).is_empty(), "{open:?}");
    assert_eq!(
        goals(&open),
        vec![Side::Away],
        "the open shot scores: {open:?}"
    );
    // With the keeper standing in the shot line, feet down: blocked.
    let mut rods = lifted(&table, &[shooter, keeper]);
    rods.push(kick(&table, shooter, hit, y));
    let keeper_slide = table.rods[keeper].nearest_man(y, 0.0).slide_m;
    rods.push(RodScript {
        port: table.rods[keeper].port,
        pose: [keeper_slide, 0.0],
        more: vec![],
    });
    let Run {
        events: blocked, m, ..
    } = run(
        &table,
        seed,
        rules(Side::Home, SLOW_SERVE),
        script(&table, &rods),
        6000,
    );
    let shot_t = kicks_by(&blocked, shooter)[0].0;
    let saves = kicks_by(&blocked, keeper);
    assert!(
        saves.iter().any(|&(t, speed)| t > shot_t && speed > 1.0),
        "the keeper stops the shot: {blocked:?}"
    );
    // The saved shot does not score; what the ball does after the save (it may end in the
    // other goal) is play, not part of this test.
    assert!(!goals(&blocked).contains(&Side::Away), "{blocked:?}");
    assert_eq!(m.score()[1], 0, "Away scored: {blocked:?}");
}
