//! `space-foosball play --headless`: a match with no window, as fast as the CPU allows.
//!
//! The computer plays both sides, or, with `--script FILE`, the Home team is played
//! through the built-in emulated board (lockstep: one 1 ms report per physics step)
//! following the scripted rod motion (`foosball-sim` motion script JSON) against the
//! computer. Every event is printed as a JSON line (`{"t_ms":…,"event":"Kick",…}`); the
//! last line is the final score, exactly `{"event":"MatchOver","score":[a,b]}`. With
//! `--format text` the lines are readable instead ([`crate::event_text`]); with
//! `--audio-out FILE.wav` the match's mixed sound is written too.

use crate::event_text;
use crate::history::record::now_unix_s;
use crate::history::{HistoryStore, MatchRecord, Mode};
use crate::window::session::QUIET_BOUNCE_M_S;
use anyhow::{bail, Context, Result};
use board_link::Board;
use foosball_audio::{mix_timeline, offline::MAX_TIMELINE_S, wav_bytes, Sound};
use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::atomic_file::write_atomic;
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{
    BoardInput, RodInputs, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS,
};
use space_foosball::play::{idle_inputs, Match, MatchConfig};
use space_foosball::rules::{Event, RulesConfig, TimedEvent};
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
    /// How events are printed: `json` (one JSON object a line) or `text` (readable
    /// lines, rounded figures).
    #[arg(long, value_enum, default_value = "json", requires = "headless")]
    pub format: Format,
    /// Also write the match's mixed game sound (kicks, bounces, goal fanfares) to this
    /// WAV file (16-bit mono, 48 kHz; written to a temporary file, then renamed).
    #[arg(long, value_name = "FILE.wav", requires = "headless")]
    pub audio_out: Option<PathBuf>,
    /// Save the match's recording (seed, table, rules and every step's rod input, JSON)
    /// to this file, for `space-foosball replay` (about 0.3 MB per second of match).
    #[arg(long, value_name = "FILE", requires = "headless")]
    pub record: Option<PathBuf>,
}

/// How headless play prints its events.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// One JSON object a line.
    Json,
    /// Readable lines with rounded figures.
    Text,
}

/// The sound the game plays for an event (as the windowed game does), if any.
pub fn sound_of(e: &Event) -> Option<Sound> {
    match *e {
        Event::Kick { speed, .. } => Some(Sound::Kick {
            speed_m_s: speed as f32,
        }),
        Event::Bounce { speed } if speed >= QUIET_BOUNCE_M_S => Some(Sound::Bounce {
            speed_m_s: speed as f32,
        }),
        Event::Goal { .. } => Some(Sound::GoalFanfare),
        _ => None,
    }
}

/// The computer against itself on `table` (name or file) with `seed`, to 99 goals: a
/// match that does not end during a measurement.
pub(crate) fn endless_match(table: &str, seed: u64) -> Result<(Table, Match)> {
    let table = load_table(table)?;
    let m = space_foosball_front::online::rollback_timing::endless_match(&table, seed)
        .context("match")?;
    Ok((table, m))
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

/// Plays a headless match on `table` (name or file) with `seed`, printing its events; with
/// `history`, keeps it in that match history (headless play keeps none by default).
pub fn run(args: &HeadlessArgs, table: &str, seed: u64, history: Option<&Path>) -> Result<()> {
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
    for path in [&args.audio_out, &args.record].into_iter().flatten() {
        check_writable(path)?;
    }
    // A history that cannot be opened is an error before the match, not after it.
    let mut history = history.map(HistoryStore::open).transpose()?;
    let (home, away) = match &args.script {
        None => ("computer", "computer"),
        Some(_) => ("script", "computer"),
    };
    let mut m = Match::new(config).context("match")?;
    let mut events: Vec<TimedEvent> = Vec::new();
    let mut cues: Vec<(f64, Sound)> = Vec::new();
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
            if history.is_some() && matches!(e.event, Event::Kick { .. } | Event::MatchOver { .. })
            {
                events.push(e);
            }
            if let Some(s) = sound_of(&e.event) {
                cues.push((e.t_ms as f64 / 1000.0, s));
            }
            match e.event {
                Event::MatchOver { .. } => over = Some(e),
                _ => print_event(&mut out, &e, args.format, &table)?,
            }
        }
    }
    if let Some(e) = over {
        print_event(&mut out, &e, args.format, &table)?;
    }
    out.flush()?;
    if let Some(store) = &mut history {
        let record = MatchRecord::from_events(
            &events,
            &table,
            [home.to_string(), away.to_string()],
            Mode::Local,
            seed,
            now_unix_s(),
        )
        .context("the match's record: no end among its events")?;
        store.add(&record, Some(m.recording()))?;
    }
    if let Some(path) = &args.record {
        m.recording()
            .save(path)
            .map_err(|e| anyhow::anyhow!("saving the recording: {e}"))?;
    }
    if let Some(path) = &args.audio_out {
        let end_s = m.time_ms() as f64 / 1000.0 + f64::from(foosball_audio::synth::GOAL_FANFARE_S);
        if end_s > MAX_TIMELINE_S {
            bail!(
                "the match lasted {end_s:.0} s, longer than the {MAX_TIMELINE_S:.0} s \
                 --audio-out records"
            );
        }
        let wav = wav_bytes(&mix_timeline(&cues, end_s));
        write_atomic(path, &wav).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// Prints one event in `format`: a JSON object or a readable line; the match's end
/// exactly `{"event":"MatchOver","score":[a,b]}` (no match time) or its text line.
pub fn print_event(
    out: &mut impl Write,
    e: &TimedEvent,
    format: Format,
    table: &Table,
) -> Result<()> {
    match (e.event, format) {
        (Event::MatchOver { score }, Format::Text) => {
            writeln!(out, "{}", event_text::over_line(score))?
        }
        (Event::MatchOver { .. }, Format::Json) => {
            writeln!(out, "{}", serde_json::to_string(&e.event)?)?
        }
        (_, Format::Json) => writeln!(out, "{}", serde_json::to_string(e)?)?,
        (_, Format::Text) => writeln!(out, "{}", event_text::line(e, table))?,
    }
    Ok(())
}

/// Fails early (before the match) when `path` cannot be written: a directory, or in
/// a directory that does not exist.
fn check_writable(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!(
            "--audio-out {} is a directory; give a file name",
            path.display()
        );
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        bail!(
            "cannot write {}: directory {} does not exist",
            path.display(),
            parent.display()
        );
    }
    Ok(())
}
