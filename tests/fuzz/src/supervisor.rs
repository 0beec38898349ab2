//! The supervisor: one child process per target, and what to do when one dies.
//!
//! Each target runs in a child (`foosball-fuzz child …`, the same executable) with the
//! allocation cap set, its own input slot file and a wall-clock limit. A child that
//! exits non-zero, is killed by a signal, or runs past the limit has failed: the input
//! in its slot is saved to `<out>/<target>-<hash>.input` (written to a temporary file,
//! then renamed) and named in the report.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use std::time::{Duration, Instant};

use crate::{slot, Target};

/// Settings of a supervised run.
#[derive(Debug, Clone)]
pub struct Options {
    /// Mutation time per target (after its corpus replay).
    pub fuzz_for: Duration,
    /// Cap on each child's live heap, bytes.
    pub heap_cap: usize,
    /// Longest one input may run.
    pub input_timeout: Duration,
    /// Seed; each target mixes in its own name.
    pub seed: u64,
    /// Where slots and failing inputs go.
    pub out_dir: PathBuf,
    /// Replay `<root>/<target>/` instead of the committed corpus (e.g. the findings).
    pub corpus_root: Option<PathBuf>,
}

/// A target whose child failed.
#[derive(Debug, Clone)]
pub struct Failure {
    /// The target.
    pub target: &'static str,
    /// What happened, one line.
    pub reason: String,
    /// Where the input under test was saved, if it could be.
    pub saved: Option<PathBuf>,
}

/// The seed of `target` in a run seeded with `seed`.
pub fn target_seed(seed: u64, target: &str) -> u64 {
    seed ^ fnv1a(target.as_bytes())
}

/// FNV-1a, 64 bits: names inputs and mixes target names into seeds.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Runs every target in `targets` in turn, each in a child of `exe`. Returns the
/// failures (empty: all passed).
pub fn run_all(exe: &Path, targets: &[&'static Target], options: &Options) -> Vec<Failure> {
    let mut failures = Vec::new();
    if let Err(e) = std::fs::create_dir_all(&options.out_dir) {
        eprintln!("cannot create {}: {e}", options.out_dir.display());
    }
    for target in targets {
        if let Some(failure) = run_child(exe, target, options) {
            eprintln!(
                "FAILED {}: {}; input {}",
                failure.target,
                failure.reason,
                failure
                    .saved
                    .as_ref()
                    .map_or("could not be saved".into(), |p| format!(
                        "saved to {}",
                        p.display()
                    ))
            );
            failures.push(failure);
        }
    }
    failures
}

fn run_child(exe: &Path, target: &'static Target, options: &Options) -> Option<Failure> {
    let slot_path = options.out_dir.join(format!("{}.slot", target.name));
    let seed = target_seed(options.seed, target.name);
    let corpus = options.corpus_root.as_ref().map_or_else(
        || crate::corpus_dir(target.name),
        |root| root.join(target.name),
    );
    let spawned = Command::new(exe)
        .arg("child")
        .arg(target.name)
        .arg("--secs")
        .arg(options.fuzz_for.as_secs_f64().to_string())
        .arg("--heap-cap")
        .arg(options.heap_cap.to_string())
        .arg("--input-timeout")
        .arg(options.input_timeout.as_secs_f64().to_string())
        .arg("--seed")
        .arg(seed.to_string())
        .arg("--slot")
        .arg(&slot_path)
        .arg("--corpus")
        .arg(&corpus)
        .spawn();
    let mut child = match spawned {
        Ok(child) => child,
        Err(e) => {
            return Some(Failure {
                target: target.name,
                reason: format!("cannot start {}: {e}", exe.display()),
                saved: None,
            })
        }
    };
    // The corpus replay is bounded by the per-input limit per input; allow it a minute
    // beyond the fuzzing time before calling the child hung.
    let limit = options.fuzz_for + options.input_timeout + Duration::from_secs(60);
    let started = Instant::now();
    let status: Result<ExitStatus, String> = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(status),
            Ok(None) if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!("still running after {} s", limit.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => break Err(format!("cannot wait for the child: {e}")),
        }
    };
    let reason = match status {
        Ok(status) if status.success() => return None,
        Ok(status) => describe(status),
        Err(reason) => reason,
    };
    let (saved, reason) = match slot::read(&slot_path) {
        Ok(contents) => {
            let reason = match contents.refused_allocation {
                Some(bytes) => format!(
                    "{reason}; the heap cap ({} MiB) refused an allocation of {bytes} bytes",
                    options.heap_cap >> 20
                ),
                None => reason,
            };
            (
                save_input(&options.out_dir, target.name, &contents.input),
                reason,
            )
        }
        Err(e) => (
            None,
            format!("{reason}; the input slot cannot be read: {e}"),
        ),
    };
    Some(Failure {
        target: target.name,
        reason,
        saved,
    })
}

fn describe(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(101), _) => "a property failed or the code panicked (exit 101)".into(),
        (Some(code), _) => format!("exited with status {code}"),
        (None, Some(6)) => "aborted (SIGABRT: allocation failure or abort)".into(),
        (None, Some(11)) => "crashed (SIGSEGV: stack overflow or memory error)".into(),
        (None, Some(signal)) => format!("killed by signal {signal}"),
        (None, None) => "ended without a status".into(),
    }
}

/// Saves `input` as `<dir>/<target>-<hash>.input`, through a temporary file.
fn save_input(dir: &Path, target: &str, input: &[u8]) -> Option<PathBuf> {
    let path = dir.join(format!("{target}-{:016x}.input", fnv1a(input)));
    let tmp = path.with_extension("input.tmp");
    std::fs::write(&tmp, input).ok()?;
    std::fs::rename(&tmp, &path).ok()?;
    Some(path)
}
