//! One target in one process: replay the committed corpus, then mutate until the
//! deadline.
//!
//! Every input is copied into the [`InputSlot`] before it runs, and a watchdog thread
//! aborts the process when one input runs longer than the per-input limit, so a hang
//! is reported like a crash. The pool starts as the corpus; mutants the target accepts
//! join it (up to [`POOL_CAP`] inputs, then they replace random earlier mutants; the
//! corpus stays), so the loop keeps working from inputs that get past the parsers.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use crate::mutate::{mutate, Rng};
use crate::slot::InputSlot;
use crate::{Target, Verdict, MAX_INPUT_LEN};

/// Most inputs kept in the pool.
pub const POOL_CAP: usize = 512;

/// How long to fuzz one target and how.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The folder of inputs to replay first (and to start the pool from).
    pub corpus: PathBuf,
    /// Mutation time after the corpus replay.
    pub fuzz_for: Duration,
    /// Seed of the mutator.
    pub seed: u64,
    /// Longest one input may run before the process aborts.
    pub input_timeout: Duration,
}

/// What a run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunStats {
    /// Corpus inputs replayed.
    pub corpus: usize,
    /// Corpus inputs accepted.
    pub corpus_accepted: usize,
    /// Mutants run.
    pub execs: u64,
    /// Mutants accepted.
    pub accepted: u64,
    /// Pool size at the end.
    pub pool: usize,
}

/// The inputs in `dir`, sorted by file name (`README*` and dot files skipped).
pub fn load_corpus(dir: &Path) -> io::Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with('.') || name.starts_with("README") || !path.is_file() {
            continue;
        }
        let bytes = std::fs::read(&path)?;
        files.push((path, bytes));
    }
    files.sort();
    Ok(files)
}

/// Milliseconds since the watchdog's epoch at which the current input started; 0 when
/// none runs.
static INPUT_STARTED_MS: AtomicU64 = AtomicU64::new(0);

fn epoch() -> Instant {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    *EPOCH.get_or_init(Instant::now)
}

fn now_ms() -> u64 {
    epoch().elapsed().as_millis() as u64 + 1
}

/// Starts the thread that aborts the process when an input runs past `limit`.
fn start_watchdog(limit: Duration, target: &'static str) {
    let _ = epoch();
    std::thread::spawn(move || loop {
        std::thread::sleep(Duration::from_millis(100));
        let started = INPUT_STARTED_MS.load(Ordering::Relaxed);
        if started != 0 && now_ms().saturating_sub(started) > limit.as_millis() as u64 {
            eprintln!(
                "{target}: one input ran longer than {} s: aborting",
                limit.as_secs_f64()
            );
            std::process::abort();
        }
    });
}

/// Runs `input` on `target` with the slot and watchdog in place.
fn run_one(target: &Target, slot: &mut InputSlot, input: &[u8]) -> Verdict {
    slot.set(input);
    INPUT_STARTED_MS.store(now_ms(), Ordering::Relaxed);
    let verdict = (target.run)(input);
    INPUT_STARTED_MS.store(0, Ordering::Relaxed);
    verdict
}

/// Replays the inputs in `options.corpus`, then mutates for `options.fuzz_for`. A
/// failing property panics (the process ends; the slot holds the input).
pub fn run(target: &'static Target, options: &RunOptions, slot: &mut InputSlot) -> RunStats {
    start_watchdog(options.input_timeout, target.name);
    let corpus = load_corpus(&options.corpus).unwrap_or_else(|e| {
        panic!(
            "{}: cannot read the corpus {}: {e}",
            target.name,
            options.corpus.display()
        )
    });
    let mut pool: Vec<Vec<u8>> = Vec::with_capacity(POOL_CAP);
    let mut corpus_accepted = 0;
    for (_, bytes) in &corpus {
        if run_one(target, slot, bytes) == Verdict::Accepted {
            corpus_accepted += 1;
        }
        pool.push(bytes.clone());
    }
    if pool.is_empty() {
        pool.push(Vec::new());
    }
    let mut rng = Rng::new(options.seed);
    let deadline = Instant::now() + options.fuzz_for;
    let (mut execs, mut accepted) = (0u64, 0u64);
    while Instant::now() < deadline {
        let base = &pool[rng.below(pool.len())];
        let other = &pool[rng.below(pool.len())];
        let max_len = target.max_len.min(MAX_INPUT_LEN);
        let input = mutate(target.format, base, other, &mut rng, max_len);
        execs += 1;
        if run_one(target, slot, &input) == Verdict::Accepted {
            accepted += 1;
            if pool.len() < POOL_CAP {
                pool.push(input);
            } else if rng.one_in(4) {
                // The corpus stays: only mutants are replaced.
                let kept = corpus.len().min(POOL_CAP - 1);
                let i = kept + rng.below(pool.len() - kept);
                pool[i] = input;
            }
        }
    }
    RunStats {
        corpus: corpus.len(),
        corpus_accepted,
        execs,
        accepted,
        pool: pool.len(),
    }
}
