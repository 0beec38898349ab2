//! Game events as values, for sound, particles, haptics and the JSON event stream.
//!
//! Serialised with an `event` tag: `{"event":"Goal","side":"home","score":[1,0]}`,
//! `{"event":"MatchOver","score":[5,3]}`; [`TimedEvent`] adds the match time:
//! `{"t_ms":1234,"event":"Kick","rod":5,"speed":2.1}`.

use crate::side::Side;
use serde::{Deserialize, Serialize};

/// Why the ball is served.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ServeReason {
    /// The first serve of the match.
    Kickoff,
    /// After a goal, to the side that conceded.
    AfterGoal,
    /// The ball was out of reach or stuck for too long.
    DeadBall,
    /// The ball left the table (or its state was not finite).
    OutOfPlay,
}

/// Something that happened in the match.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event")]
pub enum Event {
    /// A man of rod `rod` hit the ball; `speed` is the normal relative speed at the
    /// contact, m/s.
    Kick {
        /// Index of the rod in the table.
        rod: usize,
        /// Normal relative speed, m/s.
        speed: f64,
    },
    /// The ball bounced off a wall or the field; `speed` as for kicks, m/s.
    Bounce {
        /// Normal relative speed, m/s.
        speed: f64,
    },
    /// `side` scored; `score` is `[home, away]` after the goal.
    Goal {
        /// The team that scored.
        side: Side,
        /// Score after the goal, `[home, away]`.
        score: [u32; 2],
    },
    /// The ball was put in play from the middle towards `to`'s half.
    Serve {
        /// The team it is served to.
        to: Side,
        /// Why.
        reason: ServeReason,
    },
    /// The match is over; `score` is `[home, away]`.
    MatchOver {
        /// Final score, `[home, away]`.
        score: [u32; 2],
    },
}

/// An event with the match time it happened at.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimedEvent {
    /// Match time, ms (physics steps at 1 kHz since the match started).
    pub t_ms: u64,
    /// The event.
    #[serde(flatten)]
    pub event: Event,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_forms() {
        let over = Event::MatchOver { score: [5, 3] };
        assert_eq!(
            serde_json::to_string(&over).unwrap(),
            r#"{"event":"MatchOver","score":[5,3]}"#
        );
        let goal = Event::Goal {
            side: Side::Away,
            score: [0, 1],
        };
        assert_eq!(
            serde_json::to_string(&goal).unwrap(),
            r#"{"event":"Goal","side":"away","score":[0,1]}"#
        );
        let timed = TimedEvent {
            t_ms: 12,
            event: Event::Kick { rod: 5, speed: 2.5 },
        };
        let text = serde_json::to_string(&timed).unwrap();
        assert_eq!(text, r#"{"t_ms":12,"event":"Kick","rod":5,"speed":2.5}"#);
        assert_eq!(serde_json::from_str::<TimedEvent>(&text).unwrap(), timed);
        let serve = Event::Serve {
            to: Side::Home,
            reason: ServeReason::DeadBall,
        };
        let text = serde_json::to_string(&serve).unwrap();
        assert_eq!(
            text,
            r#"{"event":"Serve","to":"home","reason":"dead_ball"}"#
        );
        assert_eq!(serde_json::from_str::<Event>(&text).unwrap(), serve);
    }
}
