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

/// Writes a motion script in `dir` in which every Home rod (ports 0, 1, 3, 5) holds for 1 s,
/// then spins at −12 rad/s for the rest of the match; returns its path.
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn spinning_home_script(dir: &std::path::Path) -> std::path::PathBuf {
    let script = dir.join("spin.json");
    let tracks: Vec<String> = [0, 1, 3, 5]
        .iter()
        .map(|port| {
            format!(
                r#"{{"rod":{port},"segments":[{{"hold":{{"duration_s":1.0}}}},
                {{"velocity":{{"duration_s":600,"angle_rad_per_s":-12.0}}}}]}}"#
            )
        })
        .collect();
    std::fs::write(&script, format!(r#"{{"rods":[{}]}}"#, tracks.join(","))).unwrap();
    script
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
/// from [`spinning_home_script`] (written in `dir`), with `extra` arguments; its output.
#[allow(dead_code)] // used by some of the test binaries that include this module
pub fn play_spinning_home(dir: &std::path::Path, extra: &[&str]) -> Output {
    let script = spinning_home_script(dir);
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
