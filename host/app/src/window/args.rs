//! The command-line options of the windowed `play`.

use super::board::BoardChoice;
use super::script::Script;
use super::WindowOptions;
use anyhow::{bail, Result};
use foosball_render::PresentChoice;
use std::path::{Path, PathBuf};

/// Options of `space-foosball play` for the window.
#[derive(clap::Args, Debug, Clone)]
pub struct WindowArgs {
    /// The board: auto (USB if plugged in, else the built-in emulated board driven by
    /// keyboard, mouse and gamepad), usb, emulated, socket (the `sim serve` emulator at
    /// its default path) or socket:PATH.
    #[arg(long, default_value = "auto", value_parser = parse_board)]
    pub board: BoardChoice,
    /// The table: a preset (standard, paper) or a TOML file.
    #[arg(long, default_value = "standard")]
    pub table: String,
    /// Window width, pixels.
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Window height, pixels.
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// Borderless fullscreen (the cabinet).
    #[arg(long)]
    pub fullscreen: bool,
    /// Present with the lowest latency the adapter offers (mailbox) instead of vsync.
    #[arg(long)]
    pub low_latency: bool,
    /// Seed of the first match's serves.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The calibration file (default: $XDG_CONFIG_HOME/space-foosball/calibration.json
    /// or ~/.config/space-foosball/calibration.json).
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// Start in calibration mode.
    #[arg(long)]
    pub calibrate: bool,
    /// The match history every finished match is kept in (SQLite; see `space-foosball
    /// history`; default: `$SPACE_FOOSBALL_HISTORY`, else
    /// ~/.local/share/space-foosball/history.sqlite3). Headless play keeps its match only
    /// where this is given.
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
    /// Quit this many seconds after the first frame showed (unattended checks).
    #[arg(long, hide = true)]
    pub exit_after_s: Option<f64>,
    /// Write the frame the window presents last (at --exit-after-s) to this PNG.
    #[arg(long, hide = true, requires = "exit_after_s")]
    pub capture_window: Option<PathBuf>,
    /// Scripted key presses: `start`, or SECONDS:KEY[+|-],… (see `space_foosball_front::script`).
    #[arg(long, hide = true, value_parser = parse_script)]
    pub demo_input: Option<Script>,
}

fn parse_board(s: &str) -> Result<BoardChoice, String> {
    s.parse()
}

fn parse_script(s: &str) -> Result<Script, String> {
    s.parse()
}

/// The default calibration file.
pub fn default_calibration_path() -> Option<PathBuf> {
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
        .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".config")))?;
    Some(config.join("space-foosball").join("calibration.json"))
}

impl WindowArgs {
    /// Checks the options and turns them into [`WindowOptions`].
    pub fn options(&self) -> Result<WindowOptions> {
        for (name, v) in [("--width", self.width), ("--height", self.height)] {
            if !(64..=foosball_render::MAX_SIDE).contains(&v) {
                bail!(
                    "{name} {v} is not allowed (64..={} pixels)",
                    foosball_render::MAX_SIDE
                );
            }
        }
        if let Some(s) = self.exit_after_s {
            if !(s.is_finite() && s > 0.0) {
                bail!("--exit-after-s must be a positive number of seconds, not {s}");
            }
        }
        if let Some(path) = &self.capture_window {
            let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
            if dir.is_some_and(|d| !d.is_dir()) {
                bail!("--capture-window {}: no such directory", path.display());
            }
            if path.is_dir() {
                bail!("--capture-window {} is a directory", path.display());
            }
        }
        Ok(WindowOptions {
            board: self.board.clone(),
            table: crate::headless::load_table(&self.table)?,
            size: (self.width, self.height),
            fullscreen: self.fullscreen,
            present: if self.low_latency {
                PresentChoice::LowLatency
            } else {
                PresentChoice::Vsync
            },
            seed: self.seed,
            calibration_path: self.calibration.clone().or_else(default_calibration_path),
            calibrate: self.calibrate,
            history_path: match &self.history {
                Some(p) => Some(p.clone()),
                // No home folder: play goes on, keeping no history.
                None => crate::history::store::default_path().ok(),
            },
            exit_after_s: self.exit_after_s,
            capture_window: self.capture_window.clone(),
            script: self.demo_input.clone().unwrap_or_default(),
        })
    }
}
