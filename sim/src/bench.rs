//! How fast the emulation runs: emulated seconds of all eight sensors at wire level
//! per wall-clock second, on one core.

use crate::board::{BoardConfig, EmulatedBoard};
use crate::error::SimError;
use crate::motion::script::{MotionScript, RodTrack, ScriptSpec, Segment};
use foosball_protocol::PADDLES;
use serde::Serialize;
use std::time::Instant;

/// Result of one benchmark run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BenchResult {
    /// Emulated time measured, seconds (after a warm-up second of initialisation).
    pub emulated_s: f64,
    /// Wall-clock time it took, seconds.
    pub wall_s: f64,
    /// The figure of merit: `emulated_s / wall_s`.
    pub emulated_s_per_wall_s: f64,
    /// PS/2 frames the emulated PIOs received during the measurement (all ports).
    pub frames: u64,
    /// Stream packets the mice sent during the measurement (all ports).
    pub packets: u64,
}

/// All rods moving back and forth and turning for `seconds` (+1 s), so every mouse
/// streams packets at its full sample rate.
pub fn busy_script(seconds: f64) -> Result<MotionScript, SimError> {
    let half_periods = ((seconds + 1.0) / 0.25).ceil() as usize + 1;
    let rods = (0..PADDLES)
        .map(|rod| {
            let sign = if rod % 2 == 0 { 1.0 } else { -1.0 };
            RodTrack {
                rod,
                start: Default::default(),
                segments: (0..half_periods)
                    .map(|i| {
                        let dir = if i % 2 == 0 { sign } else { -sign };
                        Segment::Velocity {
                            duration_s: 0.25,
                            axial_m_per_s: 0.2 * dir,
                            angle_rad_per_s: 20.0 * dir,
                        }
                    })
                    .collect(),
            }
        })
        .collect();
    Ok(MotionScript::from_spec(ScriptSpec {
        rods,
        faults: Vec::new(),
    })?)
}

/// Runs the default board with [`busy_script`] for `seconds` of emulated time after a
/// 1 s warm-up, and measures the wall time on the calling thread.
pub fn run(seconds: f64) -> Result<BenchResult, SimError> {
    if !(seconds.is_finite() && (0.001..=3600.0).contains(&seconds)) {
        return Err(SimError::InvalidConfig(format!(
            "benchmark duration must be 0.001–3600 s, got {seconds}"
        )));
    }
    let mut board = EmulatedBoard::new(BoardConfig::default(), Box::new(busy_script(seconds)?))?;
    board.run_reports(1000);
    let totals = |b: &EmulatedBoard| {
        (0..PADDLES)
            .filter_map(|p| b.port_stats(p))
            .fold((0, 0), |(f, k), s| {
                (f + s.frames_received, k + s.packets_sent)
            })
    };
    let (frames0, packets0) = totals(&board);
    let reports = (seconds * 1000.0).round() as u64;
    let start = Instant::now();
    for _ in 0..reports {
        std::hint::black_box(board.step_report());
    }
    let wall_s = start.elapsed().as_secs_f64().max(1e-9);
    let (frames1, packets1) = totals(&board);
    let emulated_s = reports as f64 / 1000.0;
    Ok(BenchResult {
        emulated_s,
        wall_s,
        emulated_s_per_wall_s: emulated_s / wall_s,
        frames: frames1 - frames0,
        packets: packets1 - packets0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bench_runs_faster_than_real_time_and_streams_everywhere() {
        let r = run(0.5).unwrap();
        // 8 mice × 200 packets/s × 0.5 s, minus a few skipped while bytes queue.
        assert!(r.packets > 700, "{r:?}");
        assert!(r.frames >= 3 * r.packets, "{r:?}");
        assert!(r.emulated_s_per_wall_s > 1.0, "{r:?}");
        assert!(run(-1.0).is_err());
    }
}
