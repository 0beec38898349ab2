//! A lively demonstration snapshot (screenshots, benchmark, tests): rods swinging, the
//! ball bouncing across the table, recent kicks and bounces. A pure function of time.

use crate::scene::Screen;
use crate::view::{
    BallSnapshot, EventKind, FrameSnapshot, RenderEvent, RodPose, TableGeometry, Team,
};

/// The demo scene at time `t` (s) on `table`, with `score`.
pub fn demo_snapshot(table: &TableGeometry, t: f64, score: [u32; 2]) -> FrameSnapshot {
    let rods: Vec<RodPose> = table
        .rods
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let k = i as f64;
            RodPose {
                slide_m: 0.4 * r.travel_m * (0.9 * t + 1.7 * k).sin(),
                angle_rad: 0.6 * (1.3 * t + 0.9 * k).sin(),
            }
        })
        .collect();
    let r = table.ball_radius_m;
    // The ball: a bouncing path across the table (period of a hop 0.8 s).
    let hop = 0.8;
    let phase = (t / hop).fract();
    let height = 0.12 * 4.0 * phase * (1.0 - phase);
    let x = 0.32 * (0.5 * t).sin();
    let y = 0.18 * (0.8 * t).sin();
    let vz = 0.12 * 4.0 * (1.0 - 2.0 * phase) / hop;
    let ball = BallSnapshot {
        position: [x, y, r + height],
        velocity: [0.16 * (0.5 * t).cos(), 0.144 * (0.8 * t).cos(), vz],
    };
    // Last bounce on the cloth, and a kick a little earlier.
    let t_bounce = t - phase * hop;
    let bx = 0.32 * (0.5 * t_bounce).sin();
    let by = 0.18 * (0.8 * t_bounce).sin();
    let events = vec![
        RenderEvent {
            time_s: t - 0.25,
            kind: EventKind::Kick,
            position: [-0.2, -0.1, 0.03],
            speed: 3.0,
        },
        RenderEvent {
            time_s: t_bounce,
            kind: EventKind::Bounce,
            position: [bx, by, r],
            speed: 1.0,
        },
    ];
    FrameSnapshot::posed(table, t, &rods, ball, score, events)
}

/// The demo scene just after a goal by `scorer` (burst in the goal mouth).
pub fn goal_snapshot(
    table: &TableGeometry,
    t: f64,
    score: [u32; 2],
    scorer: Team,
) -> FrameSnapshot {
    let mut s = demo_snapshot(table, t, score);
    let x = table.goal_line_x(scorer.other());
    let r = table.ball_radius_m;
    s.ball.position = [x + 0.03 * scorer.attack_dir(), 0.02, r];
    s.events.push(RenderEvent {
        time_s: t - 0.35,
        kind: EventKind::Goal(scorer),
        position: [x, 0.0, 0.03],
        speed: 4.0,
    });
    s
}

/// The demo scene each screen is pictured with (screenshots, README pictures) at time
/// `t` (s): the goal ceremony just after a Home goal (2–1), the final result at 5–3,
/// every other screen over the demo match at 2–1.
pub fn screen_snapshot(table: &TableGeometry, t: f64, screen: Screen) -> FrameSnapshot {
    match screen {
        Screen::GoalCeremony => goal_snapshot(table, t, [2, 1], Team::Home),
        Screen::FinalResult => demo_snapshot(table, t, [5, 3]),
        _ => demo_snapshot(table, t, [2, 1]),
    }
}
