//! The guided calibration motion and the collector that turns it into fit samples.
//!
//! The player (or a script on the emulated board) follows steps whose end poses are
//! known without measuring: the travel stops of the rod and whole turns. At the end of
//! each step, while the rod is held still, the game records a **checkpoint**: the count
//! sums since the first step and the step's known pose. The checkpoints are the samples
//! of [`PaddleCalibration::fit`]. Poses are in the paddle frame (see [`crate::input`]).

use super::calibration::{CalibrationError, PaddleCalibration};
use foosball_protocol::{InReport, PaddleStatus};
use std::f64::consts::TAU;

/// One step of the guided motion.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidedStep {
    /// What the player is asked to do.
    pub instruction: String,
    /// The pose the rod is in at the end of the step: `[slide_m, angle_rad]`.
    pub pose: [f64; 2],
}

/// A sequence of steps; the first one is where counting starts.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidedMotion {
    /// The steps, in order.
    pub steps: Vec<GuidedStep>,
}

impl GuidedMotion {
    /// The standard procedure for a rod with axial travel `travel_m` (m): from the near
    /// stop with the men upright, slide to the far stop, turn `turns` full turns
    /// forward, slide back to the near stop, turn `turns` back to upright, and turn
    /// `turns` backwards once more (so rotation is sampled on both sides of zero).
    /// End-to-end slides and full turns excite each axis alone, which separates gain and
    /// cross-talk.
    pub fn standard(travel_m: f64, turns: u32) -> Self {
        let half = 0.5 * travel_m;
        let turn = TAU * f64::from(turns);
        let step = |instruction: &str, slide: f64, angle: f64| GuidedStep {
            instruction: instruction.into(),
            pose: [slide, angle],
        };
        Self {
            steps: vec![
                step(
                    "pull the rod to the near stop, men upright, and hold",
                    -half,
                    0.0,
                ),
                step("push the rod to the far stop and hold", half, 0.0),
                step(
                    &format!("turn the rod {turns} full turns forward and hold"),
                    half,
                    turn,
                ),
                step("pull the rod to the near stop and hold", -half, turn),
                step(
                    &format!("turn the rod {turns} full turns back and hold"),
                    -half,
                    0.0,
                ),
                step(
                    &format!("turn the rod {turns} more full turns back and hold"),
                    -half,
                    -turn,
                ),
            ],
        }
    }
}

/// Collects one paddle's counts from IN reports and the checkpoints of a guided motion.
#[derive(Debug, Clone)]
pub struct GuidedCollector {
    port: usize,
    sums: [i64; 2],
    samples: Vec<([f64; 2], [f64; 2])>,
    last_sequence: Option<u16>,
    lost_reports: u64,
    absent_reports: u64,
    still_ms: u64,
}

impl GuidedCollector {
    /// A collector for the paddle on board port `port`.
    pub fn new(port: usize) -> Self {
        Self {
            port,
            sums: [0; 2],
            samples: Vec::new(),
            last_sequence: None,
            lost_reports: 0,
            absent_reports: 0,
            still_ms: 0,
        }
    }

    /// Adds one report's counts for the port. Counting starts with the first report
    /// after [`GuidedCollector::start`] (or construction).
    pub fn push(&mut self, report: &InReport) {
        if let Some(last) = self.last_sequence {
            self.lost_reports += u64::from(report.sequence.wrapping_sub(last).wrapping_sub(1));
        }
        self.last_sequence = Some(report.sequence);
        let Some(paddle) = report.paddles.get(self.port) else {
            return;
        };
        if !paddle.status.contains(PaddleStatus::PRESENT) {
            self.absent_reports += 1;
        }
        self.sums[0] += i64::from(paddle.axial);
        self.sums[1] += i64::from(paddle.rotation);
        if paddle.axial == 0 && paddle.rotation == 0 {
            self.still_ms += 1;
        } else {
            self.still_ms = 0;
        }
    }

    /// Starts over: counts from zero (the rod is at the first step's pose now).
    pub fn start(&mut self) {
        *self = Self::new(self.port);
    }

    /// Milliseconds (reports) since the last motion: the game advances a step when the
    /// rod has been still long enough.
    pub fn still_ms(&self) -> u64 {
        self.still_ms
    }

    /// Count sums `[axial, rotation]` since the start.
    pub fn sums(&self) -> [i64; 2] {
        self.sums
    }

    /// Records that the rod is now at `pose` (the current step's known end pose).
    pub fn checkpoint(&mut self, pose: [f64; 2]) {
        self.samples
            .push(([self.sums[0] as f64, self.sums[1] as f64], pose));
    }

    /// The checkpoints so far.
    pub fn samples(&self) -> &[([f64; 2], [f64; 2])] {
        &self.samples
    }

    /// Fits the calibration. Fails if reports were lost or the sensor was absent during
    /// the motion (counts are missing: the player repeats it), or if the checkpoints do
    /// not determine the map.
    pub fn fit(&self) -> Result<PaddleCalibration, CalibrationError> {
        if self.lost_reports > 0 {
            return Err(CalibrationError::Underdetermined(format!(
                "{} reports were lost during the motion; repeat it",
                self.lost_reports
            )));
        }
        if self.absent_reports > 0 {
            return Err(CalibrationError::Underdetermined(format!(
                "the sensor on port {} was absent for {} ms; repeat the motion",
                self.port, self.absent_reports
            )));
        }
        PaddleCalibration::fit(&self.samples)
    }
}
