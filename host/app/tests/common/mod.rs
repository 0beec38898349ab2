//! Shared by the app's end-to-end tests that run the binary without a window.

use std::process::{Command, Output};

/// The `space-foosball` binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_space-foosball");

/// Runs `space-foosball ARGS` with no display (so nothing can open a window).
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run space-foosball")
}

/// The committed motion script in which every Home rod (ports 0, 1, 3, 5) holds for 1 s,
/// then spins at −12 rad/s for the rest of the match (`sim/scripts/spin-home.json`).
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn spinning_home_script() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sim/scripts/spin-home.json")
}

/// Runs `space-foosball ARGS` as [`run`] does and fails the test, with its stderr, unless
/// it succeeds.
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn run_ok(args: &[&str]) -> Output {
    let out = run(args);
    assert!(
        out.status.success(),
        "space-foosball {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Plays a one-goal headless match (seed 2) in which Home plays through the emulated board
/// from [`spinning_home_script`], with `extra` arguments; its output.
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn play_spinning_home(extra: &[&str]) -> Output {
    let script = spinning_home_script();
    let mut args = vec![
        "play",
        "--headless",
        "--seed",
        "2",
        "--goals",
        "1",
        "--script",
        script.to_str().expect("a UTF-8 path"),
    ];
    args.extend_from_slice(extra);
    run_ok(&args)
}
