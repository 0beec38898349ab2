//! `space-foosball bench rollback`: what rollback netcode costs on the full table
//! ([`space_foosball_front::online::rollback_timing`], the page's measure too), as one
//! JSON line:
//!
//! ```text
//! {"table", "repeats", "frames", "steps", "save_us_median", "save_us_worst",
//!  "restore_us_median", "restore_us_worst", "rollback_ms_median", "rollback_ms_worst"}
//! ```

use anyhow::{bail, Result};
use space_foosball_front::online::rollback_timing::{endless_match, time_rollbacks};
use std::time::Instant;

/// Arguments of `bench rollback`.
#[derive(clap::Args, Debug)]
pub struct RollbackArgs {
    /// Rollbacks timed (1–1000).
    #[arg(long, default_value_t = 50)]
    pub repeats: u32,
    /// Table: `standard`, `paper` or a TOML file.
    #[arg(long, default_value = "standard")]
    pub table: String,
    /// Seed of the match.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `bench rollback`.
pub fn run(args: &RollbackArgs) -> Result<()> {
    if !(1..=1000).contains(&args.repeats) {
        bail!("--repeats must be 1–1000, got {}", args.repeats);
    }
    let table = crate::headless::load_table(&args.table)?;
    let mut m = endless_match(&table, args.seed)?;
    let clock = Instant::now();
    let figures = time_rollbacks(&table, &mut m, args.repeats, &|| {
        clock.elapsed().as_secs_f64()
    })?;
    println!("{}", serde_json::to_string(&figures)?);
    Ok(())
}
