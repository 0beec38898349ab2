//! The `sim` command line on user errors: one line on stderr (`error: …`), exit status
//! 1, no backtrace whatever `RUST_BACKTRACE` says; a closed stdout ends quietly; a
//! missing file is said not to exist.

use std::process::{Command, Output, Stdio};

fn sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .env("RUST_LIB_BACKTRACE", "1")
        .stdin(Stdio::null())
        .output()
        .expect("run sim")
}

/// Runs `sim` expecting a user error; returns its one stderr line.
fn user_error(args: &[&str]) -> String {
    let out = sim(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(out.stdout.is_empty(), "{args:?}: stdout {:?}", out.stdout);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: not one line: {stderr}");
    assert!(lines[0].starts_with("error: "), "{args:?}: {stderr}");
    for noise in ["backtrace", "panicked", "Caused by", "Usage:"] {
        assert!(!stderr.contains(noise), "{args:?}: {stderr}");
    }
    lines[0].to_owned()
}

#[test]
fn user_errors_are_one_line_and_status_1_even_with_rust_backtrace() {
    let dir = tempfile::tempdir().unwrap();
    let sock = dir.path().join("s.sock");
    let sock = sock.to_str().unwrap();
    let e = user_error(&["serve", "--socket", sock, "--resolution", "3"]);
    assert!(e.contains("--resolution must be 1, 2, 4 or 8"), "{e}");
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{"rods":[{"rod":0,"segments":[{"hold":{"duration_s":0}}]}]}"#,
    )
    .unwrap();
    let e = user_error(&["check-script", bad.to_str().unwrap()]);
    assert!(e.contains("duration_s"), "{e}");
    let e = user_error(&["serve", "--socket", sock, "--bogus"]);
    assert!(e.contains("--bogus") && e.contains("sim --help"), "{e}");
    let e = user_error(&["serve", "--socket", sock, "--resolution", "many"]);
    assert!(e.contains("many"), "{e}");
    let e = user_error(&[]);
    assert!(e.contains("serve, usbip, bench or check-script"), "{e}");
    let e = user_error(&["serve", "--interactive", "--script", bad.to_str().unwrap()]);
    assert!(e.contains("--interactive") && e.contains("--script"), "{e}");
}

#[test]
fn a_missing_file_is_said_not_to_exist() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let missing = missing.to_str().unwrap();
    let sock = dir.path().join("s.sock");
    let sock = sock.to_str().unwrap();
    let e = user_error(&["check-script", missing]);
    assert_eq!(
        e,
        format!("error: motion script {missing}: the file does not exist")
    );
    let e = user_error(&["serve", "--socket", sock, "--script", missing]);
    assert_eq!(
        e,
        format!("error: --script {missing}: the file does not exist")
    );
    let e = user_error(&["serve", "--socket", sock, "--recording", missing]);
    assert_eq!(
        e,
        format!("error: --recording {missing}: the file does not exist")
    );
}

#[test]
fn a_closed_stdout_ends_quietly() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/demo.json");
    // The reading end is closed before `sim` writes: its write fails with EPIPE.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(["check-script", script])
        .env("RUST_BACKTRACE", "1")
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("run sim");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.is_empty(), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}

#[test]
fn help_and_version_still_print() {
    let out = sim(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("serve"));
    let out = sim(&["serve", "--help"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("--interactive"));
    let out = sim(&["--version"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("sim "));
}
