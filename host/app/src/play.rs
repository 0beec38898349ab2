//! `space-foosball play`. The match itself (physics, window, rods) arrives with the
//! physics match issue; until then `play` says plainly what is and is not there and
//! where to go instead, and exits non-zero. It never pretends to play.

use anyhow::{bail, Result};

/// Arguments of `space-foosball play` (none yet: board choice, players and
/// `--headless` arrive with the match).
#[derive(clap::Args, Debug)]
pub struct Args {}

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

/// What to run instead, shared by both messages.
const ALTERNATIVES: &str = "Play without a window with `space-foosball play --headless` \
(arrives with the match), or render the screens with \
`space-foosball screenshot --screen all --out DIR`.";

/// Explains why there is no match to play here and fails.
pub fn run(_args: &Args) -> Result<()> {
    match display() {
        None => bail!(
            "no display found (neither DISPLAY nor WAYLAND_DISPLAY is set), so no window \
             can open. {ALTERNATIVES}"
        ),
        Some(d) => bail!(
            "display found ({d}), but the windowed match is not built yet: it arrives with \
             the physics match issue. {ALTERNATIVES}"
        ),
    }
}
