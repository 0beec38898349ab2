//! `space-foosball`: the Space Foosball program, the composition root that joins the
//! game, the renderer, the sound and the board.
//!
//! ```text
//! space-foosball screenshot --screen <name|all> --out <file.png|DIR> [--width 1280] [--height 720]
//! space-foosball play
//! ```

mod play;
mod screenshot;

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
    /// Play a match (needs a display; the match arrives with the physics match issue).
    Play(play::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Screenshot(args) => screenshot::run(&args),
        Command::Play(args) => play::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("space-foosball: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
