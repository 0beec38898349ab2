//! The online match's frame loop on GGRS (60 frames a second, 16 or 17 physics steps each).

use super::input::{rod_inputs, SideInput};
use crate::history::record::now_unix_s;
use crate::history::{HistoryStore, MatchRecord, Mode};
use anyhow::{bail, Context, Result};
use foosball_sim::motion::script::MotionScript;
use foosball_sim::motion::MotionSource;
use ggrs::{
    Config, DesyncDetection, GgrsEvent, GgrsRequest, P2PSession, PlayerType, PredictRepeatLast,
    SessionBuilder, SessionState, UdpNonBlockingSocket,
};
use serde::Serialize;
use space_foosball::play::{Match, MatchConfig, RodController, SavedMatch};
use space_foosball::recording::MatchRecording;
use space_foosball::rules::{Event, RulesConfig, TimedEvent};
use space_foosball::side::Side;
use space_foosball::Table;
use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Frames a second: the session's clock (the physics steps at 1 kHz within them).
pub const FPS: u64 = 60;
/// Frames a side may run ahead of the inputs it has: a rollback is at most this long.
pub const MAX_PREDICTION_FRAMES: usize = 8;
/// Frames kept on after the end, so the other side gets the inputs it needs to end too.
const LINGER_FRAMES: u64 = 90;
/// Frames between the checksums the sides compare (desync detection).
const DESYNC_INTERVAL: u32 = 10;
/// Most kicks kept for the history (hours of play).
const MAX_KEPT_EVENTS: usize = 100_000;
/// The longest a session waits for the other side to answer before giving up.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(20);

/// GGRS's types for a foosball match.
pub struct Foosball;

impl Config for Foosball {
    type Input = SideInput;
    type InputPredictor = PredictRepeatLast;
    type State = FrameState;
    type Address = SocketAddr;
}

/// The match saved at the start of a frame.
#[derive(Clone)]
pub struct FrameState {
    saved: SavedMatch,
    frame: i32,
}

/// What drives this side's rods.
pub enum LocalRods {
    /// Held centred and upright.
    Idle,
    /// A motion script (`foosball-sim`'s format), each board port's pose read at the frame's
    /// time as the rod of the table on that port.
    Script(Box<MotionScript>),
}

/// How to play online.
pub struct OnlineOptions {
    /// The team played here (the host plays Home, who joins Away).
    pub side: Side,
    /// The local UDP port.
    pub port: u16,
    /// The other side's address.
    pub remote: SocketAddr,
    /// The table (both sides must use the same).
    pub table: Table,
    /// The match's seed (both sides must use the same).
    pub seed: u64,
    /// Goals that win.
    pub goals: u32,
    /// What drives this side's rods.
    pub rods: LocalRods,
    /// End after this many frames (the match may still be on), if set.
    pub max_frames: Option<u64>,
    /// Frames of input delay.
    pub input_delay: usize,
    /// Save the match's recording here at the end, or where the other side left.
    pub record: Option<PathBuf>,
    /// Keep the finished match in this match history.
    pub history: Option<PathBuf>,
}

/// How an online match went, printed as its last JSON line.
#[derive(Debug, Serialize)]
pub struct OnlineOutcome {
    /// Always `OnlineOver`.
    pub event: &'static str,
    /// The team played here.
    pub side: Side,
    /// Frames played (confirmed by both sides).
    pub frames: u64,
    /// Whether the match ended (otherwise `max_frames` ended it).
    pub match_over: bool,
    /// Score `[home, away]`.
    pub score: [u32; 2],
    /// Checksum of the final state (the same on both sides, hex).
    pub state_hash: String,
    /// Desyncs GGRS detected (0: both sides stepped alike).
    pub desyncs: u64,
    /// Rollbacks (states loaded) and frames stepped again after them.
    pub rollbacks: u64,
    /// Frames stepped again.
    pub resimulated_frames: u64,
    /// Round trip to the other side at the end, ms.
    pub ping_ms: u128,
}

/// The steps of frame `f`: from `f × 1000 / 60` to `(f + 1) × 1000 / 60` ms.
pub fn steps_of_frame(frame: u64) -> u64 {
    (frame + 1) * 1000 / FPS - frame * 1000 / FPS
}

impl LocalRods {
    /// This side's rods at the start of `frame`.
    fn input(&mut self, table: &Table, side: Side, frame: u64) -> SideInput {
        let LocalRods::Script(script) = self else {
            return SideInput::default();
        };
        let poses = script.poses_at(frame * 1_000_000 / FPS);
        let all: Vec<[f64; 2]> = table
            .rods
            .iter()
            .map(|r| {
                let p = poses.get(r.port).copied().unwrap_or_default();
                let half = 0.5 * r.travel_m;
                [p.axial_m.clamp(-half, half), p.angle_rad]
            })
            .collect();
        SideInput::from_poses(table, side, &all)
    }
}

fn save_recording(m: &Match, path: &std::path::Path) -> Result<()> {
    m.recording()
        .save(path)
        .map_err(|e| anyhow::anyhow!("saving the recording {}: {e}", path.display()))
}

/// Keeps a finished online match in the history at `path` (`events`: its kicks and end,
/// as confirmed by both sides), with its `replay`; one ended by `--max-frames` before its
/// end is not kept.
fn keep_in_history(
    events: &[TimedEvent],
    table: &Table,
    side: Side,
    remote: SocketAddr,
    seed: u64,
    path: &std::path::Path,
    replay: Option<&MatchRecording>,
) -> Result<()> {
    if !events
        .iter()
        .any(|e| matches!(e.event, Event::MatchOver { .. }))
    {
        return Ok(());
    }
    let mut teams = [String::new(), String::new()];
    teams[side.index()] = "local".into();
    teams[side.other().index()] = format!("peer {remote}");
    let record = MatchRecord::from_events(events, table, teams, Mode::Online, seed, now_unix_s())
        .context("the match's end is not among its events")?;
    HistoryStore::open(path)?.add(&record, replay)?;
    Ok(())
}

/// The match side of a session: the match, the frame its state is at, and what the end
/// and the history need.
struct OnlineMatch {
    m: Match,
    table: Table,
    /// The frame the match's state is at (frames before it are stepped).
    state_frame: u64,
    /// The frame after which the match ended in this timeline (a rollback may undo it).
    over_at: Option<u64>,
    /// The last frame stepped (`--max-frames`), or none.
    last_frame: u64,
    desyncs: u64,
    rollbacks: u64,
    resimulated: u64,
    /// The newest saves, for keeping the match as far as both sides confirmed it.
    saves: VecDeque<FrameState>,
    /// The kicks and the end, with the frame that made them (a rollback drops the later).
    kept_events: Vec<(u64, TimedEvent)>,
}

impl OnlineMatch {
    fn new(opts: &OnlineOptions) -> Result<Self> {
        let mut config = MatchConfig::computer_vs_computer(opts.table.clone(), opts.seed);
        config.controllers = [RodController::Player; 2];
        config.rules = RulesConfig {
            goals_to_win: opts.goals,
            ..RulesConfig::default()
        };
        Ok(Self {
            m: Match::new(config).context("match")?,
            table: opts.table.clone(),
            state_frame: 0,
            over_at: None,
            last_frame: opts.max_frames.unwrap_or(u64::MAX),
            desyncs: 0,
            rollbacks: 0,
            resimulated: 0,
            saves: VecDeque::with_capacity(MAX_PREDICTION_FRAMES + 2),
            kept_events: Vec::new(),
        })
    }

    /// Carries out GGRS's requests of one frame.
    fn handle(&mut self, requests: Vec<GgrsRequest<Foosball>>) -> Result<()> {
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
                        bail!("GGRS lost the match's state of frame {frame}");
                    };
                    self.m.restore(&state.saved);
                    self.state_frame = u64::try_from(state.frame).unwrap_or(0);
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
    fn end(&self) -> u64 {
        self.over_at.unwrap_or(self.last_frame).min(self.last_frame)
    }

    /// The error for a side that left after frame `confirmed` (the last both confirmed),
    /// the match restored to then and its recording kept where `record` says.
    fn left(&mut self, addr: SocketAddr, confirmed: i32, record: Option<&Path>) -> anyhow::Error {
        let kept = u64::try_from(confirmed + 1).unwrap_or(0);
        if let Some(s) = self
            .saves
            .iter()
            .find(|s| u64::try_from(s.frame) == Ok(kept))
        {
            self.m.restore(&s.saved);
        }
        let where_kept = match record.map(|path| (path, save_recording(&self.m, path))) {
            Some((path, Ok(()))) => format!("; the match to then is kept in {}", path.display()),
            Some((_, Err(e))) => format!("; {e}"),
            None => String::new(),
        };
        anyhow::anyhow!("the other side ({addr}) left the match at frame {kept}{where_kept}")
    }

    /// The outcome once the match has ended, keeping it where asked.
    fn finish(&self, opts: &OnlineOptions, ping_ms: u128) -> Result<OnlineOutcome> {
        if let Some(path) = &opts.record {
            save_recording(&self.m, path)?;
        }
        if let Some(path) = &opts.history {
            let events: Vec<TimedEvent> = self.kept_events.iter().map(|(_, e)| *e).collect();
            keep_in_history(
                &events,
                &self.table,
                opts.side,
                opts.remote,
                opts.seed,
                path,
                Some(self.m.recording()),
            )?;
        }
        Ok(OnlineOutcome {
            event: "OnlineOver",
            side: opts.side,
            frames: self.end(),
            match_over: self.m.is_over(),
            score: self.m.score(),
            state_hash: format!("{:032x}", self.m.state_hash()),
            desyncs: self.desyncs,
            rollbacks: self.rollbacks,
            resimulated_frames: self.resimulated,
            ping_ms,
        })
    }
}

/// Starts the GGRS session: this side local, the other at `opts.remote`.
fn start_session(opts: &OnlineOptions) -> Result<P2PSession<Foosball>> {
    let socket = UdpNonBlockingSocket::bind_to_port(opts.port)
        .with_context(|| format!("UDP port {}", opts.port))?;
    let local = opts.side.index();
    Ok(SessionBuilder::<Foosball>::new()
        .with_num_players(2)?
        .with_fps(FPS as usize)?
        .with_max_prediction_window(MAX_PREDICTION_FRAMES)
        .with_input_delay(opts.input_delay)
        .with_desync_detection_mode(DesyncDetection::On {
            interval: DESYNC_INTERVAL,
        })
        .add_player(PlayerType::Local, local)?
        .add_player(PlayerType::Remote(opts.remote), 1 - local)?
        .start_p2p_session(socket)?)
}

/// Handles the session's events; an error where the other side left before the end.
fn handle_events(
    sess: &mut P2PSession<Foosball>,
    game: &mut OnlineMatch,
    opts: &OnlineOptions,
    done: bool,
    started: Instant,
) -> Result<()> {
    let confirmed = sess.confirmed_frame();
    for e in sess.events().collect::<Vec<_>>() {
        match e {
            GgrsEvent::DesyncDetected { frame, .. } => {
                game.desyncs += 1;
                eprintln!("space-foosball: the sides' states differ at frame {frame}");
            }
            GgrsEvent::Disconnected { addr } if !done => {
                return Err(game.left(addr, confirmed, opts.record.as_deref()));
            }
            GgrsEvent::NetworkInterrupted { addr, .. } => {
                eprintln!("space-foosball: no word from {addr}: waiting");
            }
            GgrsEvent::Synchronized { addr } => {
                // The lobby's line: who, which side, how late the rods are sent.
                println!(
                    "{}",
                    serde_json::json!({
                        "event": "Synchronized",
                        "peer": addr,
                        "side": opts.side,
                        "input_delay_frames": opts.input_delay,
                        "after_ms": started.elapsed().as_millis(),
                    })
                );
            }
            _ => {}
        }
    }
    Ok(())
}

/// Plays an online match to its end (or `max_frames`); its outcome.
pub fn play(mut opts: OnlineOptions) -> Result<OnlineOutcome> {
    let mut game = OnlineMatch::new(&opts)?;
    let mut sess = start_session(&opts)?;
    let local = opts.side.index();
    let frame_time = Duration::from_micros(1_000_000 / FPS);
    let started = Instant::now();
    let mut next = Instant::now();
    // The frame this side asks for next.
    let mut frame: u64 = 0;
    let mut done: Option<OnlineOutcome> = None;
    let mut lingered = 0u64;
    loop {
        sess.poll_remote_clients();
        handle_events(&mut sess, &mut game, &opts, done.is_some(), started)?;
        if sess.current_state() != SessionState::Running {
            if started.elapsed() > CONNECT_TIMEOUT {
                bail!("no answer from {} within {CONNECT_TIMEOUT:?}", opts.remote);
            }
            std::thread::sleep(Duration::from_millis(2));
            next = Instant::now();
            continue;
        }
        let now = Instant::now();
        if now < next {
            std::thread::sleep((next - now).min(Duration::from_millis(2)));
            continue;
        }
        // A side ahead of the other waits a little (GGRS's recommendation, in effect).
        next += if sess.frames_ahead() > 0 {
            frame_time.mul_f64(1.1)
        } else {
            frame_time
        };
        let input = opts.rods.input(&game.table, opts.side, frame);
        sess.add_local_input(local, input)?;
        match sess.advance_frame() {
            Ok(requests) => game.handle(requests)?,
            Err(ggrs::GgrsError::PredictionThreshold) => continue,
            Err(e) => return Err(e.into()),
        }
        frame += 1;
        if done.is_some() {
            lingered += 1;
            if lingered >= LINGER_FRAMES {
                break;
            }
            continue;
        }
        // The state is final once every frame up to its end is confirmed by both sides.
        let end = game.end();
        let confirmed = u64::try_from(sess.confirmed_frame() + 1).unwrap_or(0);
        if game.state_frame >= end && confirmed >= end {
            let ping_ms = sess.network_stats(1 - local).map_or(0, |s| s.ping);
            done = Some(game.finish(&opts, ping_ms)?);
        }
    }
    let mut out = done.expect("the loop ends only once done");
    out.desyncs = game.desyncs;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_hold_the_steps_of_a_second_between_them() {
        let steps: u64 = (0..FPS).map(steps_of_frame).sum();
        assert_eq!(steps, 1000);
        assert!((0..FPS).all(|f| (16..=17).contains(&steps_of_frame(f))));
    }

    #[test]
    fn a_finished_online_match_is_kept_as_online_with_the_peer_named() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("history.sqlite3");
        let table = Table::standard();
        let remote: SocketAddr = "127.0.0.1:7001".parse().unwrap();
        let kick = TimedEvent {
            t_ms: 900,
            event: Event::Kick { rod: 3, speed: 4.5 },
        };
        // Not over (ended by --max-frames): nothing kept.
        keep_in_history(&[kick], &table, Side::Away, remote, 7, &db, None).unwrap();
        assert!(!db.exists());
        let over = TimedEvent {
            t_ms: 2000,
            event: Event::MatchOver { score: [0, 1] },
        };
        keep_in_history(&[kick, over], &table, Side::Away, remote, 7, &db, None).unwrap();
        let kept = HistoryStore::open(&db).unwrap().recent(5).unwrap();
        assert_eq!(kept.len(), 1);
        assert_eq!(kept[0].mode, Mode::Online);
        assert_eq!(
            kept[0].teams,
            ["peer 127.0.0.1:7001".to_string(), "local".into()]
        );
        assert_eq!((kept[0].score, kept[0].shots.len()), ([0, 1], 1));
    }
}
