//! A match: the arena, the rules, who controls each rod, and the recording of the input.
//!
//! [`Match::step`] is one 1 ms step: the rods of a [`RodController::Player`] team follow
//! the given [`RodInputs`] (the board's newest poses), the rods of a
//! [`RodController::Computer`] team follow the computer opponent ([`crate::ai`]); the
//! arena steps; the rules turn the ball's state and contacts into events and serves.
//!
//! **Determinism.** Everything in a match is a function of its [`MatchConfig`] (table,
//! rules, seed, controllers, physics settings) and the per-step inputs: no clock, no
//! thread, no hash order. The seed drives the serve (direction jitter and speed, see
//! [`serve_jitter`]). Every step's input is recorded ([`Match::recording`], rod poses of
//! every rod); [`Match::replay`] plays a recording back to the same events and final
//! state, bit for bit (`tests/replay.rs`).
//!
//! [`PhysicsThread`] runs a match on its own thread at a fixed 1 kHz; [`haptics`] turns
//! its kicks into OUT reports for the board.

pub mod haptics;
pub mod reference;
mod rng;
pub mod thread;

pub use haptics::KickHaptics;
pub use rng::MatchRng;
pub use thread::{PhysicsThread, ThreadOptions, ThreadStats};

use crate::ai::{self, AiLimits, RodTarget};
use crate::arena::{Arena, ArenaError, ArenaSettings, DT_S};
use crate::input::paddles::{InputHealth, RodInputs, RodState};
use crate::recording::{MatchRecording, RecordedInput, RecordingError};
use crate::rules::{BallState, Event, Phase, Rules, RulesConfig, ServeSpec, TimedEvent};
use crate::side::Side;
use crate::table::Table;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The computer's default reaction time, ms (a quick human's).
pub const DEFAULT_REACTION_MS: u32 = 40;
/// The computer's default largest shot aim, m: off the edge of the foot.
pub const DEFAULT_MAX_AIM_M: f64 = 0.022;

/// How many of the latest events a [`MatchSnapshot`] carries.
pub const RECENT_EVENTS: usize = 16;

/// Who moves a team's rods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RodController {
    /// A person at the board: the rods follow the input poses.
    Player,
    /// The computer opponent.
    Computer,
}

/// Everything that defines a match (besides the per-step input).
#[derive(Debug, Clone, PartialEq)]
pub struct MatchConfig {
    /// The table.
    pub table: Table,
    /// The rules.
    pub rules: RulesConfig,
    /// Seed of everything random (the serves).
    pub seed: u64,
    /// Who plays each team, `[home, away]`.
    pub controllers: [RodController; 2],
    /// How fast the computer moves its rods.
    pub ai: AiLimits,
    /// The physics.
    pub arena: ArenaSettings,
    /// The computer's reaction time, ms: it plays on the ball as it was this long ago.
    pub reaction_ms: u32,
    /// Largest sideways aim of the computer's shots, m (see
    /// [`ai::desired_pose_aimed`]); each kick draws a new aim in `±max_aim_m`.
    pub max_aim_m: f64,
    /// Whether [`Match::recording`] keeps every step's input (128 bytes per ms on the
    /// standard table, ~7.7 MB per minute): on for matches to replay, off for an
    /// attract mode that runs for hours.
    pub record_inputs: bool,
}

impl MatchConfig {
    /// The computer against itself (attract mode, headless play), default rules.
    pub fn computer_vs_computer(table: Table, seed: u64) -> Self {
        Self {
            table,
            rules: RulesConfig::default(),
            seed,
            controllers: [RodController::Computer; 2],
            ai: AiLimits::default(),
            arena: ArenaSettings::default(),
            reaction_ms: DEFAULT_REACTION_MS,
            max_aim_m: DEFAULT_MAX_AIM_M,
            record_inputs: true,
        }
    }

    /// A person (Home, at the board) against the computer (Away), default rules.
    pub fn player_vs_computer(table: Table, seed: u64) -> Self {
        Self {
            controllers: [RodController::Player, RodController::Computer],
            ..Self::computer_vs_computer(table, seed)
        }
    }

    /// Who controls rod `rod`.
    pub fn controller_of(&self, rod: usize) -> RodController {
        self.controllers[self.table.rods[rod].team.index()]
    }
}

/// Why a match could not be created or replayed.
#[derive(Debug, thiserror::Error)]
pub enum MatchError {
    /// The arena could not be built (bad table or settings).
    #[error(transparent)]
    Arena(#[from] ArenaError),
    /// The rules are unusable.
    #[error("invalid rules: {0}")]
    Rules(String),
    /// The recording cannot be replayed.
    #[error(transparent)]
    Recording(#[from] RecordingError),
}

/// What the renderer, the sound and the UI need of a match at one instant. Cheap to
/// clone (a few hundred bytes).
#[derive(Debug, Clone, PartialEq)]
pub struct MatchSnapshot {
    /// Match time, s (steps × 1 ms).
    pub time_s: f64,
    /// Rod poses in physics, per rod of the table.
    pub rods: Vec<RodTarget>,
    /// The ball.
    pub ball: BallState,
    /// The ball's spin, rad/s.
    pub ball_spin: [f64; 3],
    /// Score `[home, away]`.
    pub score: [u32; 2],
    /// Where the match is.
    pub phase: Phase,
    /// The latest events (at most [`RECENT_EVENTS`]), oldest first.
    pub recent_events: Vec<TimedEvent>,
    /// Whether play is paused (set by [`PhysicsThread`]).
    pub paused: bool,
    /// The health of the input of the last step.
    pub input_health: InputHealth,
}

/// A match. See the [module](self) docs.
pub struct Match {
    config: MatchConfig,
    arena: Arena,
    rules: Rules,
    rng: MatchRng,
    computer_rods: Vec<usize>,
    /// The computer's aim per computer rod (same order as `computer_rods`), m.
    aims: Vec<f64>,
    /// The ball states of the last `reaction_ms` steps, oldest first.
    seen: VecDeque<BallState>,
    recording: MatchRecording,
    recent: VecDeque<TimedEvent>,
    last_health: InputHealth,
}

/// A match saved for rollback ([`Match::save`]): everything that decides what the match
/// does next — the physics world, the rules and the clock, the serves' generator, the
/// computer's aims and the ball it has seen, the events kept — and how far the recording
/// had got. Restored ([`Match::restore`]), the match steps on bit for bit as it did from
/// the moment it was saved.
#[derive(Clone)]
pub struct SavedMatch {
    arena: Arena,
    rules: Rules,
    rng: MatchRng,
    aims: Vec<f64>,
    seen: VecDeque<BallState>,
    recent: VecDeque<TimedEvent>,
    last_health: InputHealth,
    recorded_steps: usize,
}

/// The serve's direction jitter and speed factor for one serve: an angle within ±0.4 rad
/// off the table's axis and a speed × 0.8…1.3, from the match's generator.
pub fn serve_jitter(rng: &mut MatchRng, serve: &ServeSpec) -> ServeSpec {
    let angle = (rng.next_f64() * 2.0 - 1.0) * 0.4;
    let factor = 0.8 + 0.5 * rng.next_f64();
    let [vx, vy, vz] = serve.velocity;
    let (s, c) = virtual_physics::transcendental::sin_cos(angle);
    ServeSpec {
        velocity: [(vx * c - vy * s) * factor, (vx * s + vy * c) * factor, vz],
        ..*serve
    }
}

impl Match {
    /// A new match: rods centred and upright, the ball resting on the centre spot until
    /// the kickoff.
    pub fn new(config: MatchConfig) -> Result<Match, MatchError> {
        config
            .rules
            .validate(&config.table)
            .map_err(|e| MatchError::Rules(e.to_string()))?;
        let arena = Arena::with_settings(&config.table, config.arena)?;
        let rules = Rules::new(config.table.clone(), config.rules);
        let n = config.table.rods.len();
        let computer_rods: Vec<usize> = (0..n)
            .filter(|&i| config.controller_of(i) == RodController::Computer)
            .collect();
        if !(config.max_aim_m.is_finite() && config.max_aim_m >= 0.0) {
            return Err(MatchError::Rules(format!(
                "max_aim_m must be a non-negative number, got {}",
                config.max_aim_m
            )));
        }
        let seen_capacity = config_reaction_capacity(&config);
        let recording = MatchRecording::of_poses(config.seed, config.table.clone(), config.rules);
        Ok(Match {
            rng: MatchRng::new(config.seed),
            config,
            arena,
            rules,
            aims: vec![0.0; computer_rods.len()],
            computer_rods,
            seen: VecDeque::with_capacity(seen_capacity),
            recording,
            recent: VecDeque::with_capacity(RECENT_EVENTS),
            last_health: InputHealth::Waiting,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MatchConfig {
        &self.config
    }

    /// The table.
    pub fn table(&self) -> &Table {
        &self.config.table
    }

    /// The poses of every rod that `inputs` asks for, table order: each rod's input pose
    /// (missing or non-finite entries: the rod's current target).
    fn input_poses(&self, inputs: &RodInputs) -> Vec<RodTarget> {
        let current = self.arena.rod_targets();
        (0..self.config.table.rods.len())
            .map(|i| match inputs.rods.get(i) {
                Some(s) if s.slide_m.is_finite() && s.angle_rad.is_finite() => RodTarget {
                    slide_m: s.slide_m,
                    angle_rad: s.angle_rad,
                },
                _ => current[i],
            })
            .collect()
    }

    /// One 1 ms step; returns the step's events (with their match time). Once the match
    /// is over, steps do nothing.
    pub fn step(&mut self, inputs: &RodInputs) -> Vec<TimedEvent> {
        self.last_health = inputs.health;
        if self.is_over() {
            // Nothing moves after the final whistle, and nothing is recorded.
            return Vec::new();
        }
        let poses = self.input_poses(inputs);
        if !self.config.record_inputs {
            return self.step_with_poses(poses);
        }
        self.recording.push_poses(&RodInputs {
            rods: poses
                .iter()
                .map(|p| RodState {
                    slide_m: p.slide_m,
                    angle_rad: p.angle_rad,
                    ..RodState::default()
                })
                .collect(),
            health: inputs.health,
            time_ms: inputs.time_ms,
            lost_reports: inputs.lost_reports,
        });
        self.step_with_poses(poses)
    }

    fn step_with_poses(&mut self, mut targets: Vec<RodTarget>) -> Vec<TimedEvent> {
        if self.rules.phase() == Phase::Over {
            return Vec::new();
        }
        if !self.computer_rods.is_empty() {
            // The computer sees the ball as it was `reaction_ms` ago.
            self.seen.push_back(self.arena.ball());
            while self.seen.len() > self.config.reaction_ms as usize + 1 {
                self.seen.pop_front();
            }
            let ball = self.seen.front().copied().unwrap_or_default();
            // The computer moves its rods on from where they are in physics (a rod held
            // by a pinned ball does not run ahead of itself).
            let physics = self.arena.rod_poses();
            let current: Vec<RodTarget> = self.computer_rods.iter().map(|&i| physics[i]).collect();
            let next = ai::targets_aimed(
                &self.config.table,
                &self.computer_rods,
                &ball,
                &current,
                &self.aims,
                &self.config.ai,
                DT_S,
            );
            let in_play = self.rules.phase() == Phase::InPlay;
            for (&rod, mut pose) in self.computer_rods.iter().zip(next) {
                if !in_play {
                    // Ball not in play: the computer's rods come to rest, feet down.
                    let now = physics[rod];
                    pose = ai::step_towards(
                        now,
                        ai::resting(now),
                        &self.config.ai,
                        self.config.table.rods[rod].half_travel_m(),
                        DT_S,
                    );
                }
                targets[rod] = pose;
            }
        }
        self.arena.set_rod_targets(&targets);
        let step = self.arena.step();
        let outcome = self.rules.step(&step.ball, &step.contacts);
        if let Some(serve) = outcome.serve {
            let serve = serve_jitter(&mut self.rng, &serve);
            self.arena.place_ball(serve.position, serve.velocity);
        }
        if outcome
            .events
            .iter()
            .any(|e| matches!(e, Event::Kick { .. } | Event::Serve { .. }))
        {
            // Every kick and serve: the computer picks new aims.
            for aim in &mut self.aims {
                *aim = (self.rng.next_f64() * 2.0 - 1.0) * self.config.max_aim_m;
            }
        }
        let t_ms = self.rules.time_ms();
        let events: Vec<TimedEvent> = outcome
            .events
            .into_iter()
            .map(|event| TimedEvent { t_ms, event })
            .collect();
        for e in &events {
            if self.recent.len() == RECENT_EVENTS {
                self.recent.pop_front();
            }
            self.recent.push_back(*e);
        }
        events
    }

    /// Where the match is, for the renderer.
    pub fn snapshot(&self) -> MatchSnapshot {
        MatchSnapshot {
            time_s: self.rules.time_ms() as f64 * DT_S,
            rods: self.arena.rod_poses(),
            ball: self.arena.ball(),
            ball_spin: self.arena.ball_spin(),
            score: self.rules.score(),
            phase: self.rules.phase(),
            recent_events: self.recent.iter().copied().collect(),
            paused: false,
            input_health: self.last_health,
        }
    }

    /// Score `[home, away]`.
    pub fn score(&self) -> [u32; 2] {
        self.rules.score()
    }

    /// A checksum of where the match is: its clock, score, ball and rods, bit for bit
    /// (FNV-1a). Two sides of an online match compare it to see that they agree.
    pub fn state_hash(&self) -> u128 {
        let s = self.snapshot();
        let mut words = vec![
            s.time_s.to_bits(),
            u64::from(s.score[0]),
            u64::from(s.score[1]),
        ];
        words.extend(
            s.ball
                .position
                .iter()
                .chain(&s.ball.velocity)
                .map(|x| x.to_bits()),
        );
        for r in &s.rods {
            words.extend([r.slide_m.to_bits(), r.angle_rad.to_bits()]);
        }
        let mut h: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
        for w in words {
            for b in w.to_le_bytes() {
                h ^= u128::from(b);
                h = h.wrapping_mul(0x0000_0000_0100_0000_0000_0000_0000_013b);
            }
        }
        h
    }

    /// The match saved for rollback (see [`SavedMatch`]); the recording is not copied.
    pub fn save(&self) -> SavedMatch {
        SavedMatch {
            arena: self.arena.clone(),
            rules: self.rules.clone(),
            rng: self.rng.clone(),
            aims: self.aims.clone(),
            seen: self.seen.clone(),
            recent: self.recent.clone(),
            last_health: self.last_health,
            recorded_steps: self.recording.pose_steps(),
        }
    }

    /// Puts the match back as it was when `saved` was taken from it (the recording cut
    /// back to that step). `saved` must come from this match.
    pub fn restore(&mut self, saved: &SavedMatch) {
        self.arena.clone_from(&saved.arena);
        self.rules.clone_from(&saved.rules);
        self.rng.clone_from(&saved.rng);
        self.aims.clone_from(&saved.aims);
        self.seen.clone_from(&saved.seen);
        self.recent.clone_from(&saved.recent);
        self.last_health = saved.last_health;
        self.recording.truncate_poses(saved.recorded_steps);
    }

    /// Whether someone has won.
    pub fn is_over(&self) -> bool {
        self.rules.phase() == Phase::Over
    }

    /// The winner, once the match is over.
    pub fn winner(&self) -> Option<Side> {
        self.rules.winner()
    }

    /// Where the match is.
    pub fn phase(&self) -> Phase {
        self.rules.phase()
    }

    /// Match time, ms (steps taken).
    pub fn time_ms(&self) -> u64 {
        self.rules.time_ms()
    }

    /// The recorded input so far.
    pub fn recording(&self) -> &MatchRecording {
        &self.recording
    }

    /// The arena (ball, rods, world; for checks and measurements).
    pub fn arena(&self) -> &Arena {
        &self.arena
    }

    /// Plays `recording` again with `controllers` (who played each team when it was
    /// recorded) and the default computer and physics settings: the same events, in
    /// order, and the finished match. The recording's table, rules and seed are used.
    pub fn replay(
        recording: &MatchRecording,
        controllers: [RodController; 2],
    ) -> Result<(Match, Vec<TimedEvent>), MatchError> {
        let mut config = MatchConfig::computer_vs_computer(recording.table.clone(), 0);
        config.controllers = controllers;
        Self::replay_with(recording, config)
    }

    /// [`Match::replay`] with the settings the match was played with (`config`'s
    /// controllers, computer and physics; its table, rules and seed are taken from the
    /// recording).
    pub fn replay_with(
        recording: &MatchRecording,
        config: MatchConfig,
    ) -> Result<(Match, Vec<TimedEvent>), MatchError> {
        recording.validate()?;
        let RecordedInput::Poses(steps) = &recording.input else {
            return Err(MatchError::Recording(RecordingError::Malformed(
                "a report recording replays through the board input, not as poses".into(),
            )));
        };
        let mut m = Match::new(MatchConfig {
            table: recording.table.clone(),
            rules: recording.rules,
            seed: recording.seed,
            record_inputs: true,
            ..config
        })?;
        let mut events = Vec::new();
        for step in steps {
            let inputs = RodInputs {
                rods: step
                    .iter()
                    .map(|p| RodState {
                        slide_m: p[0],
                        angle_rad: p[1],
                        present: true,
                        ..RodState::default()
                    })
                    .collect(),
                health: InputHealth::Live,
                time_ms: 0,
                lost_reports: 0,
            };
            events.extend(m.step(&inputs));
        }
        Ok((m, events))
    }
}

fn config_reaction_capacity(config: &MatchConfig) -> usize {
    (config.reaction_ms as usize + 2).min(10_000)
}

/// Rod inputs that hold every rod of `table` centred and upright (for computer-only
/// matches, whose input is ignored).
pub fn idle_inputs(table: &Table) -> RodInputs {
    RodInputs {
        rods: vec![RodState::default(); table.rods.len()],
        health: InputHealth::Live,
        time_ms: 0,
        lost_reports: 0,
    }
}

/// Whether an event ends the match.
pub fn is_match_over(event: &Event) -> bool {
    matches!(event, Event::MatchOver { .. })
}
