//! The match rules, one rule per test.

use space_foosball::rules::{
    BallState, Contact, ContactWith, Event, Phase, Rules, RulesConfig, ServeReason,
};
use space_foosball::{Side, Table};

const R: f64 = 0.0175;

fn ball(x: f64, y: f64, vx: f64) -> BallState {
    BallState {
        position: [x, y, R],
        velocity: [vx, 0.0, 0.0],
    }
}

/// Steps `n` times with the same ball; returns all events.
fn run(rules: &mut Rules, b: BallState, n: u64) -> Vec<Event> {
    (0..n).flat_map(|_| rules.step(&b, &[]).events).collect()
}

/// A match past its kickoff.
fn in_play(config: RulesConfig) -> Rules {
    let mut rules = Rules::new(Table::standard(), config);
    let events = run(&mut rules, ball(0.0, 0.0, 0.0), config.serve_pause_ms);
    assert_eq!(
        events,
        [Event::Serve {
            to: config.first_serve,
            reason: ServeReason::Kickoff
        }]
    );
    assert_eq!(rules.phase(), Phase::InPlay);
    rules
}

#[test]
fn kickoff_serves_from_the_middle_towards_the_receiver() {
    let mut rules = Rules::new(Table::standard(), RulesConfig::default());
    for _ in 0..499 {
        let out = rules.step(&ball(0.0, 0.0, 0.0), &[]);
        assert!(out.events.is_empty() && out.serve.is_none());
    }
    let out = rules.step(&ball(0.0, 0.0, 0.0), &[]);
    let serve = out.serve.unwrap();
    assert_eq!(serve.to, Side::Home);
    assert_eq!(&serve.position[..2], &[0.0, 0.0]);
    assert!(serve.position[2] > R);
    assert!(serve.velocity[0] < 0.0, "rolls into the Home half (−x)");
    let away = Rules::new(Table::standard(), RulesConfig::default()).serve_spec(Side::Away);
    assert!(away.velocity[0] > 0.0);
}

#[test]
fn goal_counts_only_when_the_ball_has_fully_crossed_the_line_in_the_mouth() {
    let mut rules = in_play(RulesConfig::default());
    // Half over the Home goal line: no goal.
    assert!(run(&mut rules, ball(-0.6 - R + 1e-4, 0.0, -1.0), 1).is_empty());
    assert_eq!(rules.score(), [0, 0]);
    // Fully over: Away scores.
    let events = run(&mut rules, ball(-0.6 - R - 1e-4, 0.05, -1.0), 1);
    assert_eq!(
        events,
        [Event::Goal {
            side: Side::Away,
            score: [0, 1]
        }]
    );
    // After the pause, served to the side that conceded.
    let events = run(&mut rules, ball(-0.65, 0.0, 0.0), 1500);
    assert_eq!(
        events,
        [Event::Serve {
            to: Side::Home,
            reason: ServeReason::AfterGoal
        }]
    );
}

#[test]
fn beside_or_above_the_mouth_is_not_a_goal_but_out_of_play() {
    let config = RulesConfig::default();
    let mut rules = in_play(config);
    let mut b = ball(0.6 + R + 0.01, 0.2, 1.0); // beside the mouth (width 0.205)
    assert!(run(&mut rules, b, 1).is_empty());
    assert_eq!(rules.score(), [0, 0]);
    assert!(matches!(
        rules.phase(),
        Phase::AwaitingServe {
            reason: ServeReason::OutOfPlay,
            to: Side::Home,
            ..
        }
    ));
    let mut rules = in_play(config);
    b = ball(0.6 + R + 0.01, 0.0, 1.0);
    b.position[2] = 0.2; // over the crossbar
    run(&mut rules, b, 1);
    assert_eq!(rules.score(), [0, 0]);
    // NaN is out of play too, never a panic.
    let mut rules = in_play(config);
    run(&mut rules, ball(f64::NAN, 0.0, 0.0), 1);
    let events = run(&mut rules, ball(0.0, 0.0, 0.0), config.serve_pause_ms);
    assert_eq!(
        events,
        [Event::Serve {
            to: Side::Home,
            reason: ServeReason::OutOfPlay
        }]
    );
}

#[test]
fn a_slow_ball_out_of_reach_is_dead_after_the_limit() {
    let config = RulesConfig::default();
    let mut rules = in_play(config);
    // Along the side wall, where no man reaches.
    let wall = ball(0.0, 0.35 - R, 0.01);
    assert!(run(&mut rules, wall, config.dead_ball_ms).is_empty());
    assert_eq!(rules.phase(), Phase::InPlay);
    run(&mut rules, wall, 1);
    assert!(matches!(
        rules.phase(),
        Phase::AwaitingServe {
            reason: ServeReason::DeadBall,
            ..
        }
    ));
    // A fast ball there is not dead; a slow one in reach is not dead either.
    let mut rules = in_play(config);
    run(
        &mut rules,
        ball(0.0, 0.35 - R, 1.0),
        2 * config.dead_ball_ms,
    );
    assert_eq!(rules.phase(), Phase::InPlay);
    let mut rules = in_play(config);
    let mut x = 0.3;
    for _ in 0..2 * config.dead_ball_ms {
        // Creeping slowly in reach of the away defence: alive (and not stuck: it moves).
        x += 0.04e-3;
        rules.step(&ball(x, 0.0, 0.04), &[]);
    }
    assert_eq!(rules.phase(), Phase::InPlay);
}

#[test]
fn a_ball_stuck_in_one_place_is_served_again() {
    let config = RulesConfig::default();
    let mut rules = in_play(config);
    // In reach (under the home goalkeeper) but not moving: stuck after stuck_ms.
    let pinned = ball(-0.525, 0.0, 0.0);
    run(&mut rules, pinned, config.stuck_ms);
    assert_eq!(rules.phase(), Phase::InPlay);
    run(&mut rules, pinned, 1);
    assert!(matches!(
        rules.phase(),
        Phase::AwaitingServe {
            reason: ServeReason::DeadBall,
            ..
        }
    ));
}

#[test]
fn first_to_n_goals_wins_and_nothing_happens_after() {
    let config = RulesConfig {
        goals_to_win: 3,
        ..RulesConfig::default()
    };
    let mut rules = in_play(config);
    let mut all = Vec::new();
    for _ in 0..3 {
        all.extend(run(&mut rules, ball(0.7, 0.0, 1.0), 1)); // Home scores
        all.extend(run(&mut rules, ball(0.0, 0.0, 0.0), config.goal_pause_ms));
    }
    assert_eq!(rules.score(), [3, 0]);
    assert_eq!(rules.winner(), Some(Side::Home));
    assert_eq!(
        all.iter()
            .filter(|e| matches!(e, Event::Goal { .. }))
            .count(),
        3
    );
    let over = all
        .iter()
        .find(|e| matches!(e, Event::MatchOver { .. }))
        .unwrap();
    assert_eq!(
        serde_json::to_string(over).unwrap(),
        r#"{"event":"MatchOver","score":[3,0]}"#
    );
    // Serves after goals go to Away (the side that conceded).
    assert!(all
        .iter()
        .all(|e| !matches!(e, Event::Serve { to: Side::Home, .. })));
    assert!(run(&mut rules, ball(0.7, 0.0, 1.0), 100).is_empty());
    assert_eq!(rules.score(), [3, 0]);
}

#[test]
fn kicks_and_bounces_above_their_thresholds_become_events() {
    let mut rules = in_play(RulesConfig::default());
    let contacts = [
        Contact {
            with: ContactWith::Man { rod: 5 },
            normal_speed_m_per_s: 2.0,
        },
        Contact {
            with: ContactWith::Man { rod: 4 },
            normal_speed_m_per_s: 0.01, // resting contact
        },
        Contact {
            with: ContactWith::Wall,
            normal_speed_m_per_s: 0.5,
        },
        Contact {
            with: ContactWith::Field,
            normal_speed_m_per_s: 0.05,
        },
    ];
    let out = rules.step(&ball(0.0, 0.0, 1.0), &contacts);
    assert_eq!(
        out.events,
        [
            Event::Kick { rod: 5, speed: 2.0 },
            Event::Bounce { speed: 0.5 }
        ]
    );
}

#[test]
fn the_same_inputs_give_the_same_events() {
    let play = || {
        let mut rules = Rules::new(Table::paper(), RulesConfig::default());
        let mut events = Vec::new();
        for t in 0..20_000u64 {
            let x = ((t as f64) * 1e-3).sin() * 0.7;
            events.extend(rules.step(&ball(x, 0.01, 0.3), &[]).events);
        }
        (events, rules.score())
    };
    assert_eq!(play(), play());
}
