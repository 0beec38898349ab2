//! `sim`: the emulated Space Foosball sensor board as a process.
//!
//! * `sim serve`: serve IN reports over a Unix socket (what `board_link::SocketBoard`
//!   connects to), one per millisecond in real time; `--interactive` lets a person
//!   drive the rods from this terminal's keyboard.
//! * `sim usbip`: export the board as a USB device over USB/IP.
//! * `sim bench`: measure emulated seconds per wall-clock second.
//! * `sim check-script FILE`: validate a motion script.
//!
//! A user error (bad option, bad file) prints one line, `error: …`, on stderr and exits
//! with status 1, never a backtrace; a closed stdout (`sim … | head`) ends quietly.
//!
//! See `sim/README.md`.

use anyhow::{bail, Context, Result};
use clap::error::ErrorKind;
use clap::{Args, Parser, Subcommand};
use foosball_protocol::PADDLES;
use foosball_sim::board::{BoardConfig, EmulatedBoard};
use foosball_sim::faults::Fault;
use foosball_sim::interactive;
use foosball_sim::motion::live::{LiveHandle, LiveLimits, LiveMotion};
use foosball_sim::motion::recording::Playback;
use foosball_sim::motion::script::MotionScript;
use foosball_sim::motion::{MotionSource, Stationary};
use foosball_sim::ps2_device::mouse::VALID_SAMPLE_RATES;
use foosball_sim::serve::SocketServer;
use foosball_sim::usbip::{UsbIpServer, USBIP_PORT};
use sensor_board::Resolution;
use std::io::{self, Write};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

#[derive(Parser, Debug)]
#[command(name = "sim", version, about = "Emulated Space Foosball sensor board")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Serve the board's reports over a Unix socket (board_link::SocketBoard), 1 kHz.
    Serve {
        /// Socket path [default: $XDG_RUNTIME_DIR/space-foosball/board.sock, or
        /// /tmp/space-foosball-{uid}/board.sock].
        #[arg(long)]
        socket: Option<PathBuf>,
        /// Drive the rods from this terminal's keys (the game's key map; piped
        /// characters when stdin is not a terminal): 1-4 rod, W/S slide, A/D spin,
        /// Space kick, Enter push, Tab other team, q quit.
        #[arg(long, conflicts_with_all = ["script", "recording"])]
        interactive: bool,
        #[command(flatten)]
        board: BoardArgs,
    },
    /// Export the board as a USB device over USB/IP (attach with `usbip attach -r
    /// 127.0.0.1 -b 1-1` after `modprobe vhci-hcd`).
    Usbip {
        /// Address to listen on.
        #[arg(long, default_value_t = SocketAddr::from(([127, 0, 0, 1], USBIP_PORT)))]
        listen: SocketAddr,
        #[command(flatten)]
        board: BoardArgs,
    },
    /// Measure how many emulated seconds (8 sensors at wire level) run per wall-clock
    /// second on one core.
    Bench {
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Emulated seconds to measure (after 1 s of initialisation).
        #[arg(long, default_value_t = 20.0)]
        seconds: f64,
    },
    /// Validate a motion script and print its duration and faults.
    CheckScript {
        /// The JSON script.
        file: PathBuf,
    },
}

/// Options shared by `serve` and `usbip`: the board and its rods.
#[derive(Args, Debug)]
struct BoardArgs {
    /// Motion script (JSON); its faults are scheduled too.
    #[arg(long, conflicts_with = "recording")]
    script: Option<PathBuf>,
    /// Recorded rod poses (JSON) to play back.
    #[arg(long)]
    recording: Option<PathBuf>,
    /// Mouse resolution the firmware configures, counts/mm: 1, 2, 4 or 8.
    #[arg(long, default_value_t = 8)]
    resolution: u8,
    /// Sample rate the firmware configures, samples/s: 10, 20, 40, 60, 80, 100 or 200.
    #[arg(long, default_value_t = 200)]
    sample_rate: u8,
    /// PS/2 clock of the mice, kHz (10–16.7).
    #[arg(long, default_value_t = 12.5)]
    clock_khz: f64,
    /// Mouse self-test duration after reset or power-up, ms.
    #[arg(long, default_value_t = 500)]
    self_test_ms: u64,
    /// Seed of the sensor noise and random faults.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Rod surface radius seen by the sensors, mm.
    #[arg(long, default_value_t = 8.0)]
    rod_radius_mm: f64,
    /// Sensor gain error on both axes, fraction (0.02 = 2 % too many counts).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    gain_error: f64,
    /// Sensor axis cross-talk, fraction.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    cross_talk: f64,
    /// Sensor noise, counts rms per sensor frame and axis.
    #[arg(long, default_value_t = 0.0)]
    noise: f64,
    /// Sensor maximum tracking speed, m/s.
    #[arg(long, default_value_t = 3.0)]
    max_speed: f64,
    /// Probability per frame of an inverted parity bit, all ports.
    #[arg(long, default_value_t = 0.0)]
    parity_error_rate: f64,
    /// Probability per byte of a dropped byte, all ports.
    #[arg(long, default_value_t = 0.0)]
    drop_rate: f64,
    /// Ports with no mouse plugged in (comma-separated, 0–7).
    #[arg(long, value_delimiter = ',')]
    unplugged: Vec<usize>,
    /// Log connections and errors to stderr.
    #[arg(short, long)]
    verbose: bool,
}

fn resolution(counts_per_mm: u8) -> Result<Resolution> {
    Ok(match counts_per_mm {
        1 => Resolution::CountsPerMm1,
        2 => Resolution::CountsPerMm2,
        4 => Resolution::CountsPerMm4,
        8 => Resolution::CountsPerMm8,
        other => bail!("--resolution must be 1, 2, 4 or 8 counts/mm, got {other}"),
    })
}

/// Fails with "FILE does not exist" (`what` names it) before any attempt to read it.
fn require_file(path: &Path, what: &str) -> Result<()> {
    if !path.exists() {
        bail!("{what} {}: the file does not exist", path.display());
    }
    Ok(())
}

impl BoardArgs {
    /// Whether the rods have something to follow (a script or a recording).
    fn has_motion(&self) -> bool {
        self.script.is_some() || self.recording.is_some()
    }

    /// The board, its rods following `live` when given, else the script, the recording
    /// or nothing.
    fn build(&self, live: Option<LiveMotion>) -> Result<EmulatedBoard> {
        let mut config = BoardConfig::default();
        config.firmware_mouse.resolution = resolution(self.resolution)?;
        if !VALID_SAMPLE_RATES.contains(&self.sample_rate) {
            bail!(
                "--sample-rate must be one of {VALID_SAMPLE_RATES:?} samples/s, got {}",
                self.sample_rate
            );
        }
        config.firmware_mouse.sample_rate = self.sample_rate;
        if !self.clock_khz.is_finite() || !(10.0..=16.7).contains(&self.clock_khz) {
            bail!("--clock-khz must be 10–16.7 kHz, got {}", self.clock_khz);
        }
        config.wire.clock_hz = (self.clock_khz * 1000.0).round() as u32;
        config.mouse.self_test_us = self.self_test_ms.saturating_mul(1000);
        config.seed = self.seed;
        for sensor in &mut config.sensors {
            sensor.rod_radius_m = self.rod_radius_mm / 1000.0;
            sensor.axial_gain_error = self.gain_error;
            sensor.rotation_gain_error = self.gain_error;
            sensor.cross_talk = self.cross_talk;
            sensor.noise_counts_rms = self.noise;
            sensor.max_speed_m_per_s = self.max_speed;
        }
        let mut faults = Vec::new();
        let motion: Box<dyn MotionSource> = if let Some(live) = live {
            Box::new(live)
        } else if let Some(path) = &self.script {
            require_file(path, "--script")?;
            let script = MotionScript::load(path)?;
            faults = script.faults().to_vec();
            Box::new(script)
        } else if let Some(path) = &self.recording {
            require_file(path, "--recording")?;
            Box::new(Playback::load(path)?)
        } else {
            Box::new(Stationary)
        };
        let mut board = EmulatedBoard::new(config, motion)?;
        board.schedule_all(&faults)?;
        for &port in &self.unplugged {
            if port >= PADDLES {
                bail!("--unplugged: port {port} does not exist (ports are 0–7)");
            }
            board.inject(port, Fault::Unplug)?;
        }
        for port in 0..PADDLES {
            board
                .inject(
                    port,
                    Fault::ParityErrorRate {
                        probability: self.parity_error_rate,
                    },
                )
                .context("--parity-error-rate")?;
            board
                .inject(
                    port,
                    Fault::DropRate {
                        probability: self.drop_rate,
                    },
                )
                .context("--drop-rate")?;
        }
        Ok(board)
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return command_line_error(&e),
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        // `sim … | head`: the reader has what it wanted.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            // `{:#}` is the message and its causes on one line, never the backtrace
            // that `{:?}` would add under RUST_BACKTRACE.
            note(&format!("error: {}", one_line(&format!("{e:#}"))));
            ExitCode::FAILURE
        }
    }
}

/// Help and version go to stdout (status 0); a usage error is one line (status 1).
fn command_line_error(e: &clap::Error) -> ExitCode {
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            ExitCode::SUCCESS
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            note("error: a command is needed: serve, usbip, bench or check-script (see `sim --help`)");
            ExitCode::FAILURE
        }
        _ => {
            let rendered = e.render().to_string();
            let first = rendered.lines().next().unwrap_or_default();
            let message = first.strip_prefix("error: ").unwrap_or(first);
            note(&format!("error: {} (see `sim --help`)", one_line(message)));
            ExitCode::FAILURE
        }
    }
}

/// `text` with its lines joined by spaces.
fn one_line(text: &str) -> String {
    text.split('\n')
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| {
        cause
            .downcast_ref::<io::Error>()
            .is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// A line on stderr; a closed stderr is not worth a panic.
fn note(line: &str) {
    let _ = writeln!(io::stderr(), "{line}");
}

/// A line on stdout; a closed stdout is an error for [`main`] to end quietly on.
fn say(line: &str) -> Result<()> {
    let mut out = io::stdout().lock();
    writeln!(out, "{line}")?;
    out.flush()?;
    Ok(())
}

fn run(cli: Cli) -> Result<()> {
    // Runs until the process is stopped (or `q` in interactive mode); a killed
    // server's stale socket file is removed by the next one.
    let stop = Arc::new(AtomicBool::new(false));
    match cli.command {
        Command::Serve {
            socket,
            interactive,
            board,
        } => {
            let path = socket.unwrap_or_else(board_link::socket_wire::default_socket_path);
            let live =
                interactive.then(|| LiveMotion::new(LiveHandle::default(), LiveLimits::default()));
            let handle = live.as_ref().map(LiveMotion::handle);
            let mut emulated = board.build(live)?;
            let mut server = SocketServer::bind(&path)?;
            server.set_verbose(board.verbose);
            note(&format!("sim serve: emulated board on {}", path.display()));
            let _keyboard = match handle {
                Some(handle) => Some(
                    interactive::start(handle, Arc::clone(&stop))
                        .context("reading keys from the terminal")?,
                ),
                None => {
                    if !board.has_motion() {
                        note(
                            "sim serve: no --script, --recording or --interactive: the rods will \
                             sit still (no motion reaches the game); drive them by hand with \
                             `sim serve --interactive`, or give a motion script with --script FILE",
                        );
                    }
                    None
                }
            };
            server.run(&mut emulated, &stop)?;
        }
        Command::Usbip { listen, board } => {
            let mut emulated = board.build(None)?;
            let mut server = UsbIpServer::bind(listen)?;
            server.set_verbose(board.verbose);
            note(&format!(
                "sim usbip: exporting bus id {} on {} (usbip attach -r {} -b {})",
                foosball_sim::usbip::BUS_ID,
                server.local_addr()?,
                listen.ip(),
                foosball_sim::usbip::BUS_ID
            ));
            server.run(&mut emulated, &stop)?;
        }
        Command::Bench { json, seconds } => {
            let result = foosball_sim::bench::run(seconds)?;
            if json {
                say(&serde_json::to_string(&result)?)?;
            } else {
                say(&format!(
                    "{:.1} emulated s per wall-clock s ({} emulated s in {:.3} s; {} frames, {} packets)",
                    result.emulated_s_per_wall_s,
                    result.emulated_s,
                    result.wall_s,
                    result.frames,
                    result.packets
                ))?;
            }
        }
        Command::CheckScript { file } => {
            require_file(&file, "motion script")?;
            let script = MotionScript::load(&file)?;
            say(&format!(
                "{}: valid; motion lasts {:.3} s; {} fault(s) scheduled",
                file.display(),
                script.duration_us() as f64 / 1e6,
                script.faults().len()
            ))?;
        }
    }
    Ok(())
}
