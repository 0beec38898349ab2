//! `space-foosball play --headless` and `bench match` end to end: the event stream,
//! its last line, the scripted board, and bad arguments.

use std::process::Output;

mod common;

use common::{play_spinning_home, run};

fn lines(out: &Output) -> Vec<serde_json::Value> {
    String::from_utf8(out.stdout.clone())
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON: {l:?}: {e}")))
        .collect()
}

#[test]
fn computer_against_computer_prints_events_and_ends_with_the_score() {
    let out = run(&["play", "--headless", "--seed", "3", "--goals", "1"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let events = lines(&out);
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    let last = text.lines().last().unwrap();
    // Exactly this shape: no match time, the final score.
    let score = &events.last().unwrap()["score"];
    assert_eq!(
        last,
        format!(
            r#"{{"event":"MatchOver","score":[{},{}]}}"#,
            score[0], score[1]
        )
    );
    let [a, b] = [score[0].as_u64().unwrap(), score[1].as_u64().unwrap()];
    assert_eq!(a.max(b), 1);
    assert_eq!(a.min(b), 0);
    // The stream: a kickoff first, a goal, kicks, all with match times in order.
    assert_eq!(events[0]["event"], "Serve");
    assert_eq!(events[0]["reason"], "kickoff");
    assert!(events.iter().any(|e| e["event"] == "Goal"));
    assert!(events.iter().any(|e| e["event"] == "Kick"));
    let times: Vec<u64> = events[..events.len() - 1]
        .iter()
        .map(|e| e["t_ms"].as_u64().unwrap())
        .collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    // Deterministic: the same seed prints the same match.
    let again = run(&["play", "--headless", "--seed", "3", "--goals", "1"]);
    assert_eq!(again.stdout, out.stdout);
}

#[test]
fn a_scripted_board_plays_the_home_team() {
    // Every Home rod spins for the whole match (counting starts after 1 s).
    let out = play_spinning_home(&[]);
    let events = lines(&out);
    assert_eq!(events.last().unwrap()["event"], "MatchOver");
    // The board's rods kicked the ball (rods 0, 1, 3, 5 are Home's).
    assert!(
        events
            .iter()
            .any(|e| e["event"] == "Kick" && [0, 1, 3, 5].contains(&e["rod"].as_u64().unwrap())),
        "no kick by a board rod"
    );
}

#[test]
fn bad_arguments_and_files_are_clear_errors() {
    let cases: [(&[&str], &str); 5] = [
        (
            &["play", "--headless", "--goals", "0"],
            "--goals must be 1–99",
        ),
        (
            &["play", "--headless", "--table", "moon"],
            "no table \"moon\"",
        ),
        (
            &["play", "--headless", "--script", "/nonexistent/s.json"],
            "cannot read motion script",
        ),
        (&["play", "--headless", "--seed", "x"], "invalid value"),
        (&["play", "--goals", "3"], "--headless"),
    ];
    for (args, message) in cases {
        let out = run(args);
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // A table file that is not a table, a script that is not a script.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "name = 3").unwrap();
    let out = run(&["play", "--headless", "--table", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("table"));
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, r#"{"rods":[{"rod":9,"segments":[]}]}"#).unwrap();
    let out = run(&["play", "--headless", "--script", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("rod must be 0–7"), "{err}");
}

#[test]
fn bench_match_prints_the_measurements_as_json() {
    let out = run(&["bench", "match", "--json", "--steps", "300"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = lines(&out);
    assert_eq!(v.len(), 1);
    for key in ["step_us_median", "step_us_worst", "input_latency_ms"] {
        let x = v[0][key]
            .as_f64()
            .unwrap_or_else(|| panic!("{key}: {}", v[0]));
        assert!(x.is_finite() && x > 0.0, "{key} = {x}");
    }
    assert!(v[0]["step_us_worst"].as_f64() >= v[0]["step_us_median"].as_f64());
    assert_eq!(v[0]["steps"], 300);
}
