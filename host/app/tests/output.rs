//! Headless output forms end to end: `--format text` and `--audio-out FILE.wav`, and
//! the one-line user errors.

mod common;

use common::{play_spinning_home, run, run_ok};
use std::process::Command;

#[test]
fn text_format_is_readable_and_tells_the_same_match_as_json() {
    let args = ["play", "--headless", "--seed", "3", "--goals", "1"];
    let json = run(&args);
    let text = run(&[&args[..], &["--format", "text"]].concat());
    assert!(
        text.status.success(),
        "{}",
        String::from_utf8_lossy(&text.stderr)
    );
    let json = String::from_utf8(json.stdout).unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    // One line per event, the same number as JSON lines.
    assert_eq!(text.lines().count(), json.lines().count());
    let first = text.lines().next().unwrap();
    assert_eq!(first, "   0.500 s  serve    to home (kickoff)", "{first}");
    // Rounded figures: every number has at most three decimals; no JSON.
    for line in text.lines() {
        assert!(!line.contains('{'), "{line}");
        for word in line.split([' ', ',', '(', ')']) {
            if let Some((_, frac)) = word.split_once('.') {
                if word.parse::<f64>().is_ok() {
                    assert!(frac.len() <= 3, "{line}");
                }
            }
        }
    }
    let goals = text.lines().filter(|l| l.contains("GOAL")).count();
    assert_eq!(goals, 1);
    let last = text.lines().last().unwrap();
    assert!(
        last.starts_with("match over: 1-0, home wins")
            || last.starts_with("match over: 0-1, away wins"),
        "{last}"
    );
}

/// The WAV's samples (16-bit mono after the 44-byte header) as `-1…1`.
fn samples(wav: &[u8]) -> Vec<f32> {
    assert_eq!(&wav[0..4], b"RIFF");
    assert_eq!(u16::from_le_bytes([wav[22], wav[23]]), 1, "mono");
    assert_eq!(u32::from_le_bytes(wav[24..28].try_into().unwrap()), 48_000);
    wav[44..]
        .chunks_exact(2)
        .map(|c| i16::from_le_bytes([c[0], c[1]]) as f32 / 32767.0)
        .collect()
}

/// RMS level of `s` over `[t0, t1)` s.
fn level(s: &[f32], t0: f64, t1: f64) -> f32 {
    let (a, b) = (
        (t0 * 48_000.0) as usize,
        ((t1 * 48_000.0) as usize).min(s.len()),
    );
    let part = &s[a.min(b)..b];
    (part.iter().map(|x| x * x).sum::<f32>() / part.len().max(1) as f32).sqrt()
}

#[test]
fn audio_out_holds_the_kicks_and_the_goal_fanfare_where_the_events_say() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("match.wav");
    let out = run(&[
        "play",
        "--headless",
        "--seed",
        "3",
        "--goals",
        "1",
        "--audio-out",
        wav.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let events: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let s = samples(&std::fs::read(&wav).unwrap());
    // No temporary file left beside it.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    let time = |e: &serde_json::Value| e["t_ms"].as_u64().unwrap() as f64 / 1000.0;
    let goal = time(events.iter().find(|e| e["event"] == "Goal").unwrap());
    // The file lasts to the end of the fanfare (1.6 s after the goal).
    let dur = s.len() as f64 / 48_000.0;
    assert!(
        (dur - (goal + 1.6)).abs() < 0.01,
        "{dur} s vs goal at {goal} s"
    );
    // Quiet before the kickoff serve's first contact: the first event with a sound.
    let first_sound = events
        .iter()
        .filter(|e| {
            e["event"] == "Kick" || (e["event"] == "Bounce" && e["speed"].as_f64().unwrap() >= 0.25)
        })
        .map(time)
        .next()
        .unwrap();
    assert!(level(&s, 0.0, first_sound - 0.001) == 0.0);
    // A kick: loud in the 20 ms after it (the kick's peak is 0.2…0.9, 150 ms long).
    let kick = events
        .iter()
        .find(|e| e["event"] == "Kick" && e["speed"].as_f64().unwrap() > 2.0)
        .unwrap();
    assert!(
        level(&s, time(kick), time(kick) + 0.02) > 0.05,
        "kick at {}",
        time(kick)
    );
    // The fanfare: loud for its 1.6 s, and louder than any 1.6 s of play before it
    // (its peak 0.8 is held; kicks are 150 ms bursts).
    let fanfare = level(&s, goal + 0.05, goal + 1.5);
    assert!(fanfare > 0.15, "fanfare level {fanfare}");
    let mut t = 0.0;
    while t + 1.6 < goal - 0.2 {
        assert!(level(&s, t, t + 1.45) < fanfare, "{t} s");
        t += 0.8;
    }
}

#[test]
fn user_errors_are_one_line_without_backtrace_and_exit_1() {
    for args in [
        vec!["play", "--headless", "--goals", "0"],
        vec!["play", "--headless", "--table", "/no/such.toml"],
        vec!["play", "--bogus"],
        vec!["play", "--headless", "--audio-out", "/no/such/dir/x.wav"],
    ] {
        let out = Command::new(common::BIN)
            .args(&args)
            .env("RUST_BACKTRACE", "full")
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("space-foosball: error: "), "{err}");
        assert!(!err.contains("backtrace"), "{err}");
    }
}

#[test]
fn replay_reproduces_the_recorded_match_events() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("match.json");
    // Home played through the emulated board by a script (every Home rod spinning),
    // so the recorded input decides the match.
    let played = play_spinning_home(&["--record", rec.to_str().unwrap()]);
    let replayed = run_ok(&["replay", rec.to_str().unwrap(), "--home", "player"]);
    // Event for event, bit for bit (JSON keeps every digit).
    let (a, b) = (
        String::from_utf8(played.stdout).unwrap(),
        String::from_utf8(replayed.stdout).unwrap(),
    );
    assert!(a.lines().count() > 10);
    assert_eq!(a, b);
    // A file that is not a recording: one line, exit 1.
    std::fs::write(&rec, "{\"seed\": 1}").unwrap();
    let bad = run(&["replay", rec.to_str().unwrap()]);
    assert_eq!(bad.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr)
            .trim_end()
            .lines()
            .count(),
        1
    );
}
