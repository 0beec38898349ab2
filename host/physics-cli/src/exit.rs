//! How `vphys` ends: a one-line message for every error, no backtrace, and exit codes that
//! scripts can rely on.
//!
//! * 0 — done, or stdout was closed by its reader (`vphys run … | head`): a broken pipe ends
//!   the run quietly.
//! * 1 — a user error (a bad argument, a missing or invalid scene file, a step that failed).
//! * 2 — a comparison peer (Pinocchio, Rapier, parry) is not installed or not built in, so
//!   `scripts/figures` can skip it.

use std::fmt;
use std::process::ExitCode;

/// A comparison peer that this machine or this build lacks; `vphys` exits with status 2.
#[derive(Debug)]
pub struct PeerMissing(pub String);

impl fmt::Display for PeerMissing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PeerMissing {}

/// Whether the error (or any error in its chain) is a write to a closed pipe.
pub fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The error and its causes on one line: `outer: cause: root`, with the lines of a
/// multi-line message (a scene with several problems) joined by `; `.
pub fn one_line(err: &anyhow::Error) -> String {
    let mut parts: Vec<String> = Vec::new();
    for cause in err.chain() {
        let text = cause.to_string();
        let mut joined = String::new();
        for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
            if !joined.is_empty() {
                joined.push_str(if joined.ends_with(':') { " " } else { "; " });
            }
            joined.push_str(line);
        }
        // thiserror/anyhow messages often repeat their source; keep each text once.
        if !joined.is_empty() && !parts.iter().any(|p| p.contains(&joined)) {
            parts.push(joined);
        }
    }
    parts.join(": ")
}

/// Prints the outcome and returns the exit code (see the module docs).
pub fn finish(result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            if e.downcast_ref::<PeerMissing>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn a_multi_line_message_becomes_one_line() {
        let e = anyhow::anyhow!("2 problem(s) in the scene:\n  bodies[0].mass: bad\n  dt: bad");
        assert_eq!(
            one_line(&e),
            "2 problem(s) in the scene: bodies[0].mass: bad; dt: bad"
        );
    }

    #[test]
    fn causes_are_joined_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        let e = Err::<(), _>(io).context("reading x.json").unwrap_err();
        assert_eq!(one_line(&e), "reading x.json: gone");
    }

    #[test]
    fn a_broken_pipe_is_found_under_context() {
        let io = std::io::Error::from(std::io::ErrorKind::BrokenPipe);
        let e = Err::<(), _>(io).context("printing").unwrap_err();
        assert!(is_broken_pipe(&e));
        assert!(!is_broken_pipe(&anyhow::anyhow!("other")));
    }
}
