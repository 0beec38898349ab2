//! `vphys`: the Virtual Physics command line — scenes, benchmarks, the accuracy report, Table 3
//! and peer comparisons. Every error ends the program with one line on stderr and a documented
//! exit code (see `exit.rs`).
//!
//! "The paper" and its Table 3 refer to Bang, Heo, Kim and Kim, "Space Foosball: Coupling
//! Tangible Interfaces with a Real-time Game Physics Engine"; what the project takes from
//! it, section by section, is in docs/paper.md in the repository.

/// `writeln!` to stdout, returning the I/O error (a closed pipe) to the caller instead of
/// panicking as `println!` does.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}

/// `write!` to stdout; see `outln!`.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($arg)*)?
    }};
}

mod accuracy;
mod bodies;
mod cpu_clock;
mod effects;
mod exit;
mod figure;
mod front;
mod hard;
mod multibody_peer;
mod parry_peer;
mod peers;
mod rapier_peer;
#[cfg(feature = "rapier-peer")]
mod rapier_scene;
mod run;
mod suite;
mod table3;
mod tumbling_peers;

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "vphys",
    about = "Virtual Physics: scenes, benchmarks, measurements and peer comparisons"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// The paper's Table 3 measured on this crate: operation counts (geometric and 6×6 matrix
    /// form, next to the paper's) and ns per op.
    Table3 {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Counts only, no timing.
        #[arg(long)]
        no_time: bool,
    },
    /// Steps a scene (file or built-in name) and prints per-step metrics as JSON lines, or
    /// with --bodies each body's pose and velocity.
    Run {
        /// Scene file (JSON) or built-in name (towers-1120, pyramid-1240, towers-80, pyramid-55, ball-roll, ball-wall).
        scene: String,
        /// Steps (default: the scene's `steps`, else 600; at most 10⁷).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=run::MAX_STEPS))]
        steps: Option<u64>,
        /// Force sleeping on or off.
        #[arg(long)]
        sleeping: Option<bool>,
        /// Print every N-th step (and the last).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=run::MAX_STEPS))]
        every: u64,
        /// Instead of one line per printed step, one line per body and printed step: position
        /// (m), rotation as a unit quaternion [w, x, y, z], linear (m/s) and angular (rad/s)
        /// velocity, all in the world frame, and the 3D distance from the start (m).
        #[arg(long)]
        bodies: bool,
        /// Only the named bodies (repeatable; implies --bodies).
        #[arg(long = "body", value_name = "NAME")]
        body: Vec<String>,
    },
    /// Times a scene: ms per step (median, mean, worst) as JSON.
    Bench {
        /// Scene file or built-in name.
        scene: String,
        /// Steps (default: the scene's `steps`, else 600; at most 10⁷).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=run::MAX_STEPS))]
        steps: Option<u64>,
        /// Force sleeping on or off.
        #[arg(long)]
        sleeping: Option<bool>,
        /// Override the scene's substeps per step (1 … 64).
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=64))]
        substeps: Option<u16>,
        /// Override the scene's contact stiffness (Hz, > 0).
        #[arg(long)]
        contact_hertz: Option<f64>,
        /// Rigid contacts with a position bias instead of soft ones.
        #[arg(long)]
        rigid: bool,
        /// Solve the contacts one by one instead of four at a time.
        #[arg(long)]
        scalar_contacts: bool,
        /// Override the cap on contact stiffness, as a fraction of the substep rate (> 0).
        #[arg(long)]
        hertz_cap: Option<f64>,
        /// Relax (solve without position bias) only after the last substep, not after each.
        #[arg(long)]
        relax_last_only: bool,
        /// Take the scene's substeps in every step, also once the world rests (by default a
        /// resting world whose contacts allow takes a half, a third, a quarter or a sixth of them).
        #[arg(long)]
        fixed_substeps: bool,
        /// Warm start the contacts from their impulses in every substep, instead of adding
        /// back each body's change of velocity from the substep before.
        #[arg(long)]
        contact_warm_start: bool,
        /// Let the contacts settle at the overlap their loads ask, instead of holding back
        /// the sink of resting contacts.
        #[arg(long)]
        no_sink_hold: bool,
        /// Build the broad phase's grid every step, instead of keeping its pairs while the
        /// bodies' boxes stay in place.
        #[arg(long)]
        rebuild_broad_phase: bool,
        /// Keep every contact constraint whole at rest, instead of preparing those solved
        /// four at a time straight into their lanes.
        #[arg(long)]
        keep_contact_constraints: bool,
    },
    /// Cost of each effect added to a base scene, and of the same effect undeclared.
    Effects {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Steps per measurement (1 … 10⁵).
        #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..=100_000))]
        steps: u64,
    },
    /// What accuracy costs in time: reference problems × integrators × a sweep of steps;
    /// writes the table (Markdown, JSON) and the chart (PNG, SVG).
    Accuracy {
        /// Reduced sweep (5 steps, a small tower scene); writes to a temporary folder by default.
        #[arg(long)]
        quick: bool,
        /// Print `{"rows":[…],"step_cost":[…]}` on stdout instead of the summary.
        #[arg(long)]
        json: bool,
        /// Output folder (default: the crate's `accuracy/`, or a temporary folder with --quick).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Only time the free-body step of each integrator (no sweep, nothing written).
        #[arg(long)]
        step_cost: bool,
        /// Compare the fresh run's errors, drifts and flips (never timings) with the committed
        /// report in DIR (`accuracy.json`, `accuracy-quick.json`); fails naming each row that
        /// differs. Writes nothing unless --out is given.
        #[arg(long, value_name = "DIR")]
        check: Option<std::path::PathBuf>,
        /// Also the report's peer panels, into the same folder: drift against ms per step on
        /// towers-1120 and pyramid-1240 (`front.{svg,png}`: ours over its substeps, rapier3d
        /// over its iterations when built with `--features rapier-peer`) and the tumbling box
        /// beside MuJoCo (when `python3` has `mujoco`) and rapier3d (`tumbling-peers.{svg,png}`).
        /// With --json, one JSON object per line: the report, the front, the tumbling points.
        #[arg(long, conflicts_with_all = ["quick", "step_cost"])]
        peers: bool,
    },
    /// The hard cases at the defaults (heavy on light, a fast ball in a closed box, an arm on
    /// stairs, a Newton's cradle, dominoes): a table of each figure, its bound, whether it
    /// holds and ms per step; exits 1 when a case fails.
    Hard {
        /// Also the variants of the same kinds (other sizes, masses and speeds).
        #[arg(long)]
        variants: bool,
        /// Only this case (repeatable; the table's cases and the variants).
        #[arg(long = "case", value_name = "NAME")]
        case: Vec<String>,
        /// One JSON object per case instead of the table.
        #[arg(long)]
        json: bool,
        /// Steps N times finer at the same substep: each case's step divided by N and its
        /// substeps too (N must divide them), N times the steps. How a figure depends on
        /// the step rather than the substep; the bounds stay the defaults'.
        #[arg(long, value_name = "N", default_value_t = 1)]
        finer: u32,
    },
    /// Comparisons with other engines (Pinocchio).
    Peers {
        #[command(subcommand)]
        cmd: peers::PeersCmd,
    },
}

fn main() -> ExitCode {
    cpu_clock::install();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage(&e),
    };
    exit::finish(dispatch(cli))
}

/// `--help` and `--version` print and succeed; any other argument error is one line, status 1.
fn usage(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            // A closed stdout while printing help is not an error worth a message.
            let _ = e.print();
            ExitCode::SUCCESS
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            eprintln!("error: a command is missing; see `vphys --help`");
            ExitCode::from(1)
        }
        _ => {
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("invalid arguments");
            let first = first.strip_prefix("error: ").unwrap_or(first);
            match text.lines().find_map(|l| l.strip_prefix("Usage: ")) {
                Some(u) => eprintln!("error: {first} (usage: {u})"),
                None => eprintln!("error: {first}"),
            }
            ExitCode::from(1)
        }
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.cmd {
        Cmd::Table3 { json, no_time } => table3::run(json, !no_time),
        Cmd::Peers { cmd } => peers::run(cmd),
        Cmd::Hard {
            variants,
            case,
            json,
            finer,
        } => hard::run(variants, &case, json, finer),
        Cmd::Effects { json, steps } => effects::run(json, steps),
        Cmd::Accuracy {
            quick,
            json,
            out,
            step_cost,
            check,
            peers,
        } => {
            if step_cost {
                accuracy::step_cost(json)
            } else {
                accuracy::run(quick, json, out, check, peers)
            }
        }
        Cmd::Run {
            scene,
            steps,
            sleeping,
            every,
            bodies,
            body,
        } => {
            let output = if bodies || !body.is_empty() {
                run::Output::Bodies(body)
            } else {
                run::Output::Steps
            };
            run::run(&scene, steps, sleeping, every, &output)
        }
        Cmd::Bench {
            scene,
            steps,
            sleeping,
            substeps,
            contact_hertz,
            rigid,
            scalar_contacts,
            hertz_cap,
            relax_last_only,
            fixed_substeps,
            contact_warm_start,
            no_sink_hold,
            rebuild_broad_phase,
            keep_contact_constraints,
        } => run::bench(
            &scene,
            steps,
            sleeping,
            &run::SolverOverrides {
                substeps: substeps.map(usize::from),
                contact_hertz,
                rigid,
                scalar_contacts,
                hertz_cap,
                relax_last_only,
                fixed_substeps,
                contact_warm_start,
                no_sink_hold,
                rebuild_broad_phase,
                keep_contact_constraints,
            },
        ),
    }
}
