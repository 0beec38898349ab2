//! `space-foosball play`: the match in a window (see `window`). Without a display it
//! says so plainly, points to headless play and screenshots, and exits non-zero.

use anyhow::{bail, Result};

/// Arguments of `space-foosball play`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The window's options.
    #[command(flatten)]
    pub window: crate::window::args::WindowArgs,
    /// Headless play (`--headless`, `--goals`, `--script`; uses `--table`, `--seed`).
    #[command(flatten)]
    pub headless: crate::headless::HeadlessArgs,
}

/// The environment variables that name a display, in the order checked.
const DISPLAY_VARS: [&str; 2] = ["WAYLAND_DISPLAY", "DISPLAY"];

/// The display this process could open a window on, as `VAR=value`; `None` when
/// neither `WAYLAND_DISPLAY` nor `DISPLAY` is set (to a non-empty value).
pub fn display() -> Option<String> {
    DISPLAY_VARS.iter().find_map(|var| {
        std::env::var(var)
            .ok()
            .filter(|v| !v.trim().is_empty())
            .map(|v| format!("{var}={v}"))
    })
}

/// What to run instead when there is no display.
const ALTERNATIVES: &str = "Play without a window with `space-foosball play --headless`, \
or render the screens with `space-foosball screenshot --screen all --out DIR`.";

/// Plays in a window; without a display, explains where to go instead and fails.
pub fn run(args: &Args) -> Result<()> {
    if args.headless.headless {
        return crate::headless::run(
            &args.headless,
            &args.window.table,
            args.window.seed,
            args.window.history.as_deref(),
        );
    }
    let options = args.window.options()?;
    if display().is_none() {
        bail!(
            "no display found (neither DISPLAY nor WAYLAND_DISPLAY is set), so no window \
             can open. {ALTERNATIVES}"
        );
    }
    crate::window::run(options)
}
