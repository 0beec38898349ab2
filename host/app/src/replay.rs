//! `space-foosball replay FILE`: a recorded match (`play --headless --record FILE`)
//! played back headless: the same physics, rules and computer fed the recorded rod
//! input step by step reproduce the recorded match's events, printed as headless play
//! prints them (`--format json|text`).

use crate::headless::{print_event, Format};
use anyhow::{Context, Result};
use space_foosball::play::{Match, RodController};
use space_foosball::recording::MatchRecording;
use std::io::Write;
use std::path::PathBuf;

/// Who played a team in the recorded match.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Who {
    /// The computer (its rods' recorded input is ignored, as it was).
    Computer,
    /// A person or a motion script through the board (the recorded input moves its rods).
    Player,
}

/// Arguments of `space-foosball replay`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The recording (JSON, from `play --headless --record FILE`).
    pub file: PathBuf,
    /// Who played Home when it was recorded (`play --headless --script` records Home
    /// as the player).
    #[arg(long, value_enum, default_value = "computer")]
    pub home: Who,
    /// Who played Away when it was recorded.
    #[arg(long, value_enum, default_value = "computer")]
    pub away: Who,
    /// How events are printed: `json` or `text`.
    #[arg(long, value_enum, default_value = "json")]
    pub format: Format,
    /// End with one more JSON line: the replayed match's score, steps and state checksum
    /// (what an online match's sides print as `state_hash`).
    #[arg(long)]
    pub state_hash: bool,
}

fn controller(w: Who) -> RodController {
    match w {
        Who::Computer => RodController::Computer,
        Who::Player => RodController::Player,
    }
}

/// Replays the recording and prints its events.
pub fn run(args: &Args) -> Result<()> {
    let recording = MatchRecording::load(&args.file)
        .map_err(|e| anyhow::anyhow!("{e}"))
        .with_context(|| format!("recording {}", args.file.display()))?;
    let (m, events) = Match::replay(&recording, [controller(args.home), controller(args.away)])
        .context("replaying")?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    for e in &events {
        print_event(&mut out, e, args.format, &recording.table)?;
    }
    if args.state_hash {
        writeln!(
            out,
            "{}",
            serde_json::json!({
                "score": m.score(),
                "time_ms": m.time_ms(),
                "state_hash": format!("{:032x}", m.state_hash()),
            })
        )?;
    }
    out.flush()?;
    Ok(())
}
