//! A play session without the window: the board, the screens, the match on its physics
//! thread, and what each frame shows and sounds. The window ([`super::run`]) calls
//! [`Session::frame`] once per frame and draws the result; tests drive it directly.
//!
//! * **Input.** The board's reports go through one [`BoardInput`]. While a match runs,
//!   its physics thread polls it once per step (1 kHz) and leaves the newest rod inputs
//!   for the screens; when no match runs, the frame polls it. Calibration reads the raw
//!   reports instead (the guided collector needs the counts).
//! * **Snapshots.** The frame reads the two newest physics snapshots and interpolates
//!   ([`FrameSnapshot::at_time`]); a slow frame never slows physics, which keeps its own
//!   1 kHz schedule.
//! * **Events.** Kicks, bounces and goals drained from the physics thread become
//!   particles ([`RenderEvent`] at the ball's position), sounds, and (kicks of a person's
//!   rod) haptic OUT reports to the board.
//! * **Board lost.** When the board's link goes down, the physics thread pauses by itself
//!   (match time stops) and the frame shows the board-lost screen; when reports flow
//!   again, play resumes.

use super::calibrate::Calibrator;
use super::flow::{Action, Flow, Stage};
use crate::history::played::{attract_lines, keep_in_background, PlayedMatch};
use crate::history::MatchRecord;
use board_link::{Board, BoardError, LinkState, LinkStats};
use foosball_audio::Sound;
use foosball_protocol::{InReport, OutReport};
use foosball_render::{FrameSnapshot, Hud, Screen};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{
    BoardInput, InputHealth, RodInputs, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS,
};
use space_foosball::play::{
    KickHaptics, Match, MatchConfig, MatchSnapshot, PhysicsThread, RodController,
};
use space_foosball::rules::{Phase, TimedEvent};
use space_foosball::table::{CharacterType, Table};
use space_foosball_front::frame::{self, HudState};
use space_foosball_front::match_scene::MatchScene;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

pub use space_foosball_front::match_scene::QUIET_BOUNCE_M_S;

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // Plain data: a panic elsewhere cannot leave it half-updated.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// One board shared by the input tracker, calibration and haptics.
#[derive(Clone)]
pub struct SharedBoard(Arc<Mutex<Box<dyn Board>>>);

impl SharedBoard {
    /// Shares `board`.
    pub fn new(board: Box<dyn Board>) -> Self {
        Self(Arc::new(Mutex::new(board)))
    }
}

impl Board for SharedBoard {
    fn name(&self) -> String {
        lock(&self.0).name()
    }
    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError> {
        lock(&self.0).poll_report(timeout)
    }
    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        lock(&self.0).send(report)
    }
    fn link_state(&self) -> LinkState {
        lock(&self.0).link_state()
    }
    fn stats(&self) -> LinkStats {
        lock(&self.0).stats()
    }
}

/// What one frame shows and plays.
#[derive(Debug, Clone)]
pub struct FrameOut {
    /// The scene (interpolated between the two newest physics snapshots).
    pub snapshot: FrameSnapshot,
    /// The screen over it.
    pub screen: Screen,
    /// Live text.
    pub hud: Hud,
    /// Sounds to start now.
    pub sounds: Vec<Sound>,
    /// The stage of the screens.
    pub stage: Stage,
    /// Match time of the newest physics snapshot, s.
    pub match_time_s: f64,
    /// Whether the match is paused (board lost or the player paused).
    pub paused: bool,
    /// The board's input health.
    pub health: InputHealth,
}

/// How a session starts.
#[derive(Debug, Clone, Default)]
pub struct SessionOptions {
    /// Seed of the first match (each later match adds one).
    pub seed: u64,
    /// Where calibration mode saves (none: not saved).
    pub calibration_path: Option<PathBuf>,
    /// Key hints shown at the bottom of the screens (the emulated board's keys).
    pub key_hints: Vec<String>,
    /// The match history every finished match goes into (none: not kept).
    pub history_path: Option<PathBuf>,
}

/// A play session. See the [module](self).
pub struct Session {
    table: Table,
    board: SharedBoard,
    input: Arc<Mutex<BoardInput<SharedBoard>>>,
    latest: Arc<Mutex<RodInputs>>,
    physics: Option<PhysicsThread>,
    /// The match as the frames draw it.
    scene: MatchScene,
    controllers: [RodController; 2],
    haptics: Option<KickHaptics>,
    flow: Flow,
    user_paused: bool,
    calibrator: Option<Calibrator>,
    calibration: Calibration,
    options: SessionOptions,
    start: Instant,
    seed: u64,
    notice: Option<(String, f64)>,
    /// The table at rest (shown behind calibration, where no match runs).
    rest: MatchSnapshot,
    /// The match being played, for the history (not the attract screen's).
    played: Option<PlayedMatch>,
    /// A finished match waiting for its recording from the physics thread, to be kept in
    /// the history with its replay.
    ended: Option<MatchRecord>,
    /// The history's lines on the attract screen (top scorers, fastest shot), renewed by
    /// the thread that keeps a finished match.
    attract_lines: Arc<Mutex<Vec<String>>>,
}

/// The board's input tracker with pose prediction between mouse packets (one packet
/// period plus the PS/2 wire time ahead), which brings the input-to-rod latency from
/// about 4.9 ms to about 0.9 ms (`space-foosball bench match`).
fn board_input(
    board: SharedBoard,
    table: &Table,
    calibration: Calibration,
) -> BoardInput<SharedBoard> {
    let mut input = BoardInput::new(board, table, calibration);
    input
        .tracker_mut()
        .set_prediction_ms(MOUSE_PACKET_PREDICTION_MS);
    input.tracker_mut().set_prediction_lead_ms(PS2_WIRE_LEAD_MS);
    input
}

impl Session {
    /// A session on `board` for `table`, starting at the attract screen with the
    /// computer playing itself.
    pub fn new(
        board: Box<dyn Board>,
        table: Table,
        calibration: Calibration,
        options: SessionOptions,
    ) -> anyhow::Result<Session> {
        let board = SharedBoard::new(board);
        let input = board_input(board.clone(), &table, calibration);
        let latest = input.tracker().inputs();
        let rest = Match::new(MatchConfig::computer_vs_computer(table.clone(), 0))?.snapshot();
        let history_path = options.history_path.clone();
        let mut s = Session {
            flow: Flow::new(&table, 0.0),
            scene: MatchScene::new(&table),
            controllers: [RodController::Computer; 2],
            table,
            board,
            input: Arc::new(Mutex::new(input)),
            latest: Arc::new(Mutex::new(latest)),
            physics: None,
            haptics: None,
            user_paused: false,
            calibrator: None,
            calibration,
            seed: options.seed,
            options,
            start: Instant::now(),
            notice: None,
            rest,
            played: None,
            ended: None,
            attract_lines: Arc::new(Mutex::new(
                history_path
                    .as_deref()
                    .map(attract_lines)
                    .unwrap_or_default(),
            )),
        };
        s.start_attract()?;
        Ok(s)
    }

    fn now_s(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// The board's name.
    pub fn board_name(&self) -> String {
        self.board.name()
    }

    /// Who plays each team in the current match, `[home, away]`.
    pub fn controllers(&self) -> [RodController; 2] {
        self.controllers
    }

    /// The current stage.
    pub fn stage(&self) -> Stage {
        self.flow.stage()
    }

    /// The table rod calibration mode is asking for, if calibrating.
    pub fn calibration_rod(&self) -> Option<usize> {
        self.calibrator.as_ref().and_then(Calibrator::rod)
    }

    fn run_match(&mut self, config: MatchConfig) -> anyhow::Result<()> {
        self.keep_ended();
        self.physics = None; // stops and joins the previous match
        self.played = None;
        self.scene.restart(&config.table);
        self.controllers = config.controllers;
        self.haptics = config
            .controllers
            .contains(&RodController::Player)
            .then(|| KickHaptics::new(&config.table, config.controllers));
        let m = Match::new(config)?;
        let input = Arc::clone(&self.input);
        let latest = Arc::clone(&self.latest);
        self.physics = Some(PhysicsThread::spawn(m, move || {
            let inputs = lock(&input).poll(32);
            *lock(&latest) = inputs.clone();
            inputs
        }));
        self.user_paused = false;
        self.seed = self.seed.wrapping_add(1);
        Ok(())
    }

    /// Starts the computer playing itself (the attract screen's background).
    pub fn start_attract(&mut self) -> anyhow::Result<()> {
        let mut config = MatchConfig::computer_vs_computer(self.table.clone(), self.seed);
        // The attract screen may run for hours: no input recording (~7.7 MB per minute).
        config.record_inputs = false;
        self.run_match(config)
    }

    /// Starts a match with `characters` (`[home, away]`) and `controllers` now and
    /// shows it.
    pub fn start_match(
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
        let played = PlayedMatch::new(&config.table, controllers, self.seed);
        self.run_match(config)?;
        self.played = self.options.history_path.is_some().then_some(played);
        let now = self.now_s();
        self.flow.enter(Stage::Playing, now);
        Ok(())
    }

    /// Enters calibration mode: the match stops, the guided motion starts with rod 1.
    pub fn start_calibration(&mut self) {
        self.keep_ended();
        self.physics = None;
        self.played = None;
        self.calibrator = Some(Calibrator::new(&self.table, self.calibration));
        let now = self.now_s();
        self.flow.enter(Stage::Calibration, now);
    }

    /// Uses `fitted` from now on and saves it (written to a temporary file, then renamed,
    /// by [`Calibration::save`]); returns what the screen says about it.
    fn use_calibration(&mut self, fitted: Calibration) -> String {
        self.calibration = fitted;
        *lock(&self.input) = board_input(self.board.clone(), &self.table, fitted);
        let msg = match &self.options.calibration_path {
            Some(path) => match fitted.save(path) {
                Ok(()) => format!("CALIBRATION SAVED TO {}", path.display()),
                Err(e) => format!("CALIBRATION NOT SAVED: {e}"),
            },
            None => "CALIBRATION IN USE (NOT SAVED)".into(),
        };
        self.notice = Some((msg.clone(), self.now_s() + 6.0));
        msg
    }

    /// Once every rod is done: the fits are used and saved at once, and the calibration
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

    /// Leaves calibration mode: good fits not yet saved are used from now on and saved;
    /// back to the attract screen.
    fn finish_calibration(&mut self) -> anyhow::Result<()> {
        let leaving = self.calibrator.take();
        if let Some(fitted) = leaving.and_then(|c| c.fits_on_leaving(&self.calibration)) {
            self.use_calibration(fitted);
        }
        let now = self.now_s();
        self.flow.enter(Stage::Attract, now);
        self.start_attract()
    }

    /// Esc: leaves calibration, pauses or resumes a match; returns `true` when the
    /// player asks to quit (Esc outside a match, or Esc on the paused match).
    pub fn escape(&mut self) -> anyhow::Result<bool> {
        match self.flow.stage() {
            Stage::Calibration => {
                self.finish_calibration()?;
                Ok(false)
            }
            Stage::Playing if !self.user_paused => {
                self.set_user_paused(true);
                Ok(false)
            }
            _ => Ok(true),
        }
    }

    /// Pauses or resumes the match on the player's request.
    pub fn set_user_paused(&mut self, paused: bool) {
        self.user_paused = paused;
        if let Some(p) = &self.physics {
            p.set_paused(paused);
        }
    }

    /// Whether the player paused.
    pub fn user_paused(&self) -> bool {
        self.user_paused
    }

    /// Polls the board on this thread when no physics thread does.
    fn poll_here(&mut self) {
        let running = self.physics.as_ref().is_some_and(PhysicsThread::is_running);
        if let Some(cal) = &mut self.calibrator {
            let mut input = lock(&self.input);
            let inputs = input.poll_each(2000, |r| cal.push(r));
            drop(input);
            *lock(&self.latest) = inputs;
            self.save_when_done();
        } else if !running {
            let inputs = lock(&self.input).poll(2000);
            *lock(&self.latest) = inputs;
        }
    }

    /// The newest rod inputs.
    pub fn rod_inputs(&self) -> RodInputs {
        lock(&self.latest).clone()
    }

    /// Advances the screens and reads the match: what to draw and play now.
    pub fn frame(&mut self) -> anyhow::Result<FrameOut> {
        let now = self.now_s();
        self.poll_here();
        let rods = self.rod_inputs();
        let over = self
            .physics
            .as_ref()
            .is_some_and(|p| p.latest().1.phase == Phase::Over);
        let mut sounds = Vec::new();
        let stage_before = self.flow.stage();
        for action in self.flow.update(now, &rods, over) {
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
            self.set_user_paused(false);
        }
        let (prev, newest) = match &self.physics {
            Some(p) => p.latest(),
            None => (self.rest.clone(), self.rest.clone()),
        };
        let drained = self
            .physics
            .as_ref()
            .map(PhysicsThread::drain_events)
            .unwrap_or_default();
        self.take_events(&drained, &newest, now, &mut sounds);
        self.keep_when_over(&drained);
        frame::keep_match_sounds_in_play(stage, stage_before, &mut sounds);
        let mut snapshot = self.scene.interpolated(&prev, &newest);
        frame::mark_table(&mut snapshot, stage, &self.flow, self.calibration_rod());
        let lost = rods.health == InputHealth::BoardLost;
        let screen = frame::screen(stage, lost, self.scene.goal_ceremony(now));
        let hud = self.hud(stage, lost, now);
        Ok(FrameOut {
            snapshot,
            screen,
            hud,
            sounds,
            stage,
            match_time_s: newest.time_s,
            paused: newest.paused || self.user_paused,
            health: rods.health,
        })
    }

    fn hud(&self, stage: Stage, lost: bool, now: f64) -> Hud {
        let attract_lines = lock(&self.attract_lines).clone();
        frame::hud(&HudState {
            stage,
            lost,
            board_name: &self.board.name(),
            flow: &self.flow,
            calibrator: self.calibrator.as_ref(),
            user_paused: self.user_paused,
            paused_heading: "PAUSED\nPUSH A ROD OR ENTER TO RESUME - ESC TO QUIT",
            key_hints: &self.options.key_hints,
            notice: self
                .notice
                .as_ref()
                .filter(|(_, until)| now < *until)
                .map(|(msg, _)| msg.as_str()),
            attract_lines: &attract_lines,
            now_s: now,
        })
    }

    /// Gathers the played match's kicks; once it is over, keeps it in the history with its
    /// replay, as soon as the physics thread has left the match's recording.
    fn keep_when_over(&mut self, events: &[TimedEvent]) {
        if let Some(record) = self.played.as_mut().and_then(|p| p.take(events)) {
            self.played = None;
            self.ended = Some(record);
        }
        let thread_ended = !self.physics.as_ref().is_some_and(PhysicsThread::is_running);
        if self.ended.is_some() && thread_ended {
            self.keep_ended();
        }
    }

    /// Keeps the finished match waiting for its recording, with the recording where the
    /// physics thread left one (a match left before its end is not kept: it has no record).
    fn keep_ended(&mut self) {
        let Some(record) = self.ended.take() else {
            return;
        };
        let replay = self
            .physics
            .as_ref()
            .and_then(PhysicsThread::take_recording)
            .filter(|r| !r.is_empty());
        if let Some(path) = &self.options.history_path {
            keep_in_background(
                path.clone(),
                record,
                replay,
                Arc::clone(&self.attract_lines),
            );
        }
    }

    fn take_events(
        &mut self,
        events: &[TimedEvent],
        newest: &MatchSnapshot,
        now: f64,
        sounds: &mut Vec<Sound>,
    ) {
        self.scene.take_events(events, newest, now, sounds);
        // Haptics: a person's kicks pulse their paddle.
        if let Some(h) = &mut self.haptics {
            for report in h.reports(events) {
                // A lost board drops the pulse; the link reconnects by itself.
                let _ = self.board.send(&report);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! Unplugging the board mid-match, through the socket emulation: the same server
    //! `sim serve` runs ([`SocketServer`]), on a thread, stopped (its socket closed and
    //! removed) and started again on the same path. (`sim/tests/serve_process.rs` kills
    //! and restarts the real process behind a `SocketBoard`.)

    use super::*;
    use board_link::SocketBoard;
    use foosball_sim::motion::Stationary;
    use foosball_sim::serve::SocketServer;
    use foosball_sim::{BoardConfig, EmulatedBoard};
    use std::path::Path;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::thread::JoinHandle;

    struct Emulator {
        stop: Arc<AtomicBool>,
        thread: Option<JoinHandle<()>>,
    }

    impl Emulator {
        fn start(path: &Path) -> Emulator {
            let mut server = SocketServer::bind(path).expect("bind the emulator's socket");
            let mut board =
                EmulatedBoard::new(BoardConfig::default(), Box::new(Stationary)).unwrap();
            let stop = Arc::new(AtomicBool::new(false));
            let flag = Arc::clone(&stop);
            let thread = std::thread::spawn(move || {
                server.run(&mut board, &flag).expect("serve");
            });
            Emulator {
                stop,
                thread: Some(thread),
            }
        }

        fn unplug(mut self) {
            self.stop.store(true, Ordering::Release);
            if let Some(t) = self.thread.take() {
                t.join().unwrap();
            }
        }
    }

    impl Drop for Emulator {
        fn drop(&mut self) {
            self.stop.store(true, Ordering::Release);
            if let Some(t) = self.thread.take() {
                let _ = t.join();
            }
        }
    }

    /// Runs frames every 5 ms until `done` holds for one (returning it), or panics
    /// after `limit_s` seconds.
    fn frames_until(
        s: &mut Session,
        limit_s: f64,
        what: &str,
        done: impl Fn(&FrameOut) -> bool,
    ) -> FrameOut {
        let start = Instant::now();
        loop {
            let out = s.frame().unwrap();
            if done(&out) {
                return out;
            }
            assert!(
                start.elapsed().as_secs_f64() < limit_s,
                "no {what} within {limit_s} s: stage {:?}, screen {:?}, health {:?}",
                out.stage,
                out.screen,
                out.health
            );
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Frames for `seconds`, each checked by `check`; returns the last.
    fn frames_for(s: &mut Session, seconds: f64, check: impl Fn(&FrameOut)) -> FrameOut {
        let start = Instant::now();
        loop {
            let out = s.frame().unwrap();
            check(&out);
            if start.elapsed().as_secs_f64() >= seconds {
                return out;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn playing(out: &FrameOut) -> bool {
        matches!(out.screen, Screen::Match | Screen::GoalCeremony) && !out.paused
    }

    #[test]
    fn unplugging_the_board_mid_match_pauses_with_a_message_and_reconnecting_resumes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("board.sock");
        let emulator = Emulator::start(&path);
        let mut board = SocketBoard::new(&path);
        board.set_retry_interval(Duration::from_millis(20));
        let table = Table::standard();
        let mut s = Session::new(
            Box::new(board),
            table.clone(),
            Calibration::default(),
            SessionOptions::default(),
        )
        .unwrap();
        frames_until(&mut s, 10.0, "live input", |o| {
            o.health == InputHealth::Live
        });
        let characters = [table.teams[0].character, table.teams[1].character];
        s.start_match(characters, [RodController::Player, RodController::Computer])
            .unwrap();
        // The match runs on the socket board's input.
        let before = frames_for(&mut s, 0.5, |o| {
            assert_eq!(o.stage, Stage::Playing);
            assert!(playing(o), "{:?} paused {}", o.screen, o.paused);
        });
        assert!(before.match_time_s > 0.2, "{}", before.match_time_s);

        // Unplug: the board-lost screen and message, play paused.
        emulator.unplug();
        let lost = frames_until(&mut s, 5.0, "board-lost screen", |o| {
            o.screen == Screen::BoardLost
        });
        assert!(lost.paused);
        assert_eq!(lost.health, InputHealth::BoardLost);
        assert!(
            lost.hud.lines.iter().any(|l| l.starts_with("BOARD:")),
            "{:?}",
            lost.hud
        );
        let t_lost = lost.match_time_s;
        // Match time stands still while the board is away.
        let still = frames_for(&mut s, 0.6, |o| {
            assert_eq!(o.screen, Screen::BoardLost);
            assert!(o.paused);
        });
        assert!(
            (still.match_time_s - t_lost).abs() <= 0.002,
            "match time moved while paused: {t_lost} → {}",
            still.match_time_s
        );

        // Plug it back in: play resumes and match time runs again.
        let _emulator = Emulator::start(&path);
        frames_until(&mut s, 10.0, "resumed play", playing);
        let after = frames_for(&mut s, 0.5, |o| assert!(playing(o), "{:?}", o.screen));
        assert!(
            after.match_time_s > still.match_time_s + 0.2,
            "match time {} → {} after reconnecting",
            still.match_time_s,
            after.match_time_s
        );
        assert_eq!(s.stage(), Stage::Playing);
    }
}
