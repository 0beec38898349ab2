//! `space-foosball bench rollback`: what rollback netcode costs on the full table.
//!
//! The computer plays itself on the chosen table; at `--repeats` moments spread over the
//! match, the match is saved (`Match::save`), played on for eight 60 Hz frames (134
//! physics steps at 1 kHz), restored (`Match::restore`) and played the same 134 steps
//! again — the work a late input of eight frames ago asks for. Each repeat checks that the
//! replay ends where the first play did (bit for bit), and times the save, the restore
//! and the whole rollback (restore and the steps again). One JSON line:
//!
//! ```text
//! {"table", "repeats", "frames", "steps", "save_us_median", "save_us_worst",
//!  "restore_us_median", "restore_us_worst", "rollback_ms_median", "rollback_ms_worst"}
//! ```

use anyhow::{bail, Result};
use space_foosball::play::idle_inputs;
use std::time::Instant;

/// Frames rolled back: eight at 60 Hz.
pub const ROLLBACK_FRAMES: u32 = 8;

/// Physics steps of `frames` 60 Hz frames at 1 kHz, rounded up.
pub fn steps_of_frames(frames: u32) -> u64 {
    (u64::from(frames) * 1000).div_ceil(60)
}

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

fn median_and_worst(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[v.len() / 2], v[v.len() - 1])
}

/// Runs `bench rollback`.
pub fn run(args: &RollbackArgs) -> Result<()> {
    if !(1..=1000).contains(&args.repeats) {
        bail!("--repeats must be 1–1000, got {}", args.repeats);
    }
    let (table, mut m) = crate::headless::endless_match(&args.table, args.seed)?;
    let inputs = idle_inputs(&table);
    let steps = steps_of_frames(ROLLBACK_FRAMES);
    // Into play first, and between repeats, so the moments spread over the match.
    const BETWEEN_STEPS: u64 = 250;
    let (mut save, mut restore, mut rollback) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..args.repeats {
        for _ in 0..BETWEEN_STEPS {
            m.step(&inputs);
        }
        let t0 = Instant::now();
        let saved = m.save();
        save.push(t0.elapsed().as_secs_f64() * 1e6);
        for _ in 0..steps {
            m.step(&inputs);
        }
        let first = format!("{:?}", m.snapshot());
        let t0 = Instant::now();
        m.restore(&saved);
        let restored = t0.elapsed();
        for _ in 0..steps {
            std::hint::black_box(m.step(&inputs));
        }
        let total = t0.elapsed();
        restore.push(restored.as_secs_f64() * 1e6);
        rollback.push(total.as_secs_f64() * 1e3);
        if format!("{:?}", m.snapshot()) != first {
            bail!("the replay after a restore ended elsewhere than the first play");
        }
    }
    let (save_med, save_worst) = median_and_worst(save);
    let (restore_med, restore_worst) = median_and_worst(restore);
    let (roll_med, roll_worst) = median_and_worst(rollback);
    println!(
        "{}",
        serde_json::json!({
            "table": table.name,
            "repeats": args.repeats,
            "frames": ROLLBACK_FRAMES,
            "steps": steps,
            "save_us_median": save_med,
            "save_us_worst": save_worst,
            "restore_us_median": restore_med,
            "restore_us_worst": restore_worst,
            "rollback_ms_median": roll_med,
            "rollback_ms_worst": roll_worst,
        })
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_frames_are_134_steps() {
        assert_eq!(steps_of_frames(8), 134);
        assert_eq!(steps_of_frames(6), 100);
    }
}
