//! `foosball-fuzz`: replays the committed corpora and fuzzes every loader and decoder
//! for a bounded time under a heap cap. See the crate README.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use clap::{Parser, Subcommand};
use foosball_fuzz::{alloc, corpus_dir, runner, seeds, slot, supervisor, Target, TARGETS};

#[global_allocator]
static ALLOCATOR: alloc::CappedAllocator = alloc::CappedAllocator;

#[derive(Parser)]
#[command(about = "Fuzz targets for every loader and decoder of Space Foosball")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replays each target's corpus, then fuzzes it, each in its own process.
    Run {
        /// Seconds of fuzzing per target, after its corpus replay.
        #[arg(long, default_value_t = 15.0)]
        secs: f64,
        /// Cap on each target process's live heap, MiB.
        #[arg(long, default_value_t = 1024)]
        heap_mib: usize,
        /// Longest one input may run, seconds.
        #[arg(long, default_value_t = 10.0)]
        input_timeout: f64,
        /// Seed of the mutator (default: from the clock, printed).
        #[arg(long)]
        seed: Option<u64>,
        /// Where failing inputs are saved (default: `$CARGO_TARGET_DIR/fuzz` or
        /// `target/fuzz`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Replay `DIR/<target>/` instead of the committed corpus, e.g.
        /// `tests/fuzz/findings` (with `--secs 0`: replay only).
        #[arg(long, value_name = "DIR")]
        corpus: Option<PathBuf>,
        /// Targets to run (default: all).
        targets: Vec<String>,
    },
    /// Runs files through a target in this process (a saved failure, a finding) and
    /// prints each one's verdict, or the property it fails; exits 1 if any fails.
    Replay {
        /// Cap on the live heap, MiB (past it the process aborts).
        #[arg(long, default_value_t = 1024)]
        heap_mib: usize,
        /// The target.
        target: String,
        /// Input files.
        files: Vec<PathBuf>,
    },
    /// Lists the targets.
    List,
    /// Writes the generated seeds into `tests/fuzz/corpus/<target>/`.
    SeedCorpus,
    /// One target in this process (started by `run`).
    #[command(hide = true)]
    Child {
        target: String,
        #[arg(long)]
        secs: f64,
        #[arg(long)]
        heap_cap: usize,
        #[arg(long)]
        input_timeout: f64,
        #[arg(long)]
        seed: u64,
        #[arg(long)]
        slot: PathBuf,
        #[arg(long)]
        corpus: PathBuf,
    },
}

fn main() -> ExitCode {
    match run(Cli::parse().command) {
        Ok(code) => code,
        Err(message) => {
            eprintln!("foosball-fuzz: {message}");
            ExitCode::FAILURE
        }
    }
}

fn find(name: &str) -> Result<&'static Target, String> {
    foosball_fuzz::target(name).ok_or_else(|| {
        let names: Vec<_> = TARGETS.iter().map(|t| t.name).collect();
        format!("no target named {name:?} (targets: {})", names.join(", "))
    })
}

fn seconds(s: f64, what: &str) -> Result<Duration, String> {
    Duration::try_from_secs_f64(s).map_err(|_| format!("{what} must be a number of seconds ≥ 0"))
}

fn run(command: Command) -> Result<ExitCode, String> {
    match command {
        Command::Run {
            secs,
            heap_mib,
            input_timeout,
            seed,
            out,
            corpus,
            targets,
        } => {
            let selected = if targets.is_empty() {
                TARGETS.iter().collect()
            } else {
                targets
                    .iter()
                    .map(|n| find(n))
                    .collect::<Result<Vec<_>, _>>()?
            };
            let seed = seed.unwrap_or_else(|| {
                SystemTime::now()
                    .duration_since(UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos() as u64)
            });
            let out_dir = out.unwrap_or_else(|| {
                std::env::var_os("CARGO_TARGET_DIR")
                    .map_or_else(|| PathBuf::from("target"), PathBuf::from)
                    .join("fuzz")
            });
            let options = supervisor::Options {
                fuzz_for: seconds(secs, "--secs")?,
                heap_cap: heap_mib.saturating_mul(1 << 20),
                input_timeout: seconds(input_timeout, "--input-timeout")?,
                seed,
                out_dir,
                corpus_root: corpus,
            };
            println!(
                "fuzzing {} targets, {secs} s each, heap cap {heap_mib} MiB, seed {seed}",
                selected.len()
            );
            let exe = std::env::current_exe().map_err(|e| format!("cannot find myself: {e}"))?;
            let failures = supervisor::run_all(&exe, &selected, &options);
            if failures.is_empty() {
                println!("all {} targets passed", selected.len());
                Ok(ExitCode::SUCCESS)
            } else {
                let names: Vec<_> = failures.iter().map(|f| f.target).collect();
                eprintln!("{} targets failed: {}", failures.len(), names.join(", "));
                Ok(ExitCode::FAILURE)
            }
        }
        Command::Replay {
            heap_mib,
            target,
            files,
        } => {
            let target = find(&target)?;
            alloc::set_cap(heap_mib.saturating_mul(1 << 20));
            let mut failed = 0;
            for file in &files {
                let bytes = std::fs::read(file)
                    .map_err(|e| format!("cannot read {}: {e}", file.display()))?;
                // The panic message is printed by the panic hook; the verdict line
                // follows it.
                match std::panic::catch_unwind(|| (target.run)(&bytes)) {
                    Ok(verdict) => println!("{}: {verdict:?}", file.display()),
                    Err(_) => {
                        failed += 1;
                        println!("{}: FAILED", file.display());
                    }
                }
            }
            Ok(if failed == 0 {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Command::List => {
            for t in &TARGETS {
                println!("{:<18} {}", t.name, t.about);
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::SeedCorpus => {
            for t in &TARGETS {
                let dir = corpus_dir(t.name);
                std::fs::create_dir_all(&dir)
                    .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
                let seeds = seeds::seeds(t.name);
                for (name, bytes) in &seeds {
                    let path = dir.join(name);
                    std::fs::write(&path, bytes)
                        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                }
                println!("{:<18} {} seeds in {}", t.name, seeds.len(), dir.display());
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Child {
            target,
            secs,
            heap_cap,
            input_timeout,
            seed,
            slot: slot_path,
            corpus,
        } => {
            let target = find(&target)?;
            let mut slot = slot::InputSlot::create(&slot_path)
                .map_err(|e| format!("cannot create the slot {}: {e}", slot_path.display()))?;
            alloc::set_cap(heap_cap);
            let options = runner::RunOptions {
                corpus,
                fuzz_for: seconds(secs, "--secs")?,
                seed,
                input_timeout: seconds(input_timeout, "--input-timeout")?,
            };
            let started = std::time::Instant::now();
            let stats = runner::run(target, &options, &mut slot);
            println!(
                "{{\"target\":\"{}\",\"corpus\":{},\"corpus_accepted\":{},\"execs\":{},\"accepted\":{},\"pool\":{},\"secs\":{:.1},\"peak_heap_mib\":{:.1}}}",
                target.name,
                stats.corpus,
                stats.corpus_accepted,
                stats.execs,
                stats.accepted,
                stats.pool,
                started.elapsed().as_secs_f64(),
                alloc::peak_bytes() as f64 / f64::from(1 << 20),
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}
