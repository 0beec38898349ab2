//! The cabinet's screens, driven by the rods (paper §5): push a rod to start, spin a rod
//! to choose. Pure: rod inputs and the clock in, the stage and what to do out.
//!
//! ```text
//! Attract ──push──▶ CharacterSelect ──push──▶ Playing ──match over──▶ FinalResult
//!    ▲  (computer vs computer)  │ spin: toggle that team's character      │ push (after 2 s)
//!    │                          └─ 30 s idle ─▶ Attract                    ▼
//!    └──────────────────────── 20 s idle ────────────────────────── CharacterSelect
//! ```
//!
//! A team **joins** when one of its rods is pushed or spun on the selection screen (or
//! pushed to leave the attract screen); a team that has not joined is played by the
//! computer. The goal ceremony and the board-lost message are not stages: the session
//! shows them over `Playing` (after a goal) and over any stage (board lost).

use foosball_audio::Sound;
use space_foosball::input::paddles::{InputHealth, RodInputs};
use space_foosball::play::RodController;
use space_foosball::side::Side;
use space_foosball::table::{CharacterType, Table};

/// Slide speed that counts as a push, m/s (either way: a brisk push or pull).
pub const PUSH_SPEED_M_S: f64 = 0.25;
/// Slide from where the rod last rested that counts as a push, m (catches pushes
/// between two slow frames).
pub const PUSH_DISTANCE_M: f64 = 0.03;
/// Slide speed below which the next push can count, m/s.
pub const REARM_SPEED_M_S: f64 = 0.08;
/// Turn that counts as a spin (one choice step), rad: 1.5 π, so one kick (a full turn)
/// is one step.
pub const SPIN_RAD: f64 = 1.5 * std::f64::consts::PI;
/// Gestures are ignored this long after a stage starts, s (the push that got here).
pub const SETTLE_S: f64 = 0.6;
/// The final result accepts a push after this long, s.
pub const RESULT_MIN_S: f64 = 2.0;
/// Idle selection goes back to attract after this long, s.
pub const SELECT_IDLE_S: f64 = 30.0;
/// The final result goes back to attract after this long, s.
pub const RESULT_IDLE_S: f64 = 20.0;

/// Where the cabinet is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Logo over the computer playing itself.
    Attract,
    /// Characters per team; who joins.
    CharacterSelect,
    /// A match.
    Playing,
    /// The final score.
    FinalResult,
    /// Guided calibration of the rods.
    Calibration,
}

impl Stage {
    /// The stage in words (`attract`, `character-select`, `playing`, `final-result`,
    /// `calibration`).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Attract => "attract",
            Stage::CharacterSelect => "character-select",
            Stage::Playing => "playing",
            Stage::FinalResult => "final-result",
            Stage::Calibration => "calibration",
        }
    }
}

/// A rod gesture seen in the input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gesture {
    /// Rod `rod` was pushed or pulled briskly.
    Push(usize),
    /// Rod `rod` turned by [`SPIN_RAD`] since its last spin.
    Spin(usize),
}

/// Turns rod states into push and spin gestures.
///
/// **Push:** counts on the press (the rod moves [`PUSH_DISTANCE_M`] from where it rested,
/// or faster than [`PUSH_SPEED_M_S`]), and the next push needs a release first: the rod
/// back near where it rested, or pulled back [`PUSH_DISTANCE_M`] from the furthest point
/// of the press, and then still. Holding a push (a rod kept at the far stop, Enter held)
/// is one push however long it lasts, and its return is no second push.
///
/// **Spin:** one step per spin, whatever its speed: a turn of [`SPIN_RAD`] from where
/// the rod last rested counts once, and the next step needs the rod to slow below
/// [`SPIN_REARM_RAD_S`] first (a fast flick of several turns is one step, not a random
/// number of them).
#[derive(Debug, Clone, Default)]
pub struct Gestures {
    rods: Vec<RodGesture>,
}

/// One rod's gesture state.
#[derive(Debug, Clone, Copy, Default)]
struct RodGesture {
    /// Where the rod rested before the current press, m.
    home_m: f64,
    /// A press can count now.
    armed: bool,
    /// The press under way: its direction (`±1`) and furthest slide so far, m.
    pressed: Option<(f64, f64)>,
    /// The angle a spin is measured from, rad.
    spin_base_rad: f64,
    /// A spin can count now.
    spin_armed: bool,
}

/// Angular speed below which the next spin can count, rad/s.
pub const SPIN_REARM_RAD_S: f64 = 1.0;

impl Gestures {
    /// Forgets the past: the current poses are where the rods rest; pushes arm once the
    /// rods are still.
    pub fn reset(&mut self, rods: &RodInputs) {
        self.rods = rods
            .rods
            .iter()
            .map(|r| RodGesture {
                home_m: r.slide_m,
                armed: false,
                pressed: None,
                spin_base_rad: r.angle_rad,
                spin_armed: true,
            })
            .collect();
    }

    /// Disarms every push (a new stage: the push that got here must be released).
    pub fn disarm(&mut self) {
        for g in &mut self.rods {
            g.armed = false;
        }
    }

    /// The gestures in `rods` since the last call.
    pub fn observe(&mut self, rods: &RodInputs) -> Vec<Gesture> {
        if self.rods.len() != rods.rods.len() {
            self.reset(rods);
        }
        let mut out = Vec::new();
        if rods.health != InputHealth::Live {
            return out;
        }
        for (i, (r, g)) in rods.rods.iter().zip(&mut self.rods).enumerate() {
            if !(r.slide_m.is_finite() && r.slide_velocity_m_per_s.is_finite()) {
                continue;
            }
            let v = r.slide_velocity_m_per_s;
            let still = v.abs() <= REARM_SPEED_M_S;
            let from_home = r.slide_m - g.home_m;
            match g.pressed {
                Some((dir, furthest)) => {
                    let furthest = if dir > 0.0 {
                        furthest.max(r.slide_m)
                    } else {
                        furthest.min(r.slide_m)
                    };
                    let back_home = from_home.abs() < 0.5 * PUSH_DISTANCE_M;
                    let pulled_back = (furthest - r.slide_m) * dir >= PUSH_DISTANCE_M;
                    if back_home || pulled_back {
                        // Released: arms again once the rod is still.
                        g.pressed = None;
                        g.armed = false;
                    } else {
                        g.pressed = Some((dir, furthest));
                    }
                }
                None if g.armed
                    && (v.abs() >= PUSH_SPEED_M_S || from_home.abs() >= PUSH_DISTANCE_M) =>
                {
                    let dir = if from_home.abs() >= 0.25 * PUSH_DISTANCE_M {
                        from_home.signum()
                    } else {
                        v.signum()
                    };
                    g.armed = false;
                    g.pressed = Some((dir, r.slide_m));
                    out.push(Gesture::Push(i));
                }
                None => {}
            }
            if g.pressed.is_none() && still {
                g.armed = true;
                g.home_m = r.slide_m;
            }
            if r.angle_rad.is_finite() && r.angular_velocity_rad_per_s.is_finite() {
                let turned = (r.angle_rad - g.spin_base_rad).abs();
                if g.spin_armed && turned >= SPIN_RAD {
                    g.spin_armed = false;
                    out.push(Gesture::Spin(i));
                }
                if r.angular_velocity_rad_per_s.abs() <= SPIN_REARM_RAD_S {
                    g.spin_armed = true;
                    g.spin_base_rad = r.angle_rad;
                }
            }
        }
        out
    }
}

/// What the session must do after a flow update.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Play a sound.
    Sound(Sound),
    /// Start a match with these characters (`[home, away]`) and controllers.
    StartMatch {
        /// Character type per team.
        characters: [CharacterType; 2],
        /// Who plays each team.
        controllers: [RodController; 2],
    },
    /// (Re)start the computer playing itself behind the attract screen.
    StartAttract,
}

/// The stage machine. See the [module](self).
#[derive(Debug, Clone)]
pub struct Flow {
    stage: Stage,
    since_s: f64,
    characters: [CharacterType; 2],
    joined: [bool; 2],
    gestures: Gestures,
    teams: Vec<Side>,
}

impl Flow {
    /// Starts at the attract screen at time `now_s` for `table`'s rods.
    pub fn new(table: &Table, now_s: f64) -> Self {
        Self {
            stage: Stage::Attract,
            since_s: now_s,
            characters: [table.teams[0].character, table.teams[1].character],
            joined: [false; 2],
            gestures: Gestures::default(),
            teams: table.rods.iter().map(|r| r.team).collect(),
        }
    }

    /// The current stage.
    pub fn stage(&self) -> Stage {
        self.stage
    }

    /// The characters chosen so far, `[home, away]`.
    pub fn characters(&self) -> [CharacterType; 2] {
        self.characters
    }

    /// When the current stage began, s (the clock of [`Flow::update`]).
    pub fn since_s(&self) -> f64 {
        self.since_s
    }

    /// Which teams have joined, `[home, away]`.
    pub fn joined(&self) -> [bool; 2] {
        self.joined
    }

    /// Goes to `stage` now.
    pub fn enter(&mut self, stage: Stage, now_s: f64) {
        self.stage = stage;
        self.since_s = now_s;
        self.gestures.disarm();
    }

    fn team_of(&self, rod: usize) -> Side {
        self.teams.get(rod).copied().unwrap_or(Side::Home)
    }

    fn start_match(&mut self, now_s: f64, out: &mut Vec<Action>) {
        let controllers = self.joined.map(|j| {
            if j {
                RodController::Player
            } else {
                RodController::Computer
            }
        });
        out.push(Action::Sound(Sound::MenuConfirm));
        out.push(Action::StartMatch {
            characters: self.characters,
            controllers,
        });
        self.enter(Stage::Playing, now_s);
    }

    /// One update at time `now_s` with the newest rod states; `match_over` says the
    /// running match has ended. Returns what to do.
    pub fn update(&mut self, now_s: f64, rods: &RodInputs, match_over: bool) -> Vec<Action> {
        let gestures = self.gestures.observe(rods);
        let age = now_s - self.since_s;
        let mut out = Vec::new();
        let settled = age >= SETTLE_S;
        match self.stage {
            Stage::Attract => {
                if match_over {
                    out.push(Action::StartAttract);
                }
                if let Some(Gesture::Push(rod)) = gestures
                    .iter()
                    .copied()
                    .find(|g| settled && matches!(g, Gesture::Push(_)))
                {
                    self.joined = [false; 2];
                    self.joined[self.team_of(rod).index()] = true;
                    out.push(Action::Sound(Sound::MenuConfirm));
                    self.enter(Stage::CharacterSelect, now_s);
                }
            }
            Stage::CharacterSelect => {
                if match_over {
                    out.push(Action::StartAttract);
                }
                for g in gestures.into_iter().filter(|_| settled) {
                    match g {
                        Gesture::Spin(rod) => {
                            let t = self.team_of(rod).index();
                            self.joined[t] = true;
                            self.characters[t] = match self.characters[t] {
                                CharacterType::TallThin => CharacterType::ShortWide,
                                CharacterType::ShortWide => CharacterType::TallThin,
                            };
                            self.since_s = now_s - SETTLE_S; // activity: not idle
                            out.push(Action::Sound(Sound::MenuTick));
                        }
                        Gesture::Push(rod) => {
                            self.joined[self.team_of(rod).index()] = true;
                            self.start_match(now_s, &mut out);
                            break;
                        }
                    }
                }
                if self.stage == Stage::CharacterSelect && age > SELECT_IDLE_S {
                    self.enter(Stage::Attract, now_s);
                }
            }
            Stage::Playing => {
                if match_over {
                    self.enter(Stage::FinalResult, now_s);
                }
            }
            Stage::FinalResult => {
                let pushed = gestures.iter().any(|g| matches!(g, Gesture::Push(_)));
                if age >= RESULT_MIN_S && pushed {
                    out.push(Action::Sound(Sound::MenuConfirm));
                    out.push(Action::StartAttract);
                    self.enter(Stage::CharacterSelect, now_s);
                } else if age > RESULT_IDLE_S {
                    out.push(Action::StartAttract);
                    self.enter(Stage::Attract, now_s);
                }
            }
            Stage::Calibration => {}
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use space_foosball::input::paddles::RodState;

    fn inputs(table: &Table, f: impl Fn(usize) -> RodState) -> RodInputs {
        RodInputs {
            rods: (0..table.rods.len()).map(f).collect(),
            health: InputHealth::Live,
            time_ms: 0,
            lost_reports: 0,
        }
    }

    fn still(table: &Table) -> RodInputs {
        inputs(table, |_| RodState::default())
    }

    fn pushing(table: &Table, rod: usize) -> RodInputs {
        inputs(table, |i| RodState {
            slide_velocity_m_per_s: if i == rod { 0.6 } else { 0.0 },
            ..RodState::default()
        })
    }

    #[test]
    fn push_starts_spin_chooses_push_plays_and_the_result_returns() {
        let table = Table::standard();
        let away = table.rods_of(Side::Away).next().unwrap();
        let home = table.rods_of(Side::Home).next().unwrap();
        let mut f = Flow::new(&table, 0.0);
        f.update(1.0, &still(&table), false);
        // A push before settling does nothing; after it, Away joins and chooses.
        f.update(1.1, &pushing(&table, away), false);
        assert_eq!(f.stage(), Stage::CharacterSelect);
        assert_eq!(f.joined(), [false, true]);
        let before = f.characters();
        f.update(1.2, &still(&table), false);
        // Spin Away's rod one full turn: one step.
        let spun = inputs(&table, |i| RodState {
            angle_rad: if i == away { 6.3 } else { 0.0 },
            ..RodState::default()
        });
        let a = f.update(2.0, &spun, false);
        assert_eq!(a, vec![Action::Sound(Sound::MenuTick)]);
        assert_ne!(f.characters()[1], before[1]);
        assert_eq!(f.characters()[0], before[0]);
        // Still spun: no second step.
        assert!(f.update(2.1, &spun, false).is_empty());
        // Home pushes: both play.
        let a = f.update(2.2, &pushing(&table, home), false);
        assert_eq!(f.stage(), Stage::Playing);
        assert!(a.contains(&Action::StartMatch {
            characters: f.characters(),
            controllers: [RodController::Player, RodController::Player],
        }));
        f.update(50.0, &still(&table), true);
        assert_eq!(f.stage(), Stage::FinalResult);
        // Too early for a push, then accepted.
        f.update(50.5, &pushing(&table, home), false);
        assert_eq!(f.stage(), Stage::FinalResult);
        f.update(51.0, &still(&table), false);
        f.update(53.0, &pushing(&table, home), false);
        assert_eq!(f.stage(), Stage::CharacterSelect);
    }

    #[test]
    fn a_team_that_does_not_join_is_the_computer() {
        let table = Table::standard();
        let home = table.rods_of(Side::Home).next().unwrap();
        let mut f = Flow::new(&table, 0.0);
        f.update(1.0, &still(&table), false);
        f.update(1.1, &pushing(&table, home), false);
        f.update(1.2, &still(&table), false);
        let a = f.update(2.0, &pushing(&table, home), false);
        assert!(a.contains(&Action::StartMatch {
            characters: f.characters(),
            controllers: [RodController::Player, RodController::Computer],
        }));
    }

    #[test]
    fn lost_board_gives_no_gestures_and_idle_returns_to_attract() {
        let table = Table::standard();
        let mut g = Gestures::default();
        let mut lost = pushing(&table, 0);
        lost.health = InputHealth::BoardLost;
        g.reset(&still(&table));
        g.observe(&still(&table));
        assert!(g.observe(&lost).is_empty());
        assert_eq!(g.observe(&pushing(&table, 0)), vec![Gesture::Push(0)]);
        // A push seen only as a displacement (no frame during the motion) counts too,
        // once; a slow drift of the resting place does not.
        let at = |slide: f64| {
            inputs(&table, |i| RodState {
                slide_m: if i == 0 { slide } else { 0.0 },
                ..RodState::default()
            })
        };
        g.observe(&at(0.0));
        g.observe(&at(0.02));
        assert!(g.observe(&at(0.035)).is_empty());
        assert_eq!(g.observe(&at(0.08)), vec![Gesture::Push(0)]);
        assert!(g.observe(&at(0.08)).is_empty());
        let mut f = Flow::new(&table, 0.0);
        f.enter(Stage::CharacterSelect, 0.0);
        f.update(SELECT_IDLE_S + 1.0, &still(&table), false);
        assert_eq!(f.stage(), Stage::Attract);
    }

    /// A rod's state at slide `slide_m` moving at `v` m/s (others still).
    fn rod_at(table: &Table, rod: usize, slide_m: f64, v: f64) -> RodInputs {
        inputs(table, |i| RodState {
            slide_m: if i == rod { slide_m } else { 0.0 },
            slide_velocity_m_per_s: if i == rod { v } else { 0.0 },
            ..RodState::default()
        })
    }

    #[test]
    fn holding_the_push_two_seconds_is_one_push_and_a_second_press_starts() {
        // Enter held on the keyboard: the rod runs to the far stop in 0.1 s, stays
        // there 2 s, and comes back; then a second press and release.
        let table = Table::standard();
        let rod = table.rods_of(Side::Home).next().unwrap();
        let end = table.rods[rod].half_travel_m();
        let mut f = Flow::new(&table, 0.0);
        let dt = 1.0 / 60.0;
        let mut t = 1.0;
        f.update(t, &still(&table), false);
        let press_and_hold = |f: &mut Flow, t: &mut f64, hold_s: f64| -> Vec<Stage> {
            let mut stages = Vec::new();
            let v = end / 0.1;
            let mut run = |f: &mut Flow, t: &mut f64, slide: f64, v: f64| {
                *t += dt;
                f.update(*t, &rod_at(&table, rod, slide, v), false);
                stages.push(f.stage());
            };
            for k in 1..=6 {
                run(f, t, end * k as f64 / 6.0, v);
            }
            for _ in 0..(hold_s / dt) as usize {
                run(f, t, end, 0.0);
            }
            for k in (0..6).rev() {
                run(f, t, end * k as f64 / 6.0, -v);
            }
            for _ in 0..30 {
                run(f, t, 0.0, 0.0);
            }
            stages
        };
        let stages = press_and_hold(&mut f, &mut t, 2.0);
        assert_eq!(f.stage(), Stage::CharacterSelect, "{stages:?}");
        assert!(!stages.contains(&Stage::Playing));
        // The second press (a short one) starts the match.
        press_and_hold(&mut f, &mut t, 0.1);
        assert_eq!(f.stage(), Stage::Playing);
    }

    #[test]
    fn a_spin_is_one_step_at_any_speed() {
        let table = Table::standard();
        let rod = table.rods_of(Side::Away).next().unwrap();
        for turns_per_s in [1.0, 5.0, 20.0, 60.0] {
            let mut g = Gestures::default();
            g.reset(&still(&table));
            let w = turns_per_s * std::f64::consts::TAU;
            // A spin of 0.8 s at that speed seen at 60 frames per second, then still.
            let mut spins = 0;
            let mut angle = 0.0;
            for k in 0..90 {
                let spinning = k < 48;
                if spinning {
                    angle += w / 60.0;
                }
                let r = inputs(&table, |i| RodState {
                    angle_rad: if i == rod { angle } else { 0.0 },
                    angular_velocity_rad_per_s: if i == rod && spinning { w } else { 0.0 },
                    ..RodState::default()
                });
                spins += g
                    .observe(&r)
                    .iter()
                    .filter(|x| **x == Gesture::Spin(rod))
                    .count();
            }
            assert_eq!(spins, 1, "{turns_per_s} turns/s");
        }
    }
}
