//! What a rollback costs on the full table, on the desktop (`space-foosball bench
//! rollback`) and in the page (`spaceFoosball.benchRollback()`, printed by the browser
//! test) alike: at moments spread over a match of the computer against itself, the match
//! is saved, played on for eight 60 Hz frames (134 physics steps at 1 kHz), restored and
//! played the same steps again — the work a late input of eight frames ago asks for. The
//! replay must end where the first play did, bit for bit.

use serde::Serialize;
use space_foosball::input::paddles::RodInputs;
use space_foosball::play::{idle_inputs, Match, MatchConfig, MatchError};
use space_foosball::rules::RulesConfig;
use space_foosball::Table;

/// Frames rolled back: eight at 60 Hz.
pub const ROLLBACK_FRAMES: u32 = 8;
/// Steps played between the moments measured (and before the first, into play).
const BETWEEN_STEPS: u64 = 250;

/// Physics steps of `frames` 60 Hz frames at 1 kHz, rounded up.
pub fn steps_of_frames(frames: u32) -> u64 {
    (u64::from(frames) * 1000).div_ceil(60)
}

/// The computer against itself on `table` with `seed`, to 99 goals: a match that does
/// not end during a measurement.
pub fn endless_match(table: &Table, seed: u64) -> Result<Match, MatchError> {
    let mut config = MatchConfig::computer_vs_computer(table.clone(), seed);
    config.rules = RulesConfig {
        goals_to_win: 99,
        ..RulesConfig::default()
    };
    Match::new(config)
}

/// The figures of [`time_rollbacks`].
#[derive(Debug, Clone, Serialize)]
pub struct RollbackFigures {
    /// The table's name.
    pub table: String,
    /// Rollbacks timed.
    pub repeats: u32,
    /// Frames rolled back.
    pub frames: u32,
    /// Physics steps played again.
    pub steps: u64,
    /// Saving the match, µs.
    pub save_us_median: f64,
    /// Saving the match, worst, µs.
    pub save_us_worst: f64,
    /// Restoring the match, µs.
    pub restore_us_median: f64,
    /// Restoring the match, worst, µs.
    pub restore_us_worst: f64,
    /// The restore and the steps again, ms.
    pub rollback_ms_median: f64,
    /// The restore and the steps again, worst, ms.
    pub rollback_ms_worst: f64,
}

/// The replay after a restore ended elsewhere than the first play.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the replay after a restore ended elsewhere than the first play")]
pub struct ReplayDiffers;

fn median_and_worst(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    match (v.get(v.len() / 2), v.last()) {
        (Some(m), Some(w)) => (*m, *w),
        _ => (f64::NAN, f64::NAN),
    }
}

/// Times `repeats` rollbacks of [`ROLLBACK_FRAMES`] frames of `m` (played on `table`,
/// rods idle), on the clock `now_s` (s).
pub fn time_rollbacks(
    table: &Table,
    m: &mut Match,
    repeats: u32,
    now_s: &dyn Fn() -> f64,
) -> Result<RollbackFigures, ReplayDiffers> {
    let inputs: RodInputs = idle_inputs(table);
    let steps = steps_of_frames(ROLLBACK_FRAMES);
    let (mut save, mut restore, mut rollback) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..repeats {
        for _ in 0..BETWEEN_STEPS {
            m.step(&inputs);
        }
        let t0 = now_s();
        let saved = m.save();
        save.push((now_s() - t0) * 1e6);
        for _ in 0..steps {
            m.step(&inputs);
        }
        let first = m.state_hash();
        let t0 = now_s();
        m.restore(&saved);
        let restored = now_s();
        for _ in 0..steps {
            std::hint::black_box(m.step(&inputs));
        }
        let done = now_s();
        restore.push((restored - t0) * 1e6);
        rollback.push((done - t0) * 1e3);
        if m.state_hash() != first {
            return Err(ReplayDiffers);
        }
    }
    let (save_us_median, save_us_worst) = median_and_worst(save);
    let (restore_us_median, restore_us_worst) = median_and_worst(restore);
    let (rollback_ms_median, rollback_ms_worst) = median_and_worst(rollback);
    Ok(RollbackFigures {
        table: table.name.clone(),
        repeats,
        frames: ROLLBACK_FRAMES,
        steps,
        save_us_median,
        save_us_worst,
        restore_us_median,
        restore_us_worst,
        rollback_ms_median,
        rollback_ms_worst,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_frames_are_134_steps() {
        assert_eq!(steps_of_frames(8), 134);
        assert_eq!(steps_of_frames(6), 100);
    }

    #[test]
    fn a_rollback_replays_to_the_same_state() {
        let table = Table::standard();
        let mut m = endless_match(&table, 3).unwrap();
        let clock = std::time::Instant::now();
        let f = time_rollbacks(&table, &mut m, 2, &|| clock.elapsed().as_secs_f64()).unwrap();
        assert_eq!((f.repeats, f.steps), (2, 134));
        assert!(f.rollback_ms_median > 0.0 && f.rollback_ms_worst >= f.rollback_ms_median);
    }
}
