//! The match under rollback: GGRS's save, load and advance requests carried out on a
//! [`Match`], and what the end of an online match needs (the frame it ends after, the
//! kicks both sides confirmed).

use super::input::{rod_inputs, SideInput};
use super::session::OnlineError;
use ggrs::{Config, GgrsRequest, PredictRepeatLast};
use space_foosball::play::{Match, MatchConfig, MatchError, RodController, SavedMatch};
use space_foosball::recording::{MatchRecording, RecordingError};
use space_foosball::rules::{Event, RulesConfig, TimedEvent};
use space_foosball::Table;
use std::collections::VecDeque;
use std::fmt::Debug;
use std::hash::Hash;
use std::marker::PhantomData;

/// Frames a second: the session's clock (the physics steps at 1 kHz within them).
pub const FPS: u64 = 60;
/// Frames a side may run ahead of the inputs it has: a rollback is at most this long.
pub const MAX_PREDICTION_FRAMES: usize = 8;
/// Most kicks kept for the history (hours of play).
const MAX_KEPT_EVENTS: usize = 100_000;

/// GGRS's types for a foosball match whose peers are named by `A` (a UDP address, or a
/// signalling server's peer id).
pub struct Foosball<A>(PhantomData<A>);

impl<A> Config for Foosball<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    type Input = SideInput;
    type InputPredictor = PredictRepeatLast;
    type State = FrameState;
    type Address = A;
}

/// The match saved at the start of a frame.
#[derive(Clone)]
pub struct FrameState {
    saved: SavedMatch,
    frame: i32,
}

/// The steps of frame `f`: from `f × 1000 / 60` to `(f + 1) × 1000 / 60` ms.
pub fn steps_of_frame(frame: u64) -> u64 {
    frame_start_ms(frame + 1) - frame_start_ms(frame)
}

/// The match time frame `f` starts at, ms (one physics step per ms).
fn frame_start_ms(frame: u64) -> u64 {
    frame * 1000 / FPS
}

/// What both sides must agree on to play one match.
#[derive(Debug, Clone)]
pub struct MatchTerms {
    /// The table (both sides the same).
    pub table: Table,
    /// The match's seed (both sides the same).
    pub seed: u64,
    /// Goals that win.
    pub goals: u32,
    /// End after this many frames (the match may still be on), if set.
    pub max_frames: Option<u64>,
}

/// The match side of a session: the match, the frame its state is at, and what the end
/// and the history need.
pub struct OnlineMatch {
    m: Match,
    table: Table,
    /// The frame the match's state is at (frames before it are stepped).
    state_frame: u64,
    /// The match's frame of the session's frame 0 (a resumed match's kept frames).
    first_frame: u64,
    /// The frame after which the match ended in this timeline (a rollback may undo it).
    over_at: Option<u64>,
    /// The last frame stepped (`max_frames`), or none.
    last_frame: u64,
    rollbacks: u64,
    resimulated: u64,
    /// The newest saves, for keeping the match as far as both sides confirmed it.
    saves: VecDeque<FrameState>,
    /// The kicks and the end, with the frame that made them (a rollback drops the later).
    kept_events: Vec<(u64, TimedEvent)>,
}

impl OnlineMatch {
    /// A match on `terms`, both teams' rods driven by the players' inputs.
    pub fn new(terms: &MatchTerms) -> Result<Self, MatchError> {
        let mut config = MatchConfig::computer_vs_computer(terms.table.clone(), terms.seed);
        config.controllers = [RodController::Player; 2];
        config.rules = RulesConfig {
            goals_to_win: terms.goals,
            ..RulesConfig::default()
        };
        Ok(Self {
            m: Match::new(config)?,
            table: terms.table.clone(),
            state_frame: 0,
            first_frame: 0,
            over_at: None,
            last_frame: terms.max_frames.unwrap_or(u64::MAX),
            rollbacks: 0,
            resimulated: 0,
            saves: VecDeque::with_capacity(MAX_PREDICTION_FRAMES + 2),
            kept_events: Vec::new(),
        })
    }

    /// Resumes the match kept in `recording` (an online match's, kept to a frame both
    /// sides played): replayed to its end, it goes on from there, the session's frame 0
    /// being its next frame. `max_frames` counts from the match's start. Both sides must
    /// resume from the same recording (a desync shows it otherwise).
    pub fn resume(recording: &MatchRecording, max_frames: Option<u64>) -> Result<Self, MatchError> {
        let steps = recording.pose_steps() as u64;
        let frames = (steps * FPS).div_ceil(1000);
        if frame_start_ms(frames) != steps {
            return Err(MatchError::Recording(RecordingError::Malformed(format!(
                "{steps} steps do not end on a frame of an online match (1/{FPS} s)"
            ))));
        }
        let (m, events) = Match::replay(recording, [RodController::Player; 2])?;
        if m.is_over() {
            return Err(MatchError::Recording(RecordingError::Malformed(
                "the kept match is over: replay it instead".into(),
            )));
        }
        let kept_events = events
            .into_iter()
            .filter(|e| matches!(e.event, Event::Kick { .. }))
            .take(MAX_KEPT_EVENTS)
            .map(|e| (e.t_ms * FPS / 1000, e))
            .collect();
        Ok(Self {
            m,
            table: recording.table.clone(),
            state_frame: frames,
            first_frame: frames,
            over_at: None,
            last_frame: max_frames.unwrap_or(u64::MAX),
            rollbacks: 0,
            resimulated: 0,
            saves: VecDeque::with_capacity(MAX_PREDICTION_FRAMES + 2),
            kept_events,
        })
    }

    /// The match's frame of the session's frame `frame`.
    pub fn match_frame(&self, frame: u64) -> u64 {
        self.first_frame + frame
    }

    /// Carries out GGRS's requests of one frame.
    pub fn handle<A>(&mut self, requests: Vec<GgrsRequest<Foosball<A>>>) -> Result<(), OnlineError>
    where
        A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
    {
        let (mut had_load, mut advances) = (false, 0u64);
        for request in requests {
            match request {
                GgrsRequest::SaveGameState { cell, frame } => {
                    let state = FrameState {
                        saved: self.m.save(),
                        frame,
                    };
                    if self.saves.len() > MAX_PREDICTION_FRAMES + 1 {
                        self.saves.pop_front();
                    }
                    self.saves.retain(|s| s.frame < frame);
                    self.saves.push_back(state.clone());
                    cell.save(frame, Some(state), Some(self.m.state_hash()));
                }
                GgrsRequest::LoadGameState { cell, frame } => {
                    let Some(state) = cell.load() else {
                        return Err(OnlineError::LostState { frame });
                    };
                    self.m.restore(&state.saved);
                    self.state_frame = self.match_frame(u64::try_from(state.frame).unwrap_or(0));
                    self.kept_events.retain(|(f, _)| *f < self.state_frame);
                    if !self.m.is_over() {
                        self.over_at = None;
                    }
                    had_load = true;
                    self.rollbacks += 1;
                }
                GgrsRequest::AdvanceFrame { inputs } => {
                    self.advance([&inputs[0].0, &inputs[1].0]);
                    advances += 1;
                }
            }
        }
        // After a load, every frame but the new one was stepped again.
        if had_load {
            self.resimulated += advances.saturating_sub(1);
        }
        Ok(())
    }

    /// Steps one frame with both sides' inputs (`[home, away]`). Frames past the last one
    /// change nothing: the final state stays put while the other side confirms it.
    fn advance(&mut self, sides: [&SideInput; 2]) {
        if self.state_frame < self.last_frame {
            let rods = rod_inputs(&self.table, sides, self.m.time_ms());
            for _ in 0..steps_of_frame(self.state_frame) {
                for e in self.m.step(&rods) {
                    let keep = match e.event {
                        Event::Kick { .. } => self.kept_events.len() < MAX_KEPT_EVENTS,
                        Event::MatchOver { .. } => true,
                        _ => false,
                    };
                    if keep {
                        self.kept_events.push((self.state_frame, e));
                    }
                }
            }
        }
        self.state_frame += 1;
        if self.m.is_over() && self.over_at.is_none() {
            self.over_at = Some(self.state_frame);
        }
    }

    /// The frame the match ends after: its end, or the last frame asked for.
    pub fn end(&self) -> u64 {
        self.over_at.unwrap_or(self.last_frame).min(self.last_frame)
    }

    /// The match's frame its state is at.
    pub fn state_frame(&self) -> u64 {
        self.state_frame
    }

    /// Restores the match to the start of the session's frame `frame` where it is still
    /// saved (the other side left: the match as far as both confirmed it); whether it was.
    pub fn restore_to(&mut self, frame: u64) -> bool {
        match self
            .saves
            .iter()
            .find(|s| u64::try_from(s.frame) == Ok(frame))
        {
            Some(s) => {
                self.m.restore(&s.saved);
                self.state_frame = self.match_frame(frame);
                true
            }
            None => false,
        }
    }

    /// The match.
    pub fn game(&self) -> &Match {
        &self.m
    }

    /// The table.
    pub fn table(&self) -> &Table {
        &self.table
    }

    /// The kicks and the end in this timeline.
    pub fn kept_events(&self) -> Vec<TimedEvent> {
        self.kept_events.iter().map(|(_, e)| *e).collect()
    }

    /// States loaded (rollbacks) and frames stepped again after them.
    pub fn rollbacks(&self) -> (u64, u64) {
        (self.rollbacks, self.resimulated)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kept_match_resumes_where_it_was_kept_and_only_on_a_frame() {
        let table = Table::standard();
        let mut config = MatchConfig::computer_vs_computer(table.clone(), 3);
        config.controllers = [RodController::Player; 2];
        let mut m = Match::new(config.clone()).unwrap();
        let idle = space_foosball::play::idle_inputs(&table);
        // Frame 157 starts at step 2616 (157 000 / 60, rounded down); 2617 is no frame's.
        for _ in 0..2617 {
            m.step(&idle);
        }
        let mut kept = m.recording().clone();
        let refused = OnlineMatch::resume(&kept, None).err().unwrap();
        assert!(refused.to_string().contains("frame"), "{refused}");
        kept.truncate_poses(2616);
        let resumed = OnlineMatch::resume(&kept, Some(200)).unwrap();
        assert_eq!((resumed.state_frame(), resumed.match_frame(3)), (157, 160));
        assert_eq!(resumed.end(), 200);
        let mut again = Match::new(config).unwrap();
        for _ in 0..2616 {
            again.step(&idle);
        }
        assert_eq!(resumed.game().state_hash(), again.state_hash());
    }

    #[test]
    fn frames_hold_the_steps_of_a_second_between_them() {
        let steps: u64 = (0..FPS).map(steps_of_frame).sum();
        assert_eq!(steps, 1000);
        assert!((0..FPS).all(|f| (16..=17).contains(&steps_of_frame(f))));
    }
}
