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
