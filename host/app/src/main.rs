//! `space-foosball`: the Space Foosball program, the composition root that joins the
//! game, the renderer, the sound and the board.
//!
//! "The paper" and its section numbers (§5) refer to Bang, Heo, Kim and Kim, "Space
//! Foosball: Coupling Tangible Interfaces with a Real-time Game Physics Engine"; what the
//! project takes from it, section by section, is in docs/paper.md in the repository.
//!
//! ```text
//! space-foosball screenshot --screen <name|all> --out <file.png|DIR> [--width 1280] [--height 720]
//! space-foosball play [--board auto|usb|emulated|socket[:PATH]] [--table standard] [--fullscreen]
//! space-foosball play --headless [--seed N] [--goals N] [--table standard|paper|FILE] [--script FILE]
//! space-foosball bench match [--json] [--steps N] [--table standard|paper|FILE]
//! space-foosball bench render [--frames 120] [--width W --height H]
//! space-foosball bench rollback [--repeats 50] [--table standard|paper|FILE]
//! space-foosball play --headless --record FILE … ; space-foosball replay FILE [--home player] [--format text]
//! space-foosball board [live] [--board auto|usb|emulated|socket[:PATH] | --socket PATH] [--serial S] [--once | --frames N] [--format text|json | --json]
//! space-foosball board info|ports|settings|bootloader [--board auto|usb|emulated] [--serial S] [--json]
//! space-foosball board set port.N.FIELD VALUE [--board auto|usb|emulated] [--serial S] [--json]
//! space-foosball history [--json] [--limit N] [--history FILE]
//! space-foosball host --peer ADDRESS [--port 7000] [--script FILE] [--max-frames N] …
//! space-foosball join ADDRESS [--port 7001] [--script FILE] [--max-frames N] …
//! ```

mod bench;
mod board_tool;
mod board_view;
mod event_text;
mod headless;
mod history;
mod online;
mod play;
mod render_bench;
mod replay;
mod rollback_bench;
mod screenshot;
mod window;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "space-foosball",
    version,
    about = "Space Foosball: a foosball match in space"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a screen offscreen to a PNG (any adapter, including Mesa's software
    /// Vulkan driver, lavapipe).
    Screenshot(screenshot::Args),
    /// Play in a window: the rods (or, with no board, keyboard, mouse and gamepad on
    /// the built-in emulated board) against the computer or a second player.
    Play(play::Args),
    /// Measure the game: `bench match` (µs per physics step, input-to-rod latency),
    /// `bench render` (frame time).
    Bench(bench::Args),
    /// Play a recorded match (`play --headless --record FILE`) back headless: the
    /// recorded match's events again.
    Replay(replay::Args),
    /// The sensor board: its health, live (the default: protocol version, device time,
    /// per paddle presence, packet age, dropped packets and motion, the report rate,
    /// the host's counters); `info`, `ports`, `settings`, `set KEY VALUE` and
    /// `bootloader` for its diagnostics and settings.
    Board(board_tool::Args),
    /// The matches kept (every windowed match, and headless ones with `--history`),
    /// newest first, with the top scorers and the fastest shot; `--json` for scripts.
    History(history::cli::Args),
    /// Host an online match (headless): this side plays Home against `join` at `--peer`,
    /// with rollback (GGRS) over UDP; prints the outcome as one JSON line.
    Host(online::cli::HostArgs),
    /// Join an online match (headless) hosted at ADDRESS: this side plays Away.
    Join(online::cli::JoinArgs),
}

fn main() -> ExitCode {
    quiet_vulkan_device_select();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let result = match cli.command {
        Command::Screenshot(args) => screenshot::run(&args),
        Command::Play(args) => play::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Replay(args) => replay::run(&args),
        Command::Board(args) => board_tool::run(&args),
        Command::History(args) => history::cli::run(&args),
        Command::Host(args) => online::cli::host(&args),
        Command::Join(args) => online::cli::join(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line, whatever RUST_BACKTRACE says: `{:#}` is the error with its
            // causes, never anyhow's backtrace.
            eprintln!("space-foosball: error: {}", one_line(&format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}

/// A command-line mistake as one line and exit code 1; `--help` and `--version` print
/// as usual and succeed.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        let _ = e.print();
        return ExitCode::FAILURE;
    }
    let text = e.to_string();
    // clap's message up to its usage block, folded onto one line.
    let message = text.split("Usage:").next().unwrap_or_default().trim();
    let first = message.strip_prefix("error:").unwrap_or(message).trim();
    let first = if first.is_empty() {
        "invalid arguments"
    } else {
        first
    };
    eprintln!("space-foosball: error: {} (see --help)", one_line(first));
    ExitCode::FAILURE
}

/// `s` with its line breaks folded into spaces.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Silences `error: XDG_RUNTIME_DIR is invalid or not set in the environment.`, which
/// Mesa's Vulkan device-selection layer (`VK_LAYER_MESA_device_select`) prints twice
/// at every start when there is no Wayland session: it tries to connect to Wayland to
/// find the default GPU. Without a valid `XDG_RUNTIME_DIR` (and no `WAYLAND_DISPLAY`)
/// there is no Wayland to ask, so the layer is switched off with its own switch,
/// `NODEVICE_SELECT=1`; wgpu chooses the adapter itself either way. Runs first in
/// `main`, before any thread exists.
fn quiet_vulkan_device_select() {
    let runtime_ok =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    let wayland = std::env::var_os("WAYLAND_DISPLAY").is_some_and(|d| !d.is_empty());
    if !runtime_ok && !wayland && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}
