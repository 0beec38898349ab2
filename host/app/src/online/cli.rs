//! `space-foosball host` and `space-foosball join ADDRESS`, or both with `--room NAME`: an
//! online match, headless.

use super::session::{play, play_in_window, LocalRods, OnlineOptions, Peer};
use crate::window::board::BoardChoice;
use anyhow::{bail, Context, Result};
use foosball_sim::motion::script::MotionScript;
use space_foosball::recording::MatchRecording;
use space_foosball::side::Side;
use space_foosball_front::online::rollback::MatchTerms;
use space_foosball_front::online::room::DEFAULT_SIGNAL;
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::PathBuf;

/// What both `host` and `join` take.
#[derive(clap::Args, Debug)]
pub struct Common {
    /// Meet the other side in this room of the signalling server (`--signal`) and play
    /// over WebRTC (a page in a browser joins the same room), instead of by address.
    #[arg(long, value_name = "NAME")]
    pub room: Option<String>,
    /// The signalling server of `--room` (`matchbox_server`).
    #[arg(long, value_name = "URL", default_value = DEFAULT_SIGNAL)]
    pub signal: String,
    /// Play in a window: the lobby, the match and its end on screen, this side's rods from
    /// the board (USB, else the keyboard, mouse and gamepad, as in `play`).
    #[arg(long, conflicts_with = "script")]
    pub window: bool,
    /// The board of `--window`: `auto`, `usb`, `emulated`, or `socket[:PATH]`.
    #[arg(long, default_value = "auto", value_parser = parse_board, requires = "window")]
    pub board: BoardChoice,
    /// Close the window this many seconds after its first frame, or once the match is
    /// over (unattended checks).
    #[arg(long, hide = true, requires = "window")]
    pub exit_after_s: Option<f64>,
    /// Local UDP port (by address).
    #[arg(long, default_value_t = 7000)]
    pub port: u16,
    /// Table: `standard`, `paper` or a TOML file (both sides the same).
    #[arg(long, default_value = "standard")]
    pub table: String,
    /// The match's seed (both sides the same).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Goals that win (1–99).
    #[arg(long, default_value_t = 5)]
    pub goals: u32,
    /// Drive this side's rods by a motion script (see sim/README.md) instead of holding
    /// them still.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// End after this many 60 Hz frames, the match over or not.
    #[arg(long, value_name = "N")]
    pub max_frames: Option<u64>,
    /// Frames of input delay (0–8): fewer rollbacks, later rods.
    #[arg(long, default_value_t = 2)]
    pub input_delay: usize,
    /// Save the match's recording here at the end, or as far as both sides played it
    /// when the other side leaves (for `space-foosball replay`).
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// Keep the finished match in this match history (see `space-foosball history`).
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
    /// Resume the match kept in this recording (`--record` of a match the other side
    /// left), both sides from the same file: its table, seed and goals are used.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
}

/// Arguments of `space-foosball host`.
#[derive(clap::Args, Debug)]
pub struct HostArgs {
    /// The joining side's address (`HOST:PORT`); not with `--room`.
    #[arg(long, value_name = "ADDRESS", required_unless_present = "room")]
    pub peer: Option<String>,
    #[command(flatten)]
    pub common: Common,
}

/// Arguments of `space-foosball join`.
#[derive(clap::Args, Debug)]
pub struct JoinArgs {
    /// The hosting side's address (`HOST:PORT`); not with `--room`.
    #[arg(required_unless_present = "room")]
    pub address: Option<String>,
    #[command(flatten)]
    pub common: Common,
}

fn parse_board(s: &str) -> Result<BoardChoice, String> {
    s.parse()
}

fn address(text: &str) -> Result<SocketAddr> {
    text.to_socket_addrs()
        .with_context(|| format!("{text:?} is not an address (HOST:PORT)"))?
        .next()
        .with_context(|| format!("{text:?} names no address"))
}

fn run(side: Side, remote: Option<&str>, c: &Common) -> Result<()> {
    if !(1..=99).contains(&c.goals) {
        bail!("--goals must be 1–99, got {}", c.goals);
    }
    if c.input_delay > 8 {
        bail!("--input-delay must be 0–8 frames, got {}", c.input_delay);
    }
    let rods = match &c.script {
        Some(path) => LocalRods::Script(Box::new(
            MotionScript::load(path).map_err(|e| anyhow::anyhow!("{e}"))?,
        )),
        None => LocalRods::Idle,
    };
    let peer = match (&c.room, remote) {
        (Some(_), Some(remote)) => bail!("give an address ({remote}) or --room, not both"),
        (Some(name), None) => Peer::Room {
            signal: c.signal.clone(),
            name: name.clone(),
        },
        (None, Some(remote)) => Peer::Address(address(remote)?),
        (None, None) => bail!("give the other side's address, or --room NAME"),
    };
    let resume = match &c.resume {
        Some(path) => Some(
            MatchRecording::load(path)
                .map_err(|e| anyhow::anyhow!("{e}"))
                .with_context(|| format!("the kept match {}", path.display()))?,
        ),
        None => None,
    };
    let terms = match &resume {
        Some(r) => MatchTerms {
            table: r.table.clone(),
            seed: r.seed,
            goals: r.rules.goals_to_win,
            max_frames: c.max_frames,
        },
        None => MatchTerms {
            table: crate::headless::load_table(&c.table)?,
            seed: c.seed,
            goals: c.goals,
            max_frames: c.max_frames,
        },
    };
    let opts = OnlineOptions {
        side,
        port: c.port,
        peer,
        terms,
        resume,
        rods,
        input_delay: c.input_delay,
        record: c.record.clone(),
        history: c.history.clone(),
    };
    if c.window {
        if crate::play::display().is_none() {
            bail!("--window: no display found (neither DISPLAY nor WAYLAND_DISPLAY is set)");
        }
        return play_in_window(opts, c.board.clone(), c.exit_after_s);
    }
    let outcome = play(opts)?;
    println!("{}", serde_json::to_string(&outcome)?);
    if outcome.desyncs > 0 {
        bail!(
            "the two sides' matches differed ({} desyncs)",
            outcome.desyncs
        );
    }
    Ok(())
}

/// Hosts an online match: this side plays Home.
pub fn host(args: &HostArgs) -> Result<()> {
    run(Side::Home, args.peer.as_deref(), &args.common)
}

/// Joins an online match: this side plays Away.
pub fn join(args: &JoinArgs) -> Result<()> {
    run(Side::Away, args.address.as_deref(), &args.common)
}
