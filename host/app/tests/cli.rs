//! The `space-foosball` binary end to end: screenshots of every screen (decoded and
//! checked), argument errors, and `play` without a display.
//!
//! Screenshots need a graphics adapter; CI has Mesa's software Vulkan driver (Debian
//! `mesa-vulkan-drivers`). As in `foosball-render`'s picture tests: with no adapter
//! these tests **fail** when `CI` is set and are skipped with a notice otherwise.

use std::path::Path;
use std::process::{Command, Output};

mod common;

use common::{run, BIN};
const SCREENS: [&str; 7] = [
    "attract",
    "character-select",
    "match",
    "goal-ceremony",
    "final-result",
    "board-lost",
    "calibration",
];

/// Runs `space-foosball screenshot --screen SCREEN --out OUT --width W --height H`.
fn screenshot(screen: &str, out: &std::path::Path, width: u32, height: u32) -> Output {
    let (w, h) = (width.to_string(), height.to_string());
    run(&[
        "screenshot",
        "--screen",
        screen,
        "--out",
        out.to_str().unwrap(),
        "--width",
        &w,
        "--height",
        &h,
    ])
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `false` (skip) when the run failed only for want of a graphics adapter outside CI;
/// panics on that in CI.
fn adapter_present(o: &Output) -> bool {
    let err = stderr(o);
    if o.status.success() || !err.contains("no graphics adapter found") {
        return true;
    }
    if std::env::var_os("CI").is_some() {
        panic!(
            "CI is set but space-foosball-app cannot render screenshots (install \
             mesa-vulkan-drivers): {err}"
        );
    }
    eprintln!("NOTICE: skipping space-foosball-app screenshot test: {err}");
    false
}

/// Decodes a PNG: (width, height, RGB(A) bytes, bytes per pixel).
fn decode(path: &Path) -> (u32, u32, Vec<u8>, usize) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap_or_else(|e| panic!("{} is not a PNG: {e}", path.display()));
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    buf.truncate(info.buffer_size());
    let bpp = info.color_type.samples() * usize::from(info.bit_depth as u8 / 8);
    (info.width, info.height, buf, bpp)
}

/// Distinct colours and the spread of brightness: a real picture, not a flat fill.
fn assert_not_uniform(name: &str, pixels: &[u8], bpp: usize) {
    let px: Vec<&[u8]> = pixels.chunks_exact(bpp).collect();
    let mut colours: Vec<[u8; 3]> = px.iter().map(|p| [p[0], p[1], p[2]]).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() > 100,
        "{name}: only {} colours",
        colours.len()
    );
    let lum: Vec<f64> = px
        .iter()
        .map(|p| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]))
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    let var = lum.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lum.len() as f64;
    assert!(var.sqrt() > 20.0, "{name}: brightness barely varies");
}

#[test]
fn screenshot_all_writes_a_valid_png_of_every_screen() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("shots");
    let o = screenshot("all", &out, 320, 180);
    if !adapter_present(&o) {
        return;
    }
    assert!(o.status.success(), "screenshot failed: {}", stderr(&o));
    let mut pictures = Vec::new();
    for name in SCREENS {
        let (w, h, px, bpp) = decode(&out.join(format!("{name}.png")));
        assert_eq!((w, h), (320, 180), "{name}: size");
        assert_not_uniform(name, &px, bpp);
        pictures.push(px);
    }
    // Each screen is its own picture (overlays differ).
    for i in 0..pictures.len() {
        for j in i + 1..pictures.len() {
            assert_ne!(pictures[i], pictures[j], "{} = {}", SCREENS[i], SCREENS[j]);
        }
    }
    // Nothing but the seven PNGs: the temporary files were renamed away.
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut want: Vec<String> = SCREENS.iter().map(|s| format!("{s}.png")).collect();
    want.sort();
    assert_eq!(names, want);
}

#[test]
fn screenshot_of_one_screen_has_the_asked_size_and_replaces_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("match.png");
    std::fs::write(&file, b"old content").unwrap();
    let o = screenshot("match", &file, 200, 150);
    if !adapter_present(&o) {
        return;
    }
    assert!(o.status.success(), "screenshot failed: {}", stderr(&o));
    let (w, h, px, bpp) = decode(&file);
    assert_eq!((w, h), (200, 150));
    assert_not_uniform("match", &px, bpp);
}

#[test]
fn unknown_screen_fails_and_lists_the_valid_ones() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("x.png");
    let o = run(&[
        "screenshot",
        "--screen",
        "lobby",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("lobby"), "{err}");
    for name in SCREENS.iter().chain(&["all"]) {
        assert!(err.contains(name), "valid screen {name} not listed: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!file.exists());
}

#[test]
fn bad_sizes_and_paths_fail_clearly_without_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("x.png");
    let f = file.to_str().unwrap();
    let missing_dir = dir.path().join("no/such/dir/x.png");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--width", "0"], "--width"),
        (vec!["--height", "0"], "--height"),
        (vec!["--width", "100000"], "--width"),
        (vec!["--height=-5"], "--height"),
    ];
    for (extra, word) in cases {
        let mut args = vec!["screenshot", "--screen", "match", "--out", f];
        args.extend(&extra);
        let o = run(&args);
        let err = stderr(&o);
        assert!(!o.status.success(), "{extra:?} accepted");
        assert!(err.contains(word), "{extra:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let o = run(&[
        "screenshot",
        "--screen",
        "match",
        "--out",
        missing_dir.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(err.contains("does not exist"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // A directory where a file is wanted, and a file where a directory is wanted.
    let o = run(&[
        "screenshot",
        "--screen",
        "match",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
    std::fs::write(&file, b"x").unwrap();
    let o = run(&["screenshot", "--screen", "all", "--out", f]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is a file"), "{}", stderr(&o));
}

#[test]
fn play_without_a_display_points_to_headless_play_and_screenshots() {
    let o = run(&["play"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("no display found"), "{err}");
    assert!(err.contains("space-foosball play --headless"), "{err}");
    assert!(err.contains("space-foosball screenshot"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn play_with_an_unreachable_display_fails_clearly() {
    let o = Command::new(BIN)
        // A display number no X server uses (xvfb-run -a takes :99 upwards); the exit
        // limit keeps the test finite should one answer after all.
        .args(["play", "--board", "emulated", "--exit-after-s", "3"])
        .env_remove("WAYLAND_DISPLAY")
        .env("DISPLAY", ":64999")
        .env("SPACE_FOOSBALL_AUDIO", "off")
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("could not connect to the display"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn play_arguments_are_checked_before_anything_opens() {
    let o = run(&["play", "--board", "serial"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("socket:PATH"), "{}", stderr(&o));
    let o = run(&["play", "--width", "10"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("--width 10 is not allowed"),
        "{}",
        stderr(&o)
    );
    let o = run(&["play", "--demo-input", "1:hyperspace"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("unknown key"), "{}", stderr(&o));
    let o = run(&[
        "play",
        "--exit-after-s",
        "2",
        "--capture-window",
        "/nonexistent/x.png",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no such directory"), "{}", stderr(&o));
}
