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
//! ```

mod bench;
mod headless;
mod play;
mod render_bench;
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
    /// Measure the game: `bench match` (µs per physics step, input-to-rod latency).
    Bench(bench::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Screenshot(args) => screenshot::run(&args),
        Command::Play(args) => play::run(&args),
        Command::Bench(args) => bench::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("space-foosball: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
