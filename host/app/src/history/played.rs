//! The windowed game's match on its way into the history: its kicks gathered as the
//! frames drain the match's events, kept (on a thread of its own) once it is over.

use super::record::{now_unix_s, MatchRecord, Mode};
use super::store::HistoryStore;
use space_foosball::play::RodController;
use space_foosball::recording::MatchRecording;
use space_foosball::rules::{Event, TimedEvent};
use space_foosball::table::CharacterType;
use space_foosball::Table;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// Most events kept for one match: a match that goes on longer keeps its first kicks and
/// its end (about 40 kicks a minute in play: hours of match).
const MAX_EVENTS: usize = 100_000;

/// A match being played, for the history.
#[derive(Debug)]
pub struct PlayedMatch {
    table: Table,
    teams: [String; 2],
    seed: u64,
    events: Vec<TimedEvent>,
}

/// Who played a team, as the history names it: the character, and `(computer)` where
/// the computer played it.
pub fn team_name(character: CharacterType, controller: RodController) -> String {
    let name = match character {
        CharacterType::TallThin => "tall-thin",
        CharacterType::ShortWide => "short-wide",
    };
    match controller {
        RodController::Player => name.to_string(),
        RodController::Computer => format!("{name} (computer)"),
    }
}

impl PlayedMatch {
    /// A match on `table` (its teams' characters chosen) started with `seed`.
    pub fn new(table: &Table, controllers: [RodController; 2], seed: u64) -> Self {
        let teams = [0, 1].map(|k| team_name(table.teams[k].character, controllers[k]));
        Self {
            table: table.clone(),
            teams,
            seed,
            events: Vec::new(),
        }
    }

    /// Takes in the events a frame drained; the match's record once they hold its end.
    pub fn take(&mut self, events: &[TimedEvent]) -> Option<MatchRecord> {
        for e in events {
            let keep = match e.event {
                Event::Kick { .. } => self.events.len() < MAX_EVENTS,
                Event::MatchOver { .. } => true,
                _ => false,
            };
            if keep {
                self.events.push(*e);
            }
        }
        MatchRecord::from_events(
            &self.events,
            &self.table,
            self.teams.clone(),
            Mode::Local,
            self.seed,
            now_unix_s(),
        )
    }
}

/// Keeps `record` in the history at `path`, with its `replay` where there is one, on a
/// thread of its own (the frame does not wait for the compression or the disk), then puts
/// the history's new attract lines in `lines`; a history that cannot be written is reported
/// on stderr, and play goes on.
pub fn keep_in_background(
    path: PathBuf,
    record: MatchRecord,
    replay: Option<MatchRecording>,
    lines: Arc<Mutex<Vec<String>>>,
) {
    let spawned = std::thread::Builder::new()
        .name("history".into())
        .spawn(move || {
            let kept = HistoryStore::open(&path).and_then(|mut s| s.add(&record, replay.as_ref()));
            if let Err(e) = kept {
                eprintln!("space-foosball: the match was not kept: {e}");
                return;
            }
            let new = attract_lines(&path);
            *lines
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner) = new;
        });
    if let Err(e) = spawned {
        eprintln!("space-foosball: the match was not kept: {e}");
    }
}

/// Matches the attract screen's lines are made from: the newest this many.
const ATTRACT_MATCHES: usize = 200;

/// The attract screen's lines from `matches` (newest first): the top scorers and the
/// fastest shot, in the screen font's letters; none without a match.
pub fn attract_lines_of(matches: &[MatchRecord]) -> Vec<String> {
    if matches.is_empty() {
        return Vec::new();
    }
    let scorers: Vec<String> = super::cli::top_scorers(matches, 3)
        .iter()
        .map(|s| format!("{} {}", s.team.to_uppercase(), s.goals))
        .collect();
    let mut lines = vec![format!("TOP SCORERS: {}", scorers.join(", "))];
    if let Some(f) = super::cli::fastest_shot(matches) {
        lines.push(format!(
            "FASTEST SHOT: {:.1} M/S {}",
            f.speed_m_s,
            f.team.to_uppercase()
        ));
    }
    lines
}

/// The attract screen's lines from the history at `path`; none where it does not exist
/// yet or cannot be read (reported on stderr: the attract screen shows without them).
pub fn attract_lines(path: &std::path::Path) -> Vec<String> {
    if !path.exists() {
        return Vec::new();
    }
    match HistoryStore::open(path).and_then(|s| s.recent(ATTRACT_MATCHES)) {
        Ok(matches) => attract_lines_of(&matches),
        Err(e) => {
            eprintln!("space-foosball: the match history is not shown: {e}");
            Vec::new()
        }
    }
}
