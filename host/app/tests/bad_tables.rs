//! Every table that once broke the physics (`host/game/tests/bad_tables/`) is refused by the
//! program: exit status 1, one line on stderr, no panic and no backtrace, whatever
//! `RUST_BACKTRACE` says.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn every_bad_table_file_ends_the_program_with_one_line_and_status_1() {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../game/tests/bad_tables"
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the bad tables folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 8, "the reproducers are there: {files:?}");
    for file in files {
        let out = Command::new(env!("CARGO_BIN_EXE_space-foosball"))
            .args(["play", "--headless", "--table"])
            .arg(&file)
            .env("RUST_BACKTRACE", "1")
            .output()
            .expect("the program runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{}: {err}", file.display());
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{}: one line, got {err}", file.display());
        assert!(
            lines[0].contains("error: table file"),
            "{}: {err}",
            file.display()
        );
        assert!(!err.contains("panicked") && !err.contains("stack backtrace"));
        assert!(out.stdout.is_empty(), "{}: nothing played", file.display());
    }
}
