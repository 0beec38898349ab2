//! The online match on the desktop: the shared session (`space_foosball_front::online`)
//! polled from a loop that sleeps between frames, over UDP to an address or over WebRTC
//! to a room's other side; the outcome, the recording and the history at the end.

use super::window::{KeepMatch, OnlineWindow};
use crate::history::record::now_unix_s;
use crate::history::{HistoryStore, MatchRecord, Mode};
use crate::window::board::BoardChoice;
use anyhow::{bail, Context, Result};
use foosball_sim::motion::script::MotionScript;
use foosball_sim::motion::MotionSource;
use ggrs::{NonBlockingSocket, UdpNonBlockingSocket};
use serde::Serialize;
use space_foosball::play::Match;
use space_foosball::recording::MatchRecording;
use space_foosball::rules::{Event, TimedEvent};
use space_foosball::side::Side;
use space_foosball::Table;
use space_foosball_front::online::input::SideInput;
use space_foosball_front::online::rollback::{MatchTerms, OnlineMatch, FPS};
use space_foosball_front::online::room::{room_url, PeerChannel, PeerId, Room, TrafficError};
use space_foosball_front::online::screen::{in_room, Connect, OnlineScreen, OnlineView};
use space_foosball_front::online::session::{
    Notice, OnlineError, OnlineSession, Stand, CONNECT_TIMEOUT_S,
};
use std::fmt::Debug;
use std::hash::Hash;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What drives this side's rods.
pub enum LocalRods {
    /// Held centred and upright.
    Idle,
    /// A motion script (`foosball-sim`'s format), each board port's pose read at the frame's
    /// time as the rod of the table on that port.
    Script(Box<MotionScript>),
}

/// Where the other side is.
pub enum Peer {
    /// At a UDP address (a LAN, or two processes on one machine: no server).
    Address(SocketAddr),
    /// In room `name` on the signalling server at `signal` (`ws://…`), over WebRTC.
    Room {
        /// The signalling server.
        signal: String,
        /// The room's name.
        name: String,
    },
}

/// How to play online.
pub struct OnlineOptions {
    /// The team played here (the host plays Home, who joins Away).
    pub side: Side,
    /// The local UDP port (an address peer).
    pub port: u16,
    /// The other side.
    pub peer: Peer,
    /// Table, seed, goals and frames: both sides must use the same (a resumed match's are
    /// its recording's).
    pub terms: MatchTerms,
    /// The kept match to resume (both sides the same), instead of a new one.
    pub resume: Option<MatchRecording>,
    /// What drives this side's rods.
    pub rods: LocalRods,
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
    peer: &str,
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
    teams[side.other().index()] = format!("peer {peer}");
    let record = MatchRecord::from_events(events, table, teams, Mode::Online, seed, now_unix_s())
        .context("the match's end is not among its events")?;
    HistoryStore::open(path)?.add(&record, replay)?;
    Ok(())
}

/// The match to play: new on the terms, or the kept one resumed.
fn online_match(opts: &OnlineOptions) -> Result<OnlineMatch> {
    match &opts.resume {
        Some(recording) => {
            OnlineMatch::resume(recording, opts.terms.max_frames).context("resuming the kept match")
        }
        None => OnlineMatch::new(&opts.terms).context("match"),
    }
}

/// The outcome once the match has ended, keeping it where asked.
fn finish<A>(sess: &OnlineSession<A>, opts: &OnlineOptions, peer: &str) -> Result<OnlineOutcome>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    let online = sess.game();
    let m = online.game();
    keep_over(online, opts, peer)?;
    let (rollbacks, resimulated_frames) = online.rollbacks();
    Ok(OnlineOutcome {
        event: "OnlineOver",
        side: opts.side,
        frames: online.end(),
        match_over: m.is_over(),
        score: m.score(),
        state_hash: format!("{:032x}", m.state_hash()),
        desyncs: sess.desyncs(),
        rollbacks,
        resimulated_frames,
        ping_ms: sess.ping_ms().unwrap_or(0),
    })
}

/// Says what the players should hear of: the lobby's line (who, which side, how late the
/// rods are sent) on stdout, the rest on stderr.
fn tell<A: Debug>(notice: &Notice<A>, opts: &OnlineOptions, peer: &str, since: Duration) {
    match notice {
        Notice::Synchronized { .. } => println!(
            "{}",
            serde_json::json!({
                "event": "Synchronized",
                "peer": peer,
                "side": opts.side,
                "input_delay_frames": opts.input_delay,
                "after_ms": since.as_millis(),
            })
        ),
        Notice::Desync { frame } => {
            eprintln!("space-foosball: the sides' states differ at frame {frame}");
        }
        Notice::Interrupted => eprintln!("space-foosball: no word from {peer}: waiting"),
        Notice::Resumed => eprintln!("space-foosball: {peer} answers again"),
    }
}

/// Plays the session over `socket` against `remote` (named `peer` to the players).
fn play_over<A>(
    socket: impl NonBlockingSocket<A> + 'static,
    remote: A,
    peer: &str,
    opts: &mut OnlineOptions,
    clock: Instant,
) -> Result<OnlineOutcome>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    let now = || clock.elapsed().as_secs_f64();
    let mut sess = OnlineSession::start(
        socket,
        remote,
        opts.side,
        online_match(opts)?,
        opts.input_delay,
        now(),
    )?;
    let table = opts.terms.table.clone();
    let side = opts.side;
    let mut notices = Vec::new();
    let mut done: Option<OnlineOutcome> = None;
    loop {
        let stand = {
            let rods = &mut opts.rods;
            sess.poll(now(), &mut |f| rods.input(&table, side, f), &mut notices)
        };
        for n in notices.drain(..) {
            tell(&n, opts, peer, clock.elapsed());
        }
        match stand {
            Err(OnlineError::Left { frame, .. }) => {
                let kept = match opts.record.as_deref() {
                    Some(path) => match save_recording(sess.game().game(), path) {
                        Ok(()) => format!("; the match to then is kept in {}", path.display()),
                        Err(e) => format!("; {e}"),
                    },
                    None => String::new(),
                };
                bail!("the other side ({peer}) left the match at frame {frame}{kept}");
            }
            Err(OnlineError::NoAnswer { .. }) => {
                bail!("no answer from {peer} within {CONNECT_TIMEOUT_S} s")
            }
            Err(e) => return Err(e.into()),
            Ok(Stand::Over) if done.is_none() => done = Some(finish(&sess, opts, peer)?),
            Ok(Stand::Closed) => break,
            Ok(_) => {}
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let mut out = match done {
        Some(out) => out,
        None => finish(&sess, opts, peer)?,
    };
    out.desyncs = sess.desyncs();
    Ok(out)
}

/// The room's traffic on its own thread, for as long as the process plays: the thread
/// ends with the socket's error (the signalling server unreachable or gone).
type Traffic = std::thread::JoinHandle<Result<(), TrafficError>>;

/// Opens room `name` on the signalling server `signal`, its traffic carried on a thread.
fn open_room(signal: &str, name: &str) -> Result<(Room, Traffic)> {
    let url = room_url(signal, name)?;
    let (room, carried) = Room::open(&url);
    let traffic = std::thread::Builder::new()
        .name("room".into())
        .spawn(move || futures::executor::block_on(carried))
        .context("starting the room's thread")?;
    Ok((room, traffic))
}

/// Opens room `name` on `signal` and waits for its other side: the room (kept open for the
/// match), the other side and the data channel to it.
fn meet_in_room(signal: &str, name: &str, clock: Instant) -> Result<(Room, PeerId, PeerChannel)> {
    let (mut room, traffic) = open_room(signal, name)?;
    eprintln!("space-foosball: waiting in room {name} on {signal}");
    loop {
        if let Some(peer) = room.peer() {
            let channel = room
                .take_channel()
                .context("the room's data channel is already taken")?;
            return Ok((room, peer, channel));
        }
        if traffic.is_finished() {
            let why = match traffic.join() {
                Ok(Err(e)) => format!("{e}"),
                _ => "it closed".into(),
            };
            bail!("the signalling server {signal}: {why}");
        }
        if clock.elapsed().as_secs_f64() > CONNECT_TIMEOUT_S {
            bail!("nobody came to room {name} on {signal} within {CONNECT_TIMEOUT_S} s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Keeps a match that is over where `opts` asks (its recording, the history).
fn keep_over(online: &OnlineMatch, opts: &OnlineOptions, peer: &str) -> Result<()> {
    let m = online.game();
    if let Some(path) = &opts.record {
        save_recording(m, path)?;
    }
    if let Some(path) = &opts.history {
        keep_in_history(
            &online.kept_events(),
            online.table(),
            opts.side,
            peer,
            opts.terms.seed,
            path,
            Some(m.recording()),
        )?;
    }
    Ok(())
}

/// Plays an online match in a window (see `online::window`), its rods from `board`; the
/// status at the end is the last line on stdout. An error where it stopped before its
/// end or the sides differed.
pub fn play_in_window(
    opts: OnlineOptions,
    board: BoardChoice,
    exit_after_s: Option<f64>,
) -> Result<()> {
    let (side, delay) = (opts.side, opts.input_delay);
    let game = online_match(&opts)?;
    let (view, peer): (Box<dyn OnlineView>, String) = match &opts.peer {
        Peer::Address(remote) => {
            let remote = *remote;
            let mut socket = Some(
                UdpNonBlockingSocket::bind_to_port(opts.port)
                    .with_context(|| format!("UDP port {}", opts.port))?,
            );
            let connect: Connect<SocketAddr, UdpNonBlockingSocket> =
                Box::new(move || Ok(socket.take().map(|s| (s, remote))));
            let place = remote.to_string();
            let screen = OnlineScreen::new(connect, &place, side, game, delay);
            (Box::new(screen), place)
        }
        Peer::Room { signal, name } => {
            // The traffic thread ends with the process; a dead server shows as nobody
            // coming to the room.
            let (room, _traffic) = open_room(signal, name)?;
            let place = format!("room {name}");
            let screen = OnlineScreen::new(in_room(room), &place, side, game, delay);
            (Box::new(screen), place)
        }
    };
    let table = opts.terms.table.clone();
    let window = OnlineWindow {
        board,
        calibration_path: crate::window::args::default_calibration_path(),
        size: (1280, 720),
        fullscreen: false,
        exit_after_s,
    };
    let keep: KeepMatch = Box::new(move |online| keep_over(online, &opts, &peer));
    let status = super::window::run(view, side, table, window, keep)?;
    println!("{}", serde_json::to_string(&status)?);
    if let Some(why) = &status.error {
        bail!("the online match stopped: {}", why.to_lowercase());
    }
    if status.desyncs > 0 {
        bail!(
            "the two sides' matches differed ({} desyncs)",
            status.desyncs
        );
    }
    Ok(())
}

/// Plays an online match to its end (or `max_frames`); its outcome.
pub fn play(mut opts: OnlineOptions) -> Result<OnlineOutcome> {
    let clock = Instant::now();
    match &opts.peer {
        Peer::Address(remote) => {
            let remote = *remote;
            let socket = UdpNonBlockingSocket::bind_to_port(opts.port)
                .with_context(|| format!("UDP port {}", opts.port))?;
            play_over(socket, remote, &remote.to_string(), &mut opts, clock)
        }
        Peer::Room { signal, name } => {
            let (signal, name) = (signal.clone(), name.clone());
            let (_room, peer, channel) = meet_in_room(&signal, &name, clock)?;
            let who = format!("{peer} in room {name}");
            play_over(channel, peer, &who, &mut opts, clock)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finished_online_match_is_kept_as_online_with_the_peer_named() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("history.sqlite3");
        let table = Table::standard();
        let remote = "127.0.0.1:7001";
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
