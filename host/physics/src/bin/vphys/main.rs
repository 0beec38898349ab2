//! `vphys`: the Virtual Physics command line — Table 3 and peer comparisons.

mod peers;
mod table3;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "vphys",
    about = "Virtual Physics: measurements and peer comparisons"
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
    }
}
