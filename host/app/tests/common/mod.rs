//! Shared by the app's end-to-end tests that run the binary without a window.

use std::process::{Command, Output};

/// The `space-foosball` binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_space-foosball");

/// Runs `space-foosball ARGS` with no display (so nothing can open a window).
pub fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run space-foosball")
}
