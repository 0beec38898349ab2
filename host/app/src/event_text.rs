//! Match events as readable lines for `play --headless --format text`: the match time
//! in seconds, what happened, figures rounded to what a person reads (speeds to
//! 0.01 m/s).
//!
//! ```text
//!    0.000 s  serve    to home (kickoff)
//!    1.234 s  kick     home rod 6 (attack), 2.10 m/s
//!    1.402 s  bounce   0.84 m/s
//!   20.100 s  GOAL     away scores, 0-1
//! match over: 5-3, home wins
//! ```

use space_foosball::rules::{Event, ServeReason, TimedEvent};
use space_foosball::side::Side;
use space_foosball::Table;

fn side(s: Side) -> &'static str {
    match s {
        Side::Home => "home",
        Side::Away => "away",
    }
}

/// The line of one timed event on `table` (rod numbers count from 1, along the table).
pub fn line(e: &TimedEvent, table: &Table) -> String {
    let t = e.t_ms as f64 / 1000.0;
    let what = match e.event {
        Event::Kick { rod, speed } => {
            let who = table
                .rods
                .get(rod)
                .map(|r| format!("{} rod {} ({:?})", side(r.team), rod + 1, r.role).to_lowercase())
                .unwrap_or_else(|| format!("rod {}", rod + 1));
            format!("kick     {who}, {speed:.2} m/s")
        }
        Event::Bounce { speed } => format!("bounce   {speed:.2} m/s"),
        Event::Goal { side: s, score } => {
            format!("GOAL     {} scores, {}-{}", side(s), score[0], score[1])
        }
        Event::Serve { to, reason } => {
            let why = match reason {
                ServeReason::Kickoff => "kickoff",
                ServeReason::AfterGoal => "after a goal",
                ServeReason::DeadBall => "dead ball",
                ServeReason::OutOfPlay => "out of play",
            };
            format!("serve    to {} ({why})", side(to))
        }
        Event::MatchOver { score } => return over_line(score),
    };
    format!("{t:>8.3} s  {what}")
}

/// The last line: the final score and the winner.
pub fn over_line(score: [u32; 2]) -> String {
    let result = match score[0].cmp(&score[1]) {
        std::cmp::Ordering::Greater => "home wins",
        std::cmp::Ordering::Less => "away wins",
        std::cmp::Ordering::Equal => "a draw",
    };
    format!("match over: {}-{}, {result}", score[0], score[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_readable_and_rounded() {
        let t = Table::standard();
        let kick = TimedEvent {
            t_ms: 1234,
            event: Event::Kick {
                rod: 5,
                speed: 2.0999999999999996,
            },
        };
        assert_eq!(
            line(&kick, &t),
            "   1.234 s  kick     home rod 6 (attack), 2.10 m/s"
        );
        let goal = TimedEvent {
            t_ms: 20_100,
            event: Event::Goal {
                side: Side::Away,
                score: [0, 1],
            },
        };
        assert_eq!(line(&goal, &t), "  20.100 s  GOAL     away scores, 0-1");
        let bad = TimedEvent {
            t_ms: 0,
            event: Event::Kick {
                rod: 99,
                speed: 1.0,
            },
        };
        assert!(line(&bad, &t).contains("rod 100"));
        assert_eq!(over_line([5, 3]), "match over: 5-3, home wins");
    }
}
