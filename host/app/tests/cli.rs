//! The `space-foosball` command line: screenshots of every screen, bad arguments, and
//! `play` without a display.

use std::path::Path;
use std::process::{Command, Output};

fn space_foosball(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_space-foosball"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the space-foosball binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Decodes a PNG, returning (width, height, RGBA bytes).
fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).expect("PNG exists"));
    let mut reader = decoder.read_info().expect("valid PNG header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("valid PNG data");
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn screenshots_of_every_screen_are_valid_non_uniform_pngs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shots");
    let run = space_foosball(&[
        "screenshot",
        "--screen",
        "all",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "320",
        "--height",
        "180",
    ]);
    if !run.status.success() && stderr(&run).contains("mesa-vulkan-drivers") {
        // No adapter: the render crate's convention — fail in CI, skip elsewhere.
        assert!(
            std::env::var_os("CI").is_none(),
            "no graphics adapter in CI: {}",
            stderr(&run)
        );
        eprintln!("skipped: no graphics adapter ({})", stderr(&run));
        return;
    }
    assert!(run.status.success(), "screenshot failed: {}", stderr(&run));
    let names = [
        "attract",
        "character-select",
        "match",
        "goal-ceremony",
        "final-result",
        "board-lost",
        "calibration",
    ];
    for name in names {
        let (w, h, rgba) = read_png(&out.join(format!("{name}.png")));
        assert_eq!((w, h), (320, 180), "{name}");
        let first = &rgba[..4];
        assert!(
            rgba.chunks_exact(4).any(|px| px != first),
            "{name}.png is a single colour"
        );
    }
}

#[test]
fn unknown_screen_lists_the_valid_ones() {
    let run = space_foosball(&["screenshot", "--screen", "lobby", "--out", "x.png"]);
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(
        err.contains("lobby") && err.contains("goal-ceremony"),
        "{err}"
    );
}

#[test]
fn zero_size_is_rejected() {
    let run = space_foosball(&[
        "screenshot",
        "--screen",
        "match",
        "--out",
        "x.png",
        "--width",
        "0",
    ]);
    assert!(!run.status.success());
    assert!(stderr(&run).contains("width"), "{}", stderr(&run));
}

#[test]
fn play_without_a_display_points_to_headless_play() {
    let run = space_foosball(&["play"]);
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(err.contains("no display found"), "{err}");
    assert!(err.contains("--headless"), "{err}");
}
