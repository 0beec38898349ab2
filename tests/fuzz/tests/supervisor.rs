//! The runner as CI runs it: child processes, the heap cap, the saved input.

use std::path::Path;
use std::process::{Command, Output};

use foosball_fuzz::seeds::table_with_rods;

fn fuzz(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foosball-fuzz"))
        .args(args)
        .arg("--out")
        .arg(out)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the fuzz binary runs")
}

#[test]
fn a_short_run_replays_the_corpus_and_passes() {
    let out = tempfile::tempdir().expect("a temporary folder");
    let run = fuzz(
        &["run", "--secs", "0.5", "--seed", "1", "in-report", "ps2"],
        out.path(),
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.contains("all 2 targets passed"), "{stdout}");
    for target in ["in-report", "ps2"] {
        let line = stdout
            .lines()
            .find(|l| l.contains(&format!("\"target\":\"{target}\"")))
            .unwrap_or_else(|| panic!("no stats line for {target}: {stdout}"));
        let stats: serde_json::Value = serde_json::from_str(line).expect("stats are JSON");
        assert!(stats["corpus"].as_u64() >= Some(3), "{line}");
        assert!(stats["execs"].as_u64() > Some(0), "{line}");
    }
}

#[test]
fn an_input_past_the_heap_cap_fails_the_run_and_is_saved() {
    let out = tempfile::tempdir().expect("a temporary folder");
    // A table of 1000 rods: 100 kB of TOML (within the input slot's 128 KiB), whose
    // parse needs more than a 1 MiB heap.
    let big = table_with_rods(1000);
    assert!(
        big.len() <= foosball_fuzz::MAX_INPUT_LEN,
        "{} bytes",
        big.len()
    );
    let corpus = out.path().join("corpus");
    std::fs::create_dir_all(corpus.join("table")).expect("corpus folder");
    std::fs::write(corpus.join("table").join("big.toml"), &big).expect("corpus file");
    let corpus_arg = corpus.to_str().expect("a UTF-8 path");
    let run = fuzz(
        &[
            "run",
            "--secs",
            "0",
            "--heap-mib",
            "1",
            "--corpus",
            corpus_arg,
            "table",
        ],
        &out.path().join("results"),
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("FAILED table"), "{stderr}");
    assert!(
        stderr.contains("the heap cap (1 MiB) refused an allocation"),
        "{stderr}"
    );
    let saved = std::fs::read_dir(out.path().join("results"))
        .expect("the results folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "input"))
        .expect("the failing input is saved");
    let saved_bytes = std::fs::read(&saved).expect("saved input");
    assert!(
        saved_bytes == big,
        "saved {} bytes, the input has {}",
        saved_bytes.len(),
        big.len()
    );
    assert!(stderr.contains(&saved.display().to_string()), "{stderr}");
}

#[test]
fn an_unknown_target_is_a_one_line_error() {
    let out = tempfile::tempdir().expect("a temporary folder");
    let run = fuzz(&["run", "--secs", "0", "no-such-target"], out.path());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1));
    assert!(
        stderr.contains("no target named \"no-such-target\""),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}
