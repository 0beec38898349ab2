//! A play session in the page, without the page: the board, the screens, the match run
//! ahead by the frame's elapsed time in fixed 1 ms steps, and what each frame shows,
//! plays and sends. The browser glue calls [`WebSession::frame`] once per animation
//! frame with the clock; tests call it with any clock they like.
//!
//! It is the desktop's session (`space-foosball play`) on one thread: the screens are
//! the desktop's own [`crate::flow`], the match is [`space_foosball::play::Match`] with
//! the same computer opponent, the board goes through the same
//! [`space_foosball::input::paddles::BoardInput`] tracker, the picture is interpolated
//! between the two newest physics steps as on the desktop, and kicks of a person's rod
//! become haptic OUT reports. A lost board pauses play (match time stops) and shows the
//! board-lost screen; when reports flow again, play resumes.
//!
//! Calibration mode is the desktop's too ([`crate::calibrate::Calibrator`]): C at the
//! attract screen stops the match and guides the player through each rod's motion,
//! reading the board's raw counts; the fits are used at once and kept in a
//! [`CalibrationStore`] (the browser's `localStorage` on the page), from which the next
//! visit loads them.

use crate::board::BrowserBoard;
use crate::calibrate::Calibrator;
use crate::calibration_store::{self, CalibrationStore};
use crate::flow::{Action, Flow, Stage};
use crate::keyboard::KeyboardBoard;
use crate::stepper::Stepper;
use board_link::Board;
use foosball_audio::Sound;
use foosball_render::{FrameSnapshot, Hud, Screen};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{
    BoardInput, InputHealth, PaddleTracker, RodInputs, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS,
};
use space_foosball::play::{KickHaptics, Match, MatchConfig, MatchSnapshot, RodController};
use space_foosball::rules::{Phase, TimedEvent};
use space_foosball::table::{CharacterType, Table};
use space_foosball_front::frame::{self, HudState};
use space_foosball_front::match_scene::MatchScene;

/// The most reports one physics step takes from the board (a backlog after a stall).
const REPORTS_PER_STEP: usize = 32;
/// How long a notice (calibration saved, or not used) stays on screen, s.
const NOTICE_S: f64 = 6.0;

/// What one frame shows and plays.
#[derive(Debug, Clone)]
pub struct FrameOut {
    /// The scene, between the two newest physics steps.
    pub snapshot: FrameSnapshot,
    /// The screen over it.
    pub screen: Screen,
    /// Live text.
    pub hud: Hud,
    /// Sounds to start now.
    pub sounds: Vec<Sound>,
    /// The stage of the screens.
    pub stage: Stage,
    /// Match time of the newest physics step, s.
    pub match_time_s: f64,
    /// Whether the match is paused (board lost or the player paused).
    pub paused: bool,
    /// The board's input health.
    pub health: InputHealth,
    /// Physics steps run for this frame.
    pub steps: u32,
}

/// Where the board's reports come from.
enum Source {
    /// The page's emulated board (keyboard and mouse).
    Keyboard(Box<KeyboardBoard>),
    /// A device (WebHID): the page pushes its reports into the board.
    Device,
}

/// Counts over the session, for the page's status line and the tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Physics steps run.
    pub steps: u64,
    /// Physics steps dropped because frames came too late.
    pub dropped_steps: u64,
    /// Kick events of the running matches.
    pub kicks: u64,
    /// Goals of the running matches.
    pub goals: u64,
}

/// A play session. See the [module](self).
pub struct WebSession {
    table: Table,
    input: BoardInput<BrowserBoard>,
    board_name: String,
    source: Source,
    latest: RodInputs,
    game: Match,
    snapshots: (MatchSnapshot, MatchSnapshot),
    stepper: Stepper,
    /// 1 ms steps of the schedule so far, paused ones included.
    ticks: u64,
    /// The match as the frames draw it.
    scene: MatchScene,
    controllers: [RodController; 2],
    haptics: Option<KickHaptics>,
    flow: Flow,
    pending: Vec<TimedEvent>,
    user_paused: bool,
    seed: u64,
    key_hints: Vec<String>,
    counters: Counters,
    /// Calibration mode, while it runs.
    calibrator: Option<Calibrator>,
    /// The calibration the tracker reads the board through.
    calibration: Calibration,
    /// Where fitted calibrations are kept (none: used, not kept).
    store: Option<Box<dyn CalibrationStore>>,
    /// A message for the screen, and until when (the frames' clock, s; none: from the
    /// next frame on for [`NOTICE_S`]).
    notice: Option<(String, Option<f64>)>,
    /// The table at rest (shown behind calibration, where no match runs).
    rest: MatchSnapshot,
    /// The clock of the newest frame, s.
    now_s: f64,
}

/// The tracker of `table`'s rods read through `calibration`, predicting the pose
/// between mouse packets as on the desktop.
fn predicting_tracker(table: &Table, calibration: Calibration) -> PaddleTracker {
    let mut tracker = PaddleTracker::new(table, calibration);
    tracker.set_prediction_ms(MOUSE_PACKET_PREDICTION_MS);
    tracker.set_prediction_lead_ms(PS2_WIRE_LEAD_MS);
    tracker
}

fn board_input(
    board: BrowserBoard,
    table: &Table,
    calibration: Calibration,
) -> BoardInput<BrowserBoard> {
    let mut input = BoardInput::new(board, table, calibration);
    *input.tracker_mut() = predicting_tracker(table, calibration);
    input
}

impl WebSession {
    /// A session for `table` on the page's emulated board (keyboard and mouse), at the
    /// attract screen with the computer playing itself; `seed` is the first match's.
    pub fn new(table: Table, seed: u64) -> anyhow::Result<WebSession> {
        let board_name = "emulated (keyboard and mouse)".to_string();
        let mut board = BrowserBoard::new(board_name.clone());
        board.set_connected(true);
        let input = board_input(board, &table, Calibration::default());
        let latest = input.tracker().inputs();
        let mut config = MatchConfig::computer_vs_computer(table.clone(), seed);
        config.record_inputs = false;
        let game = Match::new(config)?;
        let snap = game.snapshot();
        let rest = snap.clone();
        Ok(WebSession {
            flow: Flow::new(&table, 0.0),
            scene: MatchScene::new(&table),
            controllers: [RodController::Computer; 2],
            source: Source::Keyboard(Box::new(KeyboardBoard::new(&table))),
            input,
            board_name,
            latest,
            game,
            snapshots: (snap.clone(), snap),
            stepper: Stepper::new(),
            ticks: 0,
            table,
            haptics: None,
            pending: Vec::new(),
            user_paused: false,
            seed: seed.wrapping_add(1),
            key_hints: vec![
                "1-4 ROD  MOUSE/W/S SLIDE  MOUSE/A/D/WHEEL SPIN  SPACE KICK".into(),
                "ENTER PUSH  TAB OTHER TEAM  C CALIBRATE  ESC PAUSE".into(),
            ],
            counters: Counters::default(),
            calibrator: None,
            calibration: Calibration::default(),
            store: None,
            notice: None,
            rest,
            now_s: 0.0,
        })
    }

    /// Keeps calibrations in `store` from now on, and reads the board through the one
    /// stored there. One that cannot be used leaves the defaults in use, says so on
    /// screen and is returned (the page logs it); the stored text is left as it is until
    /// the next calibration replaces it.
    pub fn use_calibration_store(
        &mut self,
        store: Box<dyn CalibrationStore>,
    ) -> Result<(), space_foosball::input::calibration::CalibrationError> {
        let loaded = calibration_store::load(store.as_ref());
        self.store = Some(store);
        match loaded {
            Ok(Some(c)) => {
                self.set_calibration(c);
                Ok(())
            }
            Ok(None) => Ok(()),
            Err(e) => {
                self.set_calibration(Calibration::default());
                self.notice = Some((
                    format!("CALIBRATION NOT USED ({e}); USING THE DEFAULTS"),
                    None,
                ));
                Err(e)
            }
        }
    }

    /// The calibration the board is read through.
    pub fn calibration(&self) -> &Calibration {
        &self.calibration
    }

    /// Reads the board through `calibration` from now on (the rods start from centre).
    fn set_calibration(&mut self, calibration: Calibration) {
        self.calibration = calibration;
        *self.input.tracker_mut() = predicting_tracker(&self.table, calibration);
        self.latest = self.input.tracker().inputs();
    }

    /// Enters calibration mode (from the attract screen; elsewhere nothing happens): the
    /// match stops, the guided motion starts with rod 1.
    pub fn start_calibration(&mut self) {
        if self.flow.stage() != Stage::Attract {
            return;
        }
        self.calibrator = Some(Calibrator::new(&self.table, self.calibration));
        self.flow.enter(Stage::Calibration, self.now_s);
    }

    /// The table rod calibration mode is asking for, if calibrating.
    pub fn calibration_rod(&self) -> Option<usize> {
        self.calibrator.as_ref().and_then(Calibrator::rod)
    }

    /// Uses `fitted` from now on and keeps it in the store; returns what the screen
    /// says about it.
    fn use_calibration(&mut self, fitted: Calibration) -> String {
        self.set_calibration(fitted);
        let msg = match &mut self.store {
            Some(store) => calibration_store::save(store.as_mut(), &fitted),
            None => "CALIBRATION IN USE (NOT SAVED)".into(),
        };
        self.notice = Some((msg.clone(), None));
        msg
    }

    /// Once every rod is done: the fits are used and kept at once, and the calibration
    /// screen says where.
    fn save_when_done(&mut self) {
        let Some(fitted) = self.calibrator.as_ref().and_then(Calibrator::fits_to_save) else {
            return;
        };
        let msg = self.use_calibration(fitted);
        if let Some(c) = &mut self.calibrator {
            c.set_saved(msg);
        }
    }

    /// Leaves calibration mode: good fits not yet kept are used from now on and kept;
    /// back to the attract screen.
    fn finish_calibration(&mut self) -> anyhow::Result<()> {
        let leaving = self.calibrator.take();
        if let Some(fitted) = leaving.and_then(|c| c.fits_on_leaving(&self.calibration)) {
            self.use_calibration(fitted);
        }
        self.flow.enter(Stage::Attract, self.now_s);
        self.start_attract()
    }

    /// The keyboard's emulated board, while no device is in use.
    pub fn keyboard(&mut self) -> Option<&mut KeyboardBoard> {
        match &mut self.source {
            Source::Keyboard(k) => Some(k),
            Source::Device => None,
        }
    }

    /// Switches to a device's reports (WebHID): from now on only
    /// [`WebSession::device_report`] moves the rods; the board starts connected, named
    /// `name`. The tracker starts afresh (rods centred).
    pub fn use_device(&mut self, name: &str) {
        let mut board = BrowserBoard::new(name);
        board.set_connected(true);
        self.input = board_input(board, &self.table, self.calibration);
        self.board_name = name.to_string();
        self.source = Source::Device;
        self.key_hints = vec!["C CALIBRATE  ESC PAUSE".into()];
    }

    /// Whether a device (not the keyboard) drives the rods.
    pub fn uses_device(&self) -> bool {
        matches!(self.source, Source::Device)
    }

    /// One IN report's bytes from the device, as received. Ignored on the keyboard's
    /// board.
    pub fn device_report(&mut self, bytes: &[u8]) {
        if self.uses_device() {
            self.input.board_mut().push_report(bytes);
        }
    }

    /// The device was opened again (`true`) or is gone (`false`): gone, the match
    /// pauses and the board-lost screen shows.
    pub fn device_connected(&mut self, connected: bool) {
        if self.uses_device() {
            self.input.board_mut().set_connected(connected);
        }
    }

    /// The next OUT report (haptics) for the page to send to the device, encoded.
    pub fn take_out_report(&mut self) -> Option<[u8; foosball_protocol::OUT_REPORT_LEN]> {
        self.input.board_mut().take_out_report()
    }

    /// The board's name.
    pub fn board_name(&self) -> &str {
        &self.board_name
    }

    /// The board's link counters.
    pub fn link_stats(&mut self) -> board_link::LinkStats {
        self.input.board_mut().stats()
    }

    /// OUT reports handed to the page so far.
    pub fn out_reports(&mut self) -> u64 {
        self.input.board_mut().out_reports()
    }

    /// The session's simulated clock, s: its 1 ms steps so far, paused ones included
    /// (scripted keys run on it).
    pub fn clock_s(&self) -> f64 {
        self.ticks as f64 * crate::stepper::STEP_S
    }

    /// The session's counters.
    pub fn counters(&self) -> Counters {
        Counters {
            dropped_steps: self.stepper.dropped(),
            ..self.counters
        }
    }

    /// The newest rod inputs (table frame, after calibration).
    pub fn rod_inputs(&self) -> &RodInputs {
        &self.latest
    }

    /// The newest physics step.
    pub fn newest(&self) -> &MatchSnapshot {
        &self.snapshots.1
    }

    /// Who plays each team in the current match, `[home, away]`.
    pub fn controllers(&self) -> [RodController; 2] {
        self.controllers
    }

    /// The current stage.
    pub fn stage(&self) -> Stage {
        self.flow.stage()
    }

    /// Whether the player paused.
    pub fn user_paused(&self) -> bool {
        self.user_paused
    }

    /// Pauses or resumes the match on the player's request.
    pub fn set_user_paused(&mut self, paused: bool) {
        self.user_paused = paused && self.flow.stage() == Stage::Playing;
    }

    /// Esc: leaves calibration mode (keeping its good fits), pauses a running match,
    /// resumes a paused one.
    pub fn escape(&mut self) -> anyhow::Result<()> {
        if self.flow.stage() == Stage::Calibration {
            return self.finish_calibration();
        }
        let paused = self.user_paused;
        self.set_user_paused(!paused);
        Ok(())
    }

    fn run_match(&mut self, config: MatchConfig) -> anyhow::Result<()> {
        self.scene.restart(&config.table);
        self.controllers = config.controllers;
        self.haptics = config
            .controllers
            .contains(&RodController::Player)
            .then(|| KickHaptics::new(&config.table, config.controllers));
        self.game = Match::new(config)?;
        let snap = self.game.snapshot();
        self.snapshots = (snap.clone(), snap);
        self.pending.clear();
        self.user_paused = false;
        self.seed = self.seed.wrapping_add(1);
        Ok(())
    }

    fn start_attract(&mut self) -> anyhow::Result<()> {
        let mut config = MatchConfig::computer_vs_computer(self.table.clone(), self.seed);
        config.record_inputs = false;
        self.run_match(config)
    }

    fn start_match(
        &mut self,
        characters: [CharacterType; 2],
        controllers: [RodController; 2],
    ) -> anyhow::Result<()> {
        let mut table = self.table.clone();
        for (team, c) in table.teams.iter_mut().zip(characters) {
            if team.character != c {
                team.character = c;
                team.params = None;
            }
        }
        let mut config = MatchConfig::player_vs_computer(table, self.seed);
        config.controllers = controllers;
        config.record_inputs = false;
        self.run_match(config)
    }

    /// Runs the physics steps due at `now_s`: each takes the board's reports of its
    /// millisecond (the keyboard's board makes one), then steps the match unless play
    /// is paused (by the player, or because the board is lost). In calibration mode
    /// the reports go to the calibrator and no match runs.
    fn step_physics(&mut self, now_s: f64) -> u32 {
        let steps = self.stepper.due(now_s);
        self.ticks += u64::from(steps);
        for _ in 0..steps {
            if let Source::Keyboard(k) = &mut self.source {
                let report = k.step_report().to_bytes();
                self.input.board_mut().push_report(&report);
            }
            if let Some(cal) = &mut self.calibrator {
                self.latest = self.input.poll_each(REPORTS_PER_STEP, |r| cal.push(r));
                continue;
            }
            self.latest = self.input.poll(REPORTS_PER_STEP);
            let lost = self.latest.health == InputHealth::BoardLost;
            if self.user_paused || lost || self.game.phase() == Phase::Over {
                let newest = &mut self.snapshots.1;
                newest.paused = self.user_paused || lost;
                newest.input_health = self.latest.health;
                self.snapshots.0 = newest.clone();
                continue;
            }
            let events = self.game.step(&self.latest);
            let newest = self.game.snapshot();
            self.snapshots.0 = std::mem::replace(&mut self.snapshots.1, newest);
            self.pending.extend(events);
            self.counters.steps += 1;
        }
        steps
    }

    /// Advances the physics to `now_s` (seconds on a monotonic clock) and the screens:
    /// what to draw, play and send now.
    pub fn frame(&mut self, now_s: f64) -> anyhow::Result<FrameOut> {
        self.now_s = now_s;
        let steps = self.step_physics(now_s);
        self.save_when_done();
        if let Some((_, until @ None)) = &mut self.notice {
            *until = Some(now_s + NOTICE_S);
        }
        let rods = self.latest.clone();
        let over = self.game.phase() == Phase::Over;
        let mut sounds = Vec::new();
        let stage_before = self.flow.stage();
        for action in self.flow.update(now_s, &rods, over) {
            match action {
                Action::Sound(s) => sounds.push(s),
                Action::StartMatch {
                    characters,
                    controllers,
                } => self.start_match(characters, controllers)?,
                Action::StartAttract => self.start_attract()?,
            }
        }
        let stage = self.flow.stage();
        if stage == Stage::Playing && self.user_paused && frame::rods_pushed(&rods) {
            self.user_paused = false;
        }
        let (prev, newest) = if stage == Stage::Calibration {
            (self.rest.clone(), self.rest.clone())
        } else {
            self.snapshots.clone()
        };
        let drained = std::mem::take(&mut self.pending);
        self.take_events(&drained, &newest, now_s, &mut sounds);
        frame::keep_match_sounds_in_play(stage, stage_before, &mut sounds);
        let mut snapshot = self.scene.interpolated(&prev, &newest);
        frame::mark_table(&mut snapshot, stage, &self.flow, self.calibration_rod());
        let lost = rods.health == InputHealth::BoardLost;
        let screen = frame::screen(stage, lost, self.scene.goal_ceremony(now_s));
        let hud = self.hud(stage, lost, now_s);
        Ok(FrameOut {
            snapshot,
            screen,
            hud,
            sounds,
            stage,
            match_time_s: newest.time_s,
            paused: newest.paused || self.user_paused,
            health: rods.health,
            steps,
        })
    }

    fn hud(&self, stage: Stage, lost: bool, now: f64) -> Hud {
        frame::hud(&HudState {
            stage,
            lost,
            board_name: self.board_name(),
            flow: &self.flow,
            calibrator: self.calibrator.as_ref(),
            user_paused: self.user_paused,
            paused_heading: "PAUSED\nPUSH A ROD OR ENTER TO RESUME",
            key_hints: &self.key_hints,
            notice: self
                .notice
                .as_ref()
                .filter(|(_, until)| until.is_some_and(|u| now < u) && stage != Stage::Calibration)
                .map(|(msg, _)| msg.as_str()),
            // The page keeps no match history.
            attract_lines: &[],
            now_s: now,
        })
    }

    fn take_events(
        &mut self,
        events: &[TimedEvent],
        newest: &MatchSnapshot,
        now_s: f64,
        sounds: &mut Vec<Sound>,
    ) {
        let counts = self.scene.take_events(events, newest, now_s, sounds);
        self.counters.kicks += counts.kicks;
        self.counters.goals += counts.goals;
        // Haptics: a person's kicks pulse their paddle.
        if let Some(h) = &mut self.haptics {
            for report in h.reports(events) {
                // A lost board drops the pulse.
                let _ = self.input.board_mut().send(&report);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controls::Key;
    use foosball_protocol::{InReport, OutReport};
    use space_foosball::side::Side;

    /// Frames about every 16 ms from `from_s` to `until_s`; returns the last.
    fn frames(s: &mut WebSession, from_s: f64, until_s: f64) -> FrameOut {
        let n = ((until_s - from_s) / 0.016).ceil().max(0.0) as u32;
        let mut last = s.frame(from_s).unwrap();
        for i in 1..=n {
            last = s
                .frame(from_s + (until_s - from_s) * f64::from(i) / f64::from(n))
                .unwrap();
        }
        last
    }

    fn reports(first: u16, ms: u16, moves: &[(usize, i16, i16)]) -> Vec<[u8; 43]> {
        (0..ms)
            .map(|i| {
                let mut r = InReport::all_present(first.wrapping_add(i));
                for &(port, axial, rotation) in moves {
                    r.paddles[port].axial = axial;
                    r.paddles[port].rotation = rotation;
                }
                r.to_bytes()
            })
            .collect()
    }

    /// A board's sensor on `port` whose counts are off by `gain` (1.04: 4 % more counts
    /// than the nominal map), reporting a paddle's motion to a session.
    struct Sensor {
        port: usize,
        gain: f64,
        seq: u16,
        sent: [f64; 2],
        pose: [f64; 2],
    }

    impl Sensor {
        /// Moves the paddle to `pose` (paddle frame) in 100 ms, then holds it still a
        /// while; the reports go through the page's path, 200 at a time, each batch
        /// taken by the frames of the next 0.1 s.
        fn go(&mut self, s: &mut WebSession, t: &mut f64, pose: [f64; 2]) {
            use space_foosball::input::calibration::PaddleCalibration;
            use space_foosball::input::guided::HOLD_MS;
            let nominal = PaddleCalibration::default();
            let start = self.pose;
            let mut out = Vec::new();
            for i in 1..=100 {
                let f = f64::from(i) / 100.0;
                let p = [
                    start[0] + (pose[0] - start[0]) * f,
                    start[1] + (pose[1] - start[1]) * f,
                ];
                let want = nominal.counts_for(p).unwrap().map(|c| c * self.gain);
                let d = [
                    (want[0] - self.sent[0]).round(),
                    (want[1] - self.sent[1]).round(),
                ];
                self.sent = [self.sent[0] + d[0], self.sent[1] + d[1]];
                out.push([d[0] as i16, d[1] as i16]);
            }
            out.extend(std::iter::repeat_n([0, 0], HOLD_MS as usize + 50));
            self.pose = pose;
            for chunk in out.chunks(200) {
                for counts in chunk {
                    let mut r = InReport::all_present(self.seq);
                    self.seq = self.seq.wrapping_add(1);
                    r.paddles[self.port].axial = counts[0];
                    r.paddles[self.port].rotation = counts[1];
                    s.device_report(&r.to_bytes());
                }
                frames(s, *t, *t + 0.1);
                *t += 0.1;
            }
        }
    }

    #[test]
    fn calibration_mode_fits_every_rod_keeps_the_fits_and_the_next_visit_reads_them() {
        use crate::calibration_store::memory::MemoryStore;
        use crate::calibration_store::STORAGE_KEY;
        let table = Table::standard();
        let store = MemoryStore::default();
        let mut s = WebSession::new(table.clone(), 7).unwrap();
        s.use_calibration_store(Box::new(store.clone())).unwrap();
        s.use_device("WebHID test board");
        let mut t = 0.0;
        frames(&mut s, t, t + 0.5);
        t += 0.5;
        // Only the attract screen starts calibration; then the match stands still.
        s.start_calibration();
        let out = frames(&mut s, t, t + 0.1);
        t += 0.1;
        assert_eq!(out.stage, Stage::Calibration);
        assert_eq!(out.screen, Screen::Calibration);
        assert!(out.hud.heading.starts_with("ROD 1 OF 8"), "{:?}", out.hud);
        assert_eq!(out.snapshot.held_rods, vec![0]);
        let gain = |port: usize| 1.02 + 0.01 * port as f64;
        for (i, rod) in table.rods.iter().enumerate() {
            assert_eq!(s.calibration_rod(), Some(i));
            let mut sensor = Sensor {
                port: rod.port,
                gain: gain(rod.port),
                seq: 0,
                sent: [0.0; 2],
                pose: [0.0; 2],
            };
            sensor.go(&mut s, &mut t, [0.03, 0.0]);
            let motion = space_foosball::input::guided::GuidedMotion::standard(
                rod.travel_m,
                crate::calibrate::TURNS,
            );
            for step in &motion.steps {
                sensor.go(&mut s, &mut t, step.pose);
            }
        }
        let done = frames(&mut s, t, t + 0.1);
        t += 0.1;
        assert_eq!(s.calibration_rod(), None);
        assert!(
            done.hud.heading.contains("CALIBRATION SAVED IN TEST STORE"),
            "{:?}",
            done.hud
        );
        // The fits undo each sensor's gain: 1 / gain of the nominal map, within 1 %.
        let nominal = space_foosball::input::calibration::PaddleCalibration::default();
        let check = |c: &Calibration| {
            for rod in &table.rods {
                let m = c.paddles[rod.port].matrix;
                for axis in 0..2 {
                    let ratio = m[axis][axis] / nominal.matrix[axis][axis] * gain(rod.port);
                    assert!((ratio - 1.0).abs() < 0.01, "port {}: {m:?}", rod.port);
                }
            }
        };
        check(s.calibration());
        let kept = store.text.borrow().clone().expect("kept in the store");
        check(&Calibration::from_json(&kept, STORAGE_KEY).unwrap());
        // Esc goes back to the attract match; the next visit reads the board through it.
        s.escape().unwrap();
        let back = frames(&mut s, t, t + 0.5);
        assert_eq!(back.stage, Stage::Attract);
        assert!(back.match_time_s > 0.3, "{}", back.match_time_s);
        let mut next = WebSession::new(table.clone(), 8).unwrap();
        next.use_calibration_store(Box::new(store.clone())).unwrap();
        assert_eq!(next.calibration(), s.calibration());
    }

    #[test]
    fn a_stored_calibration_that_cannot_be_used_leaves_the_defaults_and_says_why() {
        use crate::calibration_store::memory::MemoryStore;
        let store = MemoryStore::default();
        *store.text.borrow_mut() = Some("{\"format\": \"space-foosball-calibration\"".into());
        let mut s = WebSession::new(Table::standard(), 3).unwrap();
        let e = s
            .use_calibration_store(Box::new(store.clone()))
            .unwrap_err();
        assert!(e.to_string().contains("test store"), "{e}");
        assert_eq!(*s.calibration(), Calibration::default());
        let out = frames(&mut s, 0.0, 0.2);
        assert!(
            out.hud
                .lines
                .iter()
                .any(|l| l.starts_with("CALIBRATION NOT USED")),
            "{:?}",
            out.hud
        );
        // Nothing was written over it.
        assert!(store
            .text
            .borrow()
            .as_deref()
            .unwrap()
            .ends_with("calibration\""));
        // Calibration does not start from a match.
        let mut s = WebSession::new(Table::standard(), 3).unwrap();
        for (at, pressed) in [(1.0, true), (1.2, false), (2.0, true), (2.2, false)] {
            s.keyboard().unwrap().key(Key::Push, pressed);
            frames(&mut s, at, at + 0.2);
        }
        frames(&mut s, 2.6, 2.7);
        s.start_calibration();
        assert_eq!(frames(&mut s, 2.7, 2.8).stage, Stage::Playing);
    }

    #[test]
    fn the_keyboard_starts_a_match_and_the_physics_keeps_to_the_clock() {
        let mut s = WebSession::new(Table::standard(), 3).unwrap();
        let out = frames(&mut s, 0.0, 0.9);
        assert_eq!(out.screen, Screen::Attract);
        assert_eq!(out.health, InputHealth::Live);
        for (at, pressed) in [(1.0, true), (1.2, false), (2.0, true), (2.2, false)] {
            s.keyboard().unwrap().key(Key::Push, pressed);
            frames(&mut s, at, at + 0.2);
        }
        let started = frames(&mut s, 2.6, 2.6);
        assert_eq!(started.stage, Stage::Playing);
        assert_eq!(
            s.controllers(),
            [RodController::Player, RodController::Computer]
        );
        // One second of frames is one second of match time, in whole steps.
        let t0 = started.match_time_s;
        let later = frames(&mut s, 2.6, 3.6);
        let ran = later.match_time_s - t0;
        assert!((ran - 1.0).abs() <= 0.0021, "{ran} s of match time");
        // The keyboard's kick turns the rod in physics.
        let rod = s.keyboard().unwrap().keyboard_rod().unwrap();
        let before = s.newest().rods[rod].angle_rad;
        s.keyboard().unwrap().key(Key::Kick, true);
        frames(&mut s, 3.6, 4.0);
        let turned = s.newest().rods[rod].angle_rad - before;
        let forward = -Side::Home.attack_dir();
        assert!(turned * forward > 3.0, "turned {turned} rad");
        // Esc pauses: match time stands still.
        s.escape().unwrap();
        let paused = frames(&mut s, 4.0, 4.1);
        assert!(paused.paused);
        let still = frames(&mut s, 4.1, 4.5);
        assert_eq!(still.match_time_s, paused.match_time_s);
    }

    /// A software renderer's cold start: frames 1.5 s apart (each runs the most steps a
    /// frame may, 100 ms). The `start` script on the session's clock still holds each key
    /// for the match time it says, so the pushes start a match and the slide moves the rod.
    #[test]
    fn the_start_script_on_the_session_clock_survives_slow_frames() {
        let table = Table::standard();
        let mut s = WebSession::new(table.clone(), 3).unwrap();
        let mut script: crate::script::Script = "start".parse().unwrap();
        let mut wall = 0.0;
        while s.clock_s() < 6.0 {
            for (code, pressed) in script.due(s.clock_s()) {
                if let (Some(k), Some(kb)) = (code.and_then(crate::controls::map_key), s.keyboard())
                {
                    kb.key(k, pressed);
                }
            }
            s.frame(wall).unwrap();
            wall += 1.5;
        }
        assert_eq!(s.stage(), Stage::Playing);
        assert_eq!(
            s.controllers(),
            [RodController::Player, RodController::Computer]
        );
        // The script ends with the keeper slid 0.4 s at the key's speed away from its
        // player, at least 0.1 s of it held (a frame's steps either side).
        let keeper = table.rods_of(Side::Home).next().unwrap();
        let slide = s.rod_inputs().rods[keeper].slide_m;
        assert!(slide > 0.03, "the keeper slid {slide} m");
    }

    #[test]
    fn a_device_plays_a_match_a_kick_pulses_it_and_losing_it_pauses() {
        let table = Table::standard();
        let mut s = WebSession::new(table.clone(), 5).unwrap();
        s.use_device("WebHID test board");
        assert!(s.keyboard().is_none());
        let keeper = table.rods_of(Side::Home).next().unwrap();
        let port = table.rods[keeper].port;
        let mut t = 0.0;
        let mut seq = 0u16;
        // Out and back twice, 60 mm at 0.5 m/s, each followed by 100 still reports (a
        // board reports every millisecond, moving or not).
        for _ in 0..2 {
            frames(&mut s, t, t + 0.9);
            for r in reports(seq, 120, &[(port, 4, 0)]) {
                s.device_report(&r);
            }
            for r in reports(seq + 120, 100, &[]) {
                s.device_report(&r);
            }
            frames(&mut s, t + 0.9, t + 1.4);
            for r in reports(seq + 220, 120, &[(port, -4, 0)]) {
                s.device_report(&r);
            }
            for r in reports(seq + 340, 100, &[]) {
                s.device_report(&r);
            }
            seq += 440;
            t += 1.8;
            frames(&mut s, t - 0.4, t);
        }
        assert_eq!(s.stage(), Stage::Playing);
        assert_eq!(s.controllers()[0], RodController::Player);
        // Every Home rod spins until one kicks: a haptic OUT report on its port.
        let home: Vec<usize> = table
            .rods_of(Side::Home)
            .map(|r| table.rods[r].port)
            .collect();
        let spin: Vec<(usize, i16, i16)> = home.iter().map(|&p| (p, 0, 2)).collect();
        let out = loop {
            for r in reports(seq, 100, &spin) {
                s.device_report(&r);
            }
            seq = seq.wrapping_add(100);
            frames(&mut s, t, t + 0.1);
            t += 0.1;
            if let Some(bytes) = s.take_out_report() {
                break OutReport::decode(&bytes).unwrap();
            }
            assert!(t < 120.0, "no kick in 120 s: {:?}", s.counters());
        };
        let pulsed: Vec<usize> = (0..8).filter(|&p| out.haptics[p].duration_ms > 0).collect();
        assert!(!pulsed.is_empty() && pulsed.iter().all(|p| home.contains(p)));
        // Unplugged: the board-lost screen, match time stands still; back: it runs.
        s.device_connected(false);
        let lost = frames(&mut s, t, t + 0.1);
        assert_eq!(lost.screen, Screen::BoardLost);
        assert!(lost.paused);
        let still = frames(&mut s, t + 0.1, t + 0.6);
        assert_eq!(still.match_time_s, lost.match_time_s);
        s.device_connected(true);
        for r in reports(seq, 20, &[]) {
            s.device_report(&r);
        }
        let back = frames(&mut s, t + 0.6, t + 1.0);
        assert!(!back.paused);
        assert!(back.match_time_s > still.match_time_s);
    }
}
