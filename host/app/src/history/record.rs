//! What the history keeps of a finished match.

use serde::{Deserialize, Serialize};
use space_foosball::rules::{Event, TimedEvent};
use space_foosball::side::Side;
use space_foosball::Table;

/// How the match was played.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// At one cabinet (or headless on this machine).
    Local,
    /// Two cabinets over the network.
    Online,
}

impl Mode {
    /// The word stored in the database and printed.
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::Local => "local",
            Mode::Online => "online",
        }
    }

    /// The mode a stored word names.
    pub fn parse(word: &str) -> Option<Self> {
        match word {
            "local" => Some(Mode::Local),
            "online" => Some(Mode::Online),
            _ => None,
        }
    }
}

/// A kick of the ball by a man, with its speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shot {
    /// Match time of the kick, ms.
    pub t_ms: u64,
    /// The team whose man kicked.
    pub side: Side,
    /// Index of the rod in the table.
    pub rod: u32,
    /// The ball's normal speed relative to the man at the kick, m/s.
    pub speed_m_s: f64,
}

/// One finished match.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchRecord {
    /// Its row id in the database (0 before it is stored).
    pub id: i64,
    /// When it ended, s since the Unix epoch (UTC).
    pub finished_unix_s: i64,
    /// Local or online.
    pub mode: Mode,
    /// The table's name.
    pub table: String,
    /// Who played each team, `[home, away]`: a character's name, `computer` or a peer.
    pub teams: [String; 2],
    /// Final score, `[home, away]`.
    pub score: [u32; 2],
    /// Match time from the kickoff to the last goal, ms.
    pub duration_ms: u64,
    /// The match's seed (its serves), which replays a computer-only match exactly.
    pub seed: u64,
    /// Every kick, in match order.
    pub shots: Vec<Shot>,
    /// Whether its replay is kept beside it (`space-foosball history --replay ID`).
    #[serde(default)]
    pub has_replay: bool,
}

impl MatchRecord {
    /// The record of a match on `table` from its events (any order of arrival; kicks and
    /// the end are read), or `None` while no `MatchOver` is among them.
    pub fn from_events(
        events: &[TimedEvent],
        table: &Table,
        teams: [String; 2],
        mode: Mode,
        seed: u64,
        finished_unix_s: i64,
    ) -> Option<Self> {
        let (end_ms, score) = events.iter().find_map(|e| match e.event {
            Event::MatchOver { score } => Some((e.t_ms, score)),
            _ => None,
        })?;
        let shots = events
            .iter()
            .filter_map(|e| match e.event {
                Event::Kick { rod, speed } if speed.is_finite() => Some(Shot {
                    t_ms: e.t_ms,
                    side: table.rods.get(rod)?.team,
                    rod: u32::try_from(rod).ok()?,
                    speed_m_s: speed,
                }),
                _ => None,
            })
            .collect();
        Some(Self {
            id: 0,
            finished_unix_s,
            mode,
            table: table.name.clone(),
            teams,
            score,
            duration_ms: end_ms,
            seed,
            shots,
            has_replay: false,
        })
    }

    /// The fastest shot, if any.
    pub fn fastest_shot(&self) -> Option<&Shot> {
        self.shots
            .iter()
            .max_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s))
    }

    /// The winning side, `None` for a draw.
    pub fn winner(&self) -> Option<Side> {
        match self.score[0].cmp(&self.score[1]) {
            std::cmp::Ordering::Greater => Some(Side::Home),
            std::cmp::Ordering::Less => Some(Side::Away),
            std::cmp::Ordering::Equal => None,
        }
    }
}

/// Seconds since the Unix epoch now (0 if the clock is before it).
pub fn now_unix_s() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_secs()).unwrap_or(i64::MAX))
}
