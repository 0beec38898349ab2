//! `space-foosball board`: the cabinet builder's tool for the sensor board.
//!
//! * `board` or `board live`: the board's health, live, from its IN reports
//!   ([`crate::board_view`]).
//! * `board info`: firmware version, git hash, serial number, reset reason, uptime.
//! * `board ports` (or `board diag`): per port 0–7 the diagnostics Feature report
//!   (present, PS/2 device id, every counter) with the port's sample rate and
//!   resolution.
//! * `board settings`: every port's settings; `board set KEY VALUE` changes one (read,
//!   modify, write, read back; [`keys`]).
//! * `board bootloader`: restarts the board into its USB bootloader.
//!
//! `--board`, `--socket` and `--serial` choose the board ([`target`]); `--json` prints
//! one JSON object instead of text ([`show`]). Everything but the live view goes
//! through the board's Feature reports ([`board_link::FeaturePipe`]): the board on USB,
//! or the built-in emulated board, which answers them as the firmware does. A bad key
//! or value, a board that cannot be reached or that refuses is one line on stderr and
//! exit status 1.

mod commands;
pub mod keys;
pub mod show;
pub mod target;

use crate::board_view::{self, LiveArgs};
use crate::window::board::BoardChoice;
use anyhow::{bail, Result};
use std::path::PathBuf;

/// Arguments of `space-foosball board`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to do; the live view when left out.
    #[command(subcommand)]
    pub command: Option<BoardCommand>,
    /// The board: auto (USB if plugged in; for the live view, else the built-in
    /// emulated board), usb, emulated, socket (the `sim serve` emulator at its default
    /// path) or socket:PATH [default: auto].
    #[arg(long, global = true, value_parser = parse_board, conflicts_with = "socket")]
    pub board: Option<BoardChoice>,
    /// The `sim serve` emulator at this socket path (the same as `--board socket:PATH`).
    #[arg(long, global = true, value_name = "ADDR")]
    pub socket: Option<PathBuf>,
    /// The board on USB with this serial number string, when several are plugged in
    /// (`lsusb -v -d 1209:0001 | grep iSerial` lists them; so does the error when none
    /// matches).
    #[arg(long, global = true, value_name = "S")]
    pub serial: Option<String>,
    /// Print one JSON object (the live view: one per frame and line) instead of text.
    #[arg(long, global = true)]
    pub json: bool,
    /// The live view's options (also after `live`).
    #[command(flatten)]
    pub live: LiveArgs,
}

/// What `space-foosball board` does.
#[derive(clap::Subcommand, Debug)]
pub enum BoardCommand {
    /// The board's health, live, from its IN reports (the default).
    Live(LiveArgs),
    /// The commands that go through the board's Feature reports.
    #[command(flatten)]
    Feature(FeatureCommand),
}

/// The commands of `space-foosball board` that go through the board's Feature reports.
#[derive(clap::Subcommand, Debug)]
pub enum FeatureCommand {
    /// Firmware version, git hash, serial number, reset reason, uptime and the ports
    /// whose mouse is present.
    Info,
    /// Per port 0–7: present, PS/2 device id, every counter the board keeps (frames,
    /// packets, errors, resends, drops, retries, absences, inits, restarts, FIFO
    /// stalls, line faults) and the port's sample rate and resolution.
    #[command(visible_alias = "diag")]
    Ports,
    /// Every port's settings: axis map, inversions, resolution, sample rate.
    Settings,
    /// Change one setting: reads the settings, changes KEY, writes them (the board
    /// applies them and keeps them in flash) and reads them back to confirm.
    ///
    /// KEY is port.N.FIELD, N the port 0–7, FIELD one of: axial_is_y (true: the
    /// mouse's Y axis measures the rod's slide, false: its X axis), invert_axial,
    /// invert_rotation (true or false), resolution_code (0–3: 1, 2, 4 or 8
    /// counts/mm), sample_rate (10, 20, 40, 60, 80, 100 or 200 samples/s).
    /// Example: `space-foosball board set port.3.sample_rate 100`.
    Set {
        /// The setting: port.N.FIELD.
        key: String,
        /// Its new value.
        #[arg(allow_hyphen_values = true)]
        value: String,
    },
    /// Restart the board into its USB bootloader (the RPI-RP2 drive, for a new UF2).
    /// Asks nothing: the board restarts at once.
    Bootloader,
}

fn parse_board(s: &str) -> Result<BoardChoice, String> {
    s.parse()
}

/// Runs `space-foosball board`.
pub fn run(args: &Args) -> Result<()> {
    let choice = match (&args.socket, &args.board) {
        (Some(path), _) => BoardChoice::Socket(Some(path.clone())),
        (None, Some(choice)) => choice.clone(),
        (None, None) => BoardChoice::Auto,
    };
    let serial = args.serial.as_deref();
    target::check_serial(&choice, serial)?;
    let (live_args, command) = match &args.command {
        None => (args.live.clone(), None),
        Some(BoardCommand::Live(live_args)) => (args.live.or(live_args), None),
        Some(BoardCommand::Feature(command)) => (args.live.clone(), Some(command)),
    };
    let Some(command) = command else {
        let json = live_args.json_output(args.json)?;
        let board = target::open_live(&choice, serial)?;
        return board_view::run(board, &live_args, json);
    };
    if live_args.any_given() {
        bail!(
            "--once, --frames, --interval-ms, --wait-ms and --format are options of the \
             live view (`space-foosball board [live]`), not of `board {}`",
            command.name()
        );
    }
    let json = args.json;
    match command {
        FeatureCommand::Info => commands::info(&choice, serial, json),
        FeatureCommand::Ports => commands::ports(&choice, serial, json),
        FeatureCommand::Settings => commands::settings(&choice, serial, json),
        FeatureCommand::Set { key, value } => commands::set(&choice, serial, key, value, json),
        FeatureCommand::Bootloader => commands::bootloader(&choice, serial, json),
    }
}

impl FeatureCommand {
    /// The command's name on the command line.
    fn name(&self) -> &'static str {
        match self {
            Self::Info => "info",
            Self::Ports => "ports",
            Self::Settings => "settings",
            Self::Set { .. } => "set",
            Self::Bootloader => "bootloader",
        }
    }
}
