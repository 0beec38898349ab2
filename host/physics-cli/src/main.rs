//! `vphys`: the Virtual Physics command line — Table 3 and peer comparisons.
//!
//! "The paper" and its Table 3 refer to Bang, Heo, Kim and Kim, "Space Foosball: Coupling
//! Tangible Interfaces with a Real-time Game Physics Engine"; what the project takes from
//! it, section by section, is in docs/paper.md in the repository.

mod accuracy;
mod effects;
mod parry_peer;
mod peers;
mod rapier_peer;
mod run;
mod table3;

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
    /// Steps a scene (file or built-in name) and prints per-step metrics as JSON lines.
    Run {
        /// Scene file (JSON) or built-in name (towers-1120, pyramid-1240, towers-80, pyramid-55, ball-roll, ball-wall).
        scene: String,
        /// Steps (default: the scene's `steps`, else 600).
        #[arg(long)]
        steps: Option<u64>,
        /// Force sleeping on or off.
        #[arg(long)]
        sleeping: Option<bool>,
        /// Print every N-th step.
        #[arg(long, default_value_t = 1)]
        every: u64,
    },
    /// Times a scene: ms per step (median, mean, worst) as JSON.
    Bench {
        /// Scene file or built-in name.
        scene: String,
        /// Steps (default: the scene's `steps`, else 600).
        #[arg(long)]
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
    },
    /// Cost of each effect added to a base scene, and of the same effect undeclared.
    Effects {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Steps per measurement.
        #[arg(long, default_value_t = 200)]
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
    },
    /// Comparisons with other engines (Pinocchio).
    Peers {
        #[command(subcommand)]
        cmd: peers::PeersCmd,
    },
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Table3 { json, no_time } => table3::run(json, !no_time),
        Cmd::Peers { cmd } => peers::run(cmd),
        Cmd::Effects { json, steps } => effects::run(json, steps),
        Cmd::Accuracy {
            quick,
            json,
            out,
            step_cost,
        } => {
            if step_cost {
                accuracy::step_cost(json)
            } else {
                accuracy::run(quick, json, out)
            }
        }
        Cmd::Run {
            scene,
            steps,
            sleeping,
            every,
        } => run::run(&scene, steps, sleeping, every),
        Cmd::Bench {
            scene,
            steps,
            sleeping,
            substeps,
            contact_hertz,
            rigid,
            scalar_contacts,
            hertz_cap,
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
            },
        ),
    }
}
