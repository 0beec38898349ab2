//! The match rules: a state machine over abstract per-step inputs.
//!
//! The physics (or a test) calls [`Rules::step`] once per 1 ms step with the ball's
//! state and the step's contacts; the rules answer with events and, when the ball must
//! be put in play, a [`ServeSpec`] (where to place it, with what velocity). Nothing
//! here knows about the physics engine.
//!
//! * **Serve** from the middle (`x = 0`, `y = 0`, dropped from
//!   [`RulesConfig::serve_drop_height_m`]) rolling towards the receiving team's half: the
//!   kickoff to [`RulesConfig::first_serve`], after a goal to the side that conceded,
//!   after a dead ball or an out-of-play ball to the side that received the last serve.
//!   Each serve comes [`RulesConfig::serve_pause_ms`] after the reason for it
//!   ([`RulesConfig::goal_pause_ms`] after a goal: the goal ceremony).
//! * **Goal** when the ball has fully crossed a goal line (centre beyond the line by
//!   more than its radius) inside the goal mouth (`|y| ≤ width/2`, `z ≤ height`).
//! * **Dead ball**: slow (below [`RulesConfig::slow_speed_m_per_s`]) and out of every
//!   man's reach ([`Table::any_rod_can_reach`]) for [`RulesConfig::dead_ball_ms`], or
//!   slow and within [`RulesConfig::stuck_radius_m`] of one place for
//!   [`RulesConfig::stuck_ms`] (stuck, or held too long), is served again; so is a ball
//!   that stays at one rod (nearest along `x`), however fast it moves, for
//!   [`RulesConfig::possession_ms`] (possession limit; a ball rattling between two men).
//! * **Out of play**: a non-finite state, or a ball outside the field that is not in a
//!   goal, is served again.
//! * **Match over** when a team reaches [`RulesConfig::goals_to_win`] (default 5).
//! * **Kick** / **Bounce** events from contacts above a speed threshold, while in play.

mod events;
mod validate;

pub use events::{Event, ServeReason, TimedEvent};
pub use validate::RulesError;

use crate::side::Side;
use crate::table::Table;
use serde::{Deserialize, Serialize};

/// Ball state for one step, table frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BallState {
    /// Centre, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
}

impl BallState {
    /// Speed, m/s.
    pub fn speed(&self) -> f64 {
        let v = self.velocity;
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    }

    /// Whether every number is finite.
    pub fn is_finite(&self) -> bool {
        self.position
            .iter()
            .chain(&self.velocity)
            .all(|v| v.is_finite())
    }
}

/// What the ball touched in a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactWith {
    /// A man of rod `rod` (index in the table).
    Man {
        /// Rod index.
        rod: usize,
    },
    /// A wall, ramp or goal box.
    Wall,
    /// The playing field.
    Field,
}

/// One ball contact of a step, as the physics reports it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// What the ball touched.
    pub with: ContactWith,
    /// Relative speed along the contact normal before the impulse, m/s (≥ 0).
    pub normal_speed_m_per_s: f64,
}

/// Where and how to put the ball in play. Table frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ServeSpec {
    /// The receiving team.
    pub to: Side,
    /// Ball centre, m.
    pub position: [f64; 3],
    /// Ball velocity, m/s.
    pub velocity: [f64; 3],
}

/// Tunable rules. Times in ms of match time (1 step = 1 ms), speeds m/s, lengths m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RulesConfig {
    /// Goals that win the match.
    pub goals_to_win: u32,
    /// Who receives the kickoff.
    pub first_serve: Side,
    /// A slow ball out of reach this long is dead, ms.
    pub dead_ball_ms: u64,
    /// A slow ball staying in one place this long is stuck, ms.
    pub stuck_ms: u64,
    /// Below this speed the ball counts as slow, m/s.
    pub slow_speed_m_per_s: f64,
    /// "One place" for the stuck rule, m.
    pub stuck_radius_m: f64,
    /// A ball that stays at one rod (nearest to the same rod along `x`), however fast,
    /// this long is re-served as dead, ms: the possession limit of real tables, and the
    /// end of a ball trapped rattling between two men.
    pub possession_ms: u64,
    /// Pause after a goal before the next serve, ms.
    pub goal_pause_ms: u64,
    /// Pause before the kickoff and before re-serving a dead or out-of-play ball, ms.
    pub serve_pause_ms: u64,
    /// Speed of the served ball towards the receiving half, m/s.
    pub serve_speed_m_per_s: f64,
    /// Height of the ball's bottom above the field when served, m.
    pub serve_drop_height_m: f64,
    /// Contacts with men slower than this give no `Kick` event, m/s.
    pub kick_threshold_m_per_s: f64,
    /// Contacts with walls or the field slower than this give no `Bounce`, m/s.
    pub bounce_threshold_m_per_s: f64,
}

impl Default for RulesConfig {
    fn default() -> Self {
        Self {
            goals_to_win: 5,
            first_serve: Side::Home,
            dead_ball_ms: 3_000,
            stuck_ms: 10_000,
            slow_speed_m_per_s: 0.05,
            stuck_radius_m: 0.02,
            possession_ms: 10_000,
            goal_pause_ms: 1_500,
            serve_pause_ms: 500,
            serve_speed_m_per_s: 0.3,
            serve_drop_height_m: 0.02,
            kick_threshold_m_per_s: 0.05,
            bounce_threshold_m_per_s: 0.1,
        }
    }
}

/// Where the match is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Phase {
    /// Waiting to serve at match time `at_ms`.
    AwaitingServe {
        /// Match time of the serve, ms.
        at_ms: u64,
        /// Receiving team.
        to: Side,
        /// Why.
        reason: ServeReason,
    },
    /// The ball is in play.
    InPlay,
    /// Someone won.
    Over,
}

/// What one step produced.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepOutcome {
    /// Events of this step, in order.
    pub events: Vec<Event>,
    /// Put the ball here now (a serve happened this step).
    pub serve: Option<ServeSpec>,
}

/// The rules of one match.
#[derive(Debug, Clone)]
pub struct Rules {
    table: Table,
    config: RulesConfig,
    phase: Phase,
    score: [u32; 2],
    time_ms: u64,
    last_receiver: Side,
    /// Since when the ball is slow and out of reach.
    dead_since: Option<u64>,
    /// Since when, and where, the ball is slow in one place.
    stuck_anchor: Option<(u64, [f64; 3])>,
    /// Since when the ball is at which rod (nearest along `x`).
    possession: Option<(u64, usize)>,
}

impl Rules {
    /// A new match on `table`: the kickoff comes after [`RulesConfig::serve_pause_ms`].
    pub fn new(table: Table, config: RulesConfig) -> Self {
        Self {
            table,
            phase: Phase::AwaitingServe {
                at_ms: config.serve_pause_ms,
                to: config.first_serve,
                reason: ServeReason::Kickoff,
            },
            config,
            score: [0; 2],
            time_ms: 0,
            last_receiver: config.first_serve,
            dead_since: None,
            stuck_anchor: None,
            possession: None,
        }
    }

    /// Score `[home, away]`.
    pub fn score(&self) -> [u32; 2] {
        self.score
    }

    /// The phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Match time, ms (steps taken).
    pub fn time_ms(&self) -> u64 {
        self.time_ms
    }

    /// The winner, once the match is over.
    pub fn winner(&self) -> Option<Side> {
        (self.phase == Phase::Over).then(|| {
            if self.score[0] > self.score[1] {
                Side::Home
            } else {
                Side::Away
            }
        })
    }

    /// The configuration.
    pub fn config(&self) -> &RulesConfig {
        &self.config
    }

    /// Where a serve to `to` puts the ball.
    pub fn serve_spec(&self, to: Side) -> ServeSpec {
        ServeSpec {
            to,
            position: [
                0.0,
                0.0,
                self.table.ball.radius_m() + self.config.serve_drop_height_m,
            ],
            // Towards the receiving team's half: Home defends −x.
            velocity: [-to.attack_dir() * self.config.serve_speed_m_per_s, 0.0, 0.0],
        }
    }

    /// One 1 ms step: `ball` is the ball's state after the physics step, `contacts` the
    /// ball's contacts during it.
    pub fn step(&mut self, ball: &BallState, contacts: &[Contact]) -> StepOutcome {
        self.time_ms += 1;
        let mut out = StepOutcome::default();
        match self.phase {
            Phase::Over => {}
            Phase::AwaitingServe { at_ms, to, reason } => {
                if self.time_ms >= at_ms {
                    out.events.push(Event::Serve { to, reason });
                    out.serve = Some(self.serve_spec(to));
                    self.last_receiver = to;
                    self.phase = Phase::InPlay;
                    self.dead_since = None;
                    self.stuck_anchor = None;
                    self.possession = None;
                }
            }
            Phase::InPlay => self.in_play(ball, contacts, &mut out),
        }
        out
    }

    fn in_play(&mut self, ball: &BallState, contacts: &[Contact], out: &mut StepOutcome) {
        for c in contacts {
            match c.with {
                ContactWith::Man { rod } => {
                    if c.normal_speed_m_per_s >= self.config.kick_threshold_m_per_s {
                        out.events.push(Event::Kick {
                            rod,
                            speed: c.normal_speed_m_per_s,
                        });
                    }
                }
                ContactWith::Wall | ContactWith::Field => {
                    if c.normal_speed_m_per_s >= self.config.bounce_threshold_m_per_s {
                        out.events.push(Event::Bounce {
                            speed: c.normal_speed_m_per_s,
                        });
                    }
                }
            }
        }
        if !ball.is_finite() {
            self.reserve(ServeReason::OutOfPlay, self.config.serve_pause_ms);
            return;
        }
        if let Some(scorer) = self.goal_scored(ball) {
            self.score[scorer.index()] += 1;
            out.events.push(Event::Goal {
                side: scorer,
                score: self.score,
            });
            if self.score[scorer.index()] >= self.config.goals_to_win {
                out.events.push(Event::MatchOver { score: self.score });
                self.phase = Phase::Over;
            } else {
                self.phase = Phase::AwaitingServe {
                    at_ms: self.time_ms + self.config.goal_pause_ms,
                    to: scorer.other(),
                    reason: ServeReason::AfterGoal,
                };
            }
            return;
        }
        if self.out_of_play(ball) {
            self.reserve(ServeReason::OutOfPlay, self.config.serve_pause_ms);
            return;
        }
        if self.dead_or_stuck(ball) || self.held_too_long(ball) {
            self.reserve(ServeReason::DeadBall, self.config.serve_pause_ms);
        }
    }

    fn reserve(&mut self, reason: ServeReason, pause_ms: u64) {
        self.phase = Phase::AwaitingServe {
            at_ms: self.time_ms + pause_ms,
            to: self.last_receiver,
            reason,
        };
    }

    /// The team that scored, if the ball is fully inside a goal.
    fn goal_scored(&self, ball: &BallState) -> Option<Side> {
        let [x, y, z] = ball.position;
        let half_length = 0.5 * self.table.field.length_m;
        let r = self.table.ball.radius_m();
        let in_mouth = y.abs() <= 0.5 * self.table.goal.width_m && z <= self.table.goal.height_m;
        if !in_mouth {
            return None;
        }
        if x < -half_length - r {
            Some(Side::Away) // into the Home goal
        } else if x > half_length + r {
            Some(Side::Home)
        } else {
            None
        }
    }

    /// Whether the ball is somewhere it cannot be played from (and not in a goal).
    fn out_of_play(&self, ball: &BallState) -> bool {
        let [x, y, z] = ball.position;
        let f = &self.table.field;
        let r = self.table.ball.radius_m();
        let beyond_line = x.abs() > 0.5 * f.length_m + r;
        beyond_line || y.abs() > 0.5 * f.width_m || z < -r || z > f.wall_height_m + 0.5
    }

    /// Whether the ball has been at the same rod for [`RulesConfig::possession_ms`].
    fn held_too_long(&mut self, ball: &BallState) -> bool {
        let x = ball.position[0];
        let Some(rod) = (0..self.table.rods.len()).min_by(|&a, &b| {
            (self.table.rods[a].x_m - x)
                .abs()
                .total_cmp(&(self.table.rods[b].x_m - x).abs())
        }) else {
            return false;
        };
        match self.possession {
            Some((since, r)) if r == rod => self.time_ms - since >= self.config.possession_ms,
            _ => {
                self.possession = Some((self.time_ms, rod));
                false
            }
        }
    }

    fn dead_or_stuck(&mut self, ball: &BallState) -> bool {
        let slow = ball.speed() < self.config.slow_speed_m_per_s;
        if !slow {
            self.dead_since = None;
            self.stuck_anchor = None;
            return false;
        }
        let [x, y, _] = ball.position;
        if self.table.any_rod_can_reach(x, y) {
            self.dead_since = None;
        } else {
            let since = *self.dead_since.get_or_insert(self.time_ms);
            if self.time_ms - since >= self.config.dead_ball_ms {
                return true;
            }
        }
        match self.stuck_anchor {
            Some((since, at)) => {
                let d = ((ball.position[0] - at[0]).powi(2) + (ball.position[1] - at[1]).powi(2))
                    .sqrt();
                if d > self.config.stuck_radius_m {
                    self.stuck_anchor = Some((self.time_ms, ball.position));
                } else if self.time_ms - since >= self.config.stuck_ms {
                    return true;
                }
            }
            None => self.stuck_anchor = Some((self.time_ms, ball.position)),
        }
        false
    }
}
