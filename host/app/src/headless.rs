//! `space-foosball play --headless`: a match with no window, as fast as the CPU allows.
//!
//! The computer plays both sides, or, with `--script FILE`, the Home team is played
//! through the built-in emulated board (lockstep: one 1 ms report per physics step)
//! following the scripted rod motion (`foosball-sim` motion script JSON) against the
//! computer. Every event is printed as a JSON line (`{"t_ms":…,"event":"Kick",…}`); the
//! last line is the final score, exactly `{"event":"MatchOver","score":[a,b]}`.

use anyhow::{bail, Context, Result};
use board_link::Board;
use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{
    BoardInput, RodInputs, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS,
};
use space_foosball::play::{idle_inputs, Match, MatchConfig};
use space_foosball::rules::{Event, RulesConfig};
use space_foosball::table::presets;
use space_foosball::Table;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Longest headless match, ms of match time: a match that has not ended by then is
/// reported as an error (the computer against itself ends in a few minutes).
pub const MAX_MATCH_MS: u64 = 60 * 60 * 1000;

/// Options of headless play (`--table` and `--seed` are shared with the windowed game).
#[derive(clap::Args, Debug, Clone)]
pub struct HeadlessArgs {
    /// Play without a window: events as JSON lines on stdout, as fast as possible.
    #[arg(long)]
    pub headless: bool,
    /// Goals that win the match (headless; 1–99).
    #[arg(long, default_value_t = 5, requires = "headless")]
    pub goals: u32,
    /// Play the Home team through the emulated board following this motion script
    /// (JSON, see sim/README.md) instead of the computer (headless).
    #[arg(long, value_name = "FILE", requires = "headless")]
    pub script: Option<PathBuf>,
}

/// A table by preset name (`standard`, `paper`) or TOML file.
pub fn load_table(name: &str) -> Result<Table> {
    if presets::NAMES.contains(&name) {
        return Table::preset(name).with_context(|| format!("table preset {name:?}"));
    }
    let path = Path::new(name);
    if !path.exists() {
        bail!(
            "no table {name:?}: not a preset ({}) and no such file",
            presets::NAMES.join(", ")
        );
    }
    Table::load(path).with_context(|| format!("table file {}", path.display()))
}

/// Where a headless match gets its rod inputs.
enum Input {
    /// Computer against computer: the input is ignored.
    Idle(RodInputs),
    /// The emulated board following a script, in lockstep.
    Board(Box<BoardInput<InProcessBoard>>),
}

impl Input {
    fn next(&mut self) -> RodInputs {
        match self {
            Input::Idle(inputs) => inputs.clone(),
            Input::Board(board) => board.poll(1),
        }
    }
}

/// Plays a headless match on `table` (name or file) with `seed`, printing its events.
pub fn run(args: &HeadlessArgs, table: &str, seed: u64) -> Result<()> {
    if !(1..=99).contains(&args.goals) {
        bail!("--goals must be 1–99, got {}", args.goals);
    }
    let table = load_table(table)?;
    let rules = RulesConfig {
        goals_to_win: args.goals,
        ..RulesConfig::default()
    };
    let (mut config, mut input) = match &args.script {
        None => (
            MatchConfig::computer_vs_computer(table.clone(), seed),
            Input::Idle(idle_inputs(&table)),
        ),
        Some(path) => {
            // The script error names the file and says what is wrong.
            let script = MotionScript::load(path).map_err(|e| anyhow::anyhow!("{e}"))?;
            let board_config = BoardConfig {
                seed,
                ..BoardConfig::default()
            };
            let board =
                InProcessBoard::with_motion(board_config, Box::new(script), Pacing::Lockstep)
                    .context("emulated board")?;
            let name = board.name();
            let mut input = BoardInput::new(board, &table, Calibration::default());
            input
                .tracker_mut()
                .set_prediction_ms(MOUSE_PACKET_PREDICTION_MS);
            input.tracker_mut().set_prediction_lead_ms(PS2_WIRE_LEAD_MS);
            eprintln!("space-foosball: Home plays through the {name}");
            (
                MatchConfig::player_vs_computer(table.clone(), seed),
                Input::Board(Box::new(input)),
            )
        }
    };
    config.rules = rules;
    let mut m = Match::new(config).context("match")?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut over = None;
    while over.is_none() {
        if m.time_ms() >= MAX_MATCH_MS {
            out.flush().ok();
            bail!(
                "the match did not end within {} minutes of match time (score {:?})",
                MAX_MATCH_MS / 60_000,
                m.score()
            );
        }
        let inputs = input.next();
        for e in m.step(&inputs) {
            match e.event {
                Event::MatchOver { .. } => over = Some(e.event),
                _ => writeln!(out, "{}", serde_json::to_string(&e)?)?,
            }
        }
    }
    if let Some(event) = over {
        writeln!(out, "{}", serde_json::to_string(&event)?)?;
    }
    out.flush()?;
    Ok(())
}
