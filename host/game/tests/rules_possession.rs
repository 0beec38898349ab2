//! The possession limit: a ball that stays at one rod, however fast, is re-served.

use space_foosball::rules::{BallState, Event, Phase, Rules, RulesConfig, ServeReason};
use space_foosball::Table;

const R: f64 = 0.0175;

#[test]
fn a_ball_rattling_at_one_rod_is_re_served_after_the_possession_limit() {
    let table = Table::standard();
    let config = RulesConfig::default();
    let mut rules = Rules::new(table.clone(), config);
    for _ in 0..config.serve_pause_ms {
        rules.step(&BallState::default(), &[]);
    }
    assert_eq!(rules.phase(), Phase::InPlay);
    // Trapped between the two men of the Home defence (x = −0.375), bouncing left and
    // right at 10 m/s: never slow, so the stuck rule does not see it.
    let x = table.rods[1].x_m + 0.0015;
    let mut events = Vec::new();
    for ms in 0..config.possession_ms + 10 {
        let phase = (ms % 40) as f64 / 40.0;
        let y = 0.1 * (1.0 - 2.0 * (2.0 * phase - 1.0).abs());
        let vy = if phase < 0.5 { 10.0 } else { -10.0 };
        let b = BallState {
            position: [x, y, R],
            velocity: [0.0, vy, 0.0],
        };
        events.extend(rules.step(&b, &[]).events);
        if !events.is_empty() {
            break;
        }
    }
    assert!(events.is_empty(), "nothing yet: {events:?}");
    assert_eq!(
        rules.phase(),
        Phase::AwaitingServe {
            // In play from the step after the serve; the limit counts from there.
            at_ms: config.serve_pause_ms + 1 + config.possession_ms + config.serve_pause_ms,
            to: config.first_serve,
            reason: ServeReason::DeadBall
        }
    );
    // A ball moving on from rod to rod is never re-served by it.
    let mut rules = Rules::new(table.clone(), config);
    for _ in 0..config.serve_pause_ms {
        rules.step(&BallState::default(), &[]);
    }
    for ms in 0..3 * config.possession_ms {
        // Up and down the table at 0.2 m/s.
        let t = ms as f64 * 1e-3;
        let x = 0.25 * (1.0 - 2.0 * ((t * 0.2 / 2.0) % 1.0 * 2.0 - 1.0).abs());
        let b = BallState {
            position: [x, 0.1, R],
            velocity: [0.2, 0.0, 0.0],
        };
        let out = rules.step(&b, &[]);
        assert!(
            !out.events.iter().any(|e| matches!(e, Event::Serve { .. })),
            "t {t}"
        );
    }
    assert_eq!(rules.phase(), Phase::InPlay);
}
