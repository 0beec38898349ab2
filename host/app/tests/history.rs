//! `space-foosball history` and the headless matches kept in it: the list is what was
//! played, and a process killed at any moment leaves the database whole.

mod common;

use common::{play_spinning_home, run, run_ok, BIN};
use serde_json::Value;
use std::process::{Command, Stdio};
use std::time::Duration;

fn history_json(db: &std::path::Path) -> Value {
    let out = run(&["history", "--json", "--history", db.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

/// A match kept with `--history` keeps its replay beside it: written out with
/// `history --replay ID --out FILE`, it plays back event for event, bit for bit.
#[test]
fn a_kept_match_s_replay_plays_it_again() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("history.sqlite3");
    let played = play_spinning_home(&["--history", db.to_str().unwrap()]);
    let h = history_json(&db);
    let m = &h["matches"][0];
    assert_eq!(m["has_replay"], true);
    let id = m["id"].as_i64().unwrap().to_string();
    let file = dir.path().join("replay.json");
    run_ok(&[
        "history",
        "--history",
        db.to_str().unwrap(),
        "--replay",
        &id,
        "--out",
        file.to_str().unwrap(),
    ]);
    let replayed = run_ok(&["replay", file.to_str().unwrap(), "--home", "player"]);
    let (a, b) = (
        String::from_utf8(played.stdout).unwrap(),
        String::from_utf8(replayed.stdout).unwrap(),
    );
    assert!(a.lines().count() > 10);
    assert_eq!(a, b);
    // No such match: one line naming it, exit 1, no file written.
    let missing = dir.path().join("none.json");
    let out = run(&[
        "history",
        "--history",
        db.to_str().unwrap(),
        "--replay",
        "999",
        "--out",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no replay of match 999"));
    assert!(!missing.exists());
}

#[test]
fn the_matches_just_played_are_listed_newest_first_with_their_shots() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("history.sqlite3");
    let mut finals = Vec::new();
    for seed in ["3", "4"] {
        let out = run(&[
            "play",
            "--headless",
            "--goals",
            "2",
            "--seed",
            seed,
            "--history",
            db.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let last: Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
        finals.push(last["score"].clone());
        let kicks = text
            .lines()
            .filter(|l| l.contains(r#""event":"Kick""#))
            .count();
        finals.push(Value::from(kicks));
    }
    let h = history_json(&db);
    assert_eq!(h["integrity"], "ok");
    let matches = h["matches"].as_array().unwrap();
    assert_eq!(matches.len(), 2);
    // Newest first: the second match played is listed first.
    for (m, (score, kicks)) in matches
        .iter()
        .zip([(&finals[2], &finals[3]), (&finals[0], &finals[1])])
    {
        assert_eq!(&m["score"], score);
        assert_eq!(m["mode"], "local");
        assert_eq!(m["teams"], serde_json::json!(["computer", "computer"]));
        assert_eq!(
            m["shots"].as_array().unwrap().len() as u64,
            kicks.as_u64().unwrap()
        );
    }
    let fastest = matches
        .iter()
        .flat_map(|m| m["shots"].as_array().unwrap())
        .map(|s| s["speed_m_s"].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert_eq!(h["fastest_shot"]["speed_m_s"].as_f64().unwrap(), fastest);
    // The computer scored every goal of both matches.
    let goals: u64 = matches
        .iter()
        .flat_map(|m| m["score"].as_array().unwrap())
        .map(|g| g.as_u64().unwrap())
        .sum();
    assert_eq!(h["top_scorers"][0]["team"], "computer");
    assert_eq!(h["top_scorers"][0]["goals"].as_u64().unwrap(), goals);
}

/// Headless matches killed at moments spread over their run (some in play, some while
/// they write, some after): the database stays whole and holds only whole matches.
#[test]
fn a_process_killed_at_any_moment_leaves_the_history_whole() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("history.sqlite3");
    let mut finished = 0;
    let runs = 12;
    for k in 0..runs {
        let mut child = Command::new(BIN)
            .args([
                "play",
                "--headless",
                "--goals",
                "1",
                "--seed",
                &k.to_string(),
                "--history",
                db.to_str().unwrap(),
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // 0 to 330 ms: a one-goal match here takes some tens to hundreds of ms.
        std::thread::sleep(Duration::from_millis(30 * k as u64));
        let _ = child.kill();
        let status = child.wait().unwrap();
        finished += usize::from(status.success());
    }
    let h = history_json(&db);
    assert_eq!(h["integrity"], "ok");
    let matches = h["matches"].as_array().unwrap();
    // Every match that ended on its own is there; a killed one is there whole or not at all.
    assert!(
        (finished..=runs).contains(&matches.len()),
        "{} matches kept, {finished} of {runs} ended on their own",
        matches.len()
    );
    for m in matches {
        let score: Vec<u64> = m["score"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g.as_u64().unwrap())
            .collect();
        assert_eq!(score.iter().max(), Some(&1), "a whole one-goal match: {m}");
        assert!(m["duration_ms"].as_u64().unwrap() > 0);
    }
}

#[test]
fn a_file_that_is_not_a_history_is_named_in_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("notes.txt");
    std::fs::write(&path, "a shopping list, not a database of matches\n").unwrap();
    let out = run(&["history", "--history", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("notes.txt") && err.contains("not a database"),
        "{err}"
    );
    // The file is left as it was.
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "a shopping list, not a database of matches\n"
    );
}

#[test]
fn no_history_yet_lists_nothing_and_creates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("none/history.sqlite3");
    let h = history_json(&db);
    assert_eq!(h["matches"], serde_json::json!([]));
    assert!(!db.exists() && !dir.path().join("none").exists());
}
