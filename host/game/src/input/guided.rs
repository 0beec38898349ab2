//! The guided calibration motion and the collector that turns it into fit samples.
//!
//! The player (or a script on the emulated board) follows steps whose end poses are
//! known without measuring: the travel stops of the rod and whole turns. At the end of
//! each step, while the rod is held still, the game records a **checkpoint**: the count
//! sums since the first step and the step's known pose. The checkpoints are the samples
//! of [`PaddleCalibration::fit`]. Poses are in the paddle frame (see [`crate::input`]).

use super::calibration::{CalibrationError, PaddleCalibration, DEFAULT_ROD_RADIUS_M};
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

/// How long a rod must be held still to end a step, ms of reports.
pub const HOLD_MS: u64 = 600;
/// The forward slide that starts a rod's guided motion (the "push to begin"), m.
pub const BEGIN_PUSH_M: f64 = 0.02;
/// The least slide towards the player that ends the first step, m: from where the
/// begin push was recognised the near stop is at least [`BEGIN_PUSH_M`] back.
pub const FIRST_STEP_MIN_M: f64 = 0.01;
/// A step's motion along its axis must reach this share of the step's known motion.
/// The direction checks go through the paddle's current map, which may be off by the
/// sensor's gain error (a few per cent); half the motion is safely "not done".
pub const MIN_STEP_SHARE: f64 = 0.5;
/// A step may move the rod along the axis it keeps by at most this share of its own
/// motion, both measured along the rod's surface (a turn as the angle times the rod
/// radius): the men stay upright while sliding, the rod stays at its stop while
/// turning. A sensor's cross-talk (a few per cent when it sits a few degrees askew)
/// stays well under it.
pub const MAX_OFF_AXIS_SHARE: f64 = 0.25;

/// An axis of a rod's motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Along the rod.
    Slide,
    /// About the rod.
    Turn,
}

/// Why a step's motion was not taken (the player redoes the step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WrongMove {
    /// The rod moved the other way along the step's axis; `moved` is the motion (m for
    /// a slide, rad for a turn; paddle frame).
    WrongWay {
        /// The axis.
        axis: Axis,
        /// The measured motion since the step began.
        moved: f64,
    },
    /// The rod moved the right way but well short of the step's motion.
    TooShort {
        /// The axis.
        axis: Axis,
        /// The measured motion (m or rad).
        moved: f64,
        /// The step's known motion (m or rad); `None` for the first step, which goes
        /// to the near stop from wherever the rod was.
        wanted: Option<f64>,
    },
    /// The rod also moved along the other axis (`axis`) by `moved` (m or rad).
    OffAxis {
        /// The axis that should have stayed put.
        axis: Axis,
        /// How far it moved.
        moved: f64,
    },
}

impl std::fmt::Display for WrongMove {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let turns = |rad: f64| rad.abs() / TAU;
        match *self {
            WrongMove::WrongWay {
                axis: Axis::Slide,
                moved,
            } => write!(
                f,
                "wrong way: the rod slid {} you",
                if moved > 0.0 { "away from" } else { "towards" }
            ),
            WrongMove::WrongWay {
                axis: Axis::Turn,
                moved,
            } => write!(
                f,
                "wrong way: the rod turned {}",
                if moved > 0.0 { "forward" } else { "back" }
            ),
            WrongMove::TooShort {
                axis: Axis::Slide,
                moved,
                wanted: Some(wanted),
            } => write!(
                f,
                "not far enough: the rod slid {:.0} of {:.0} mm",
                moved.abs() * 1e3,
                wanted.abs() * 1e3
            ),
            WrongMove::TooShort {
                axis: Axis::Slide,
                moved,
                wanted: None,
            } => write!(
                f,
                "not far enough: the rod slid {:.0} mm, not to the stop",
                moved.abs() * 1e3
            ),
            WrongMove::TooShort {
                axis: Axis::Turn,
                moved,
                wanted,
            } => write!(
                f,
                "not far enough: the rod turned {:.1} of {:.0} turns",
                turns(moved),
                wanted.map_or(0.0, turns)
            ),
            WrongMove::OffAxis {
                axis: Axis::Turn,
                moved,
            } => write!(
                f,
                "the rod turned {:.1} turns while sliding: keep the men upright",
                turns(moved)
            ),
            WrongMove::OffAxis {
                axis: Axis::Slide,
                moved,
            } => write!(
                f,
                "the rod slid {:.0} mm while turning: keep it at the stop",
                moved.abs() * 1e3
            ),
        }
    }
}

impl GuidedMotion {
    /// Checks the motion `moved` (`[slide_m, angle_rad]`, paddle frame) made for step
    /// `step` (from the previous step's pose; for step 0 from where the begin push was
    /// recognised).
    ///
    /// Step 0 must slide towards the player by at least [`FIRST_STEP_MIN_M`] (the near
    /// stop is behind the begin push). A later step must move along each axis its
    /// poses change by the right sign and at least [`MIN_STEP_SHARE`] of the change,
    /// and along an axis they keep by at most [`MAX_TURN_WHILE_SLIDING_RAD`] or
    /// [`MAX_SLIDE_WHILE_TURNING_SHARE`] of the travel.
    pub fn check(&self, step: usize, moved: [f64; 2]) -> Result<(), WrongMove> {
        if step == 0 {
            return if moved[0] <= -FIRST_STEP_MIN_M {
                Ok(())
            } else if moved[0] > 0.0 {
                Err(WrongMove::WrongWay {
                    axis: Axis::Slide,
                    moved: moved[0],
                })
            } else {
                Err(WrongMove::TooShort {
                    axis: Axis::Slide,
                    moved: moved[0],
                    wanted: None,
                })
            };
        }
        let (Some(this), Some(prev)) = (self.steps.get(step), self.steps.get(step - 1)) else {
            return Ok(());
        };
        let axes = [Axis::Slide, Axis::Turn];
        // Motion along the rod's surface, m: a turn as the angle times the rod radius.
        let surface = [1.0, DEFAULT_ROD_RADIUS_M];
        let wanted = [this.pose[0] - prev.pose[0], this.pose[1] - prev.pose[1]];
        let wanted_surface = (0..2)
            .map(|a| (wanted[a] * surface[a]).abs())
            .fold(0.0, f64::max);
        for a in 0..2 {
            if wanted[a] == 0.0 {
                continue;
            }
            if moved[a] * wanted[a] < 0.0 {
                return Err(WrongMove::WrongWay {
                    axis: axes[a],
                    moved: moved[a],
                });
            }
            if moved[a].abs() < MIN_STEP_SHARE * wanted[a].abs() {
                return Err(WrongMove::TooShort {
                    axis: axes[a],
                    moved: moved[a],
                    wanted: Some(wanted[a]),
                });
            }
        }
        for a in 0..2 {
            if wanted[a] == 0.0
                && (moved[a] * surface[a]).abs() > MAX_OFF_AXIS_SHARE * wanted_surface
            {
                return Err(WrongMove::OffAxis {
                    axis: axes[a],
                    moved: moved[a],
                });
            }
        }
        Ok(())
    }
}

/// Where one rod's guided run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunPhase {
    /// Waiting for the push that begins it (nothing is counted yet).
    WaitingForPush,
    /// Doing step `n` (0-based) of the motion.
    Step(usize),
    /// Every step done; the fit is in [`GuidedRun::result`].
    Done,
}

/// What one report changed in a [`GuidedRun`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Progress {
    /// Nothing new.
    Nothing,
    /// The begin push was recognised: step 0 starts.
    Began,
    /// Step `n` was checked and its checkpoint taken.
    Checkpoint(usize),
    /// The step's motion was wrong: the player redoes it.
    Redo(WrongMove),
    /// The last checkpoint was taken and the map fitted.
    Finished,
}

/// One rod's guided calibration from raw IN reports: waits for a push to begin, then
/// takes each step's checkpoint once the rod has moved and been held still for
/// [`HOLD_MS`], after checking the step's motion ([`GuidedMotion::check`]; a wrong
/// one is not taken and the step is redone), and fits the map after the last step.
///
/// The checks read the counts through `map`, the paddle's current calibration (the
/// defaults, or an earlier fit): they need its signs and rough scale, not its accuracy.
#[derive(Debug, Clone)]
pub struct GuidedRun {
    motion: GuidedMotion,
    map: PaddleCalibration,
    collector: GuidedCollector,
    phase: RunPhase,
    /// Count sums the current step's motion is measured from.
    reference: [i64; 2],
    /// Lowest slide seen while waiting for the begin push, m.
    lowest_slide_m: f64,
    moved: bool,
    /// Step 0's first hold after the begin push ends that push: its motion is not
    /// checked, the step is measured from there.
    settling: bool,
    wrong: Option<WrongMove>,
    result: Option<Result<PaddleCalibration, String>>,
}

impl GuidedRun {
    /// A run of `motion` for the paddle on board port `port`, its motion read through
    /// `map` for the checks.
    pub fn new(motion: GuidedMotion, port: usize, map: PaddleCalibration) -> Self {
        Self {
            motion,
            map,
            collector: GuidedCollector::new(port),
            phase: RunPhase::WaitingForPush,
            reference: [0; 2],
            lowest_slide_m: f64::INFINITY,
            moved: false,
            settling: false,
            wrong: None,
            result: None,
        }
    }

    /// Where the run stands.
    pub fn phase(&self) -> RunPhase {
        self.phase
    }

    /// The motion being followed.
    pub fn motion(&self) -> &GuidedMotion {
        &self.motion
    }

    /// The last step's motion that was not taken, until the step is done.
    pub fn wrong(&self) -> Option<WrongMove> {
        self.wrong
    }

    /// The fitted map, or why it could not be fitted; `None` until [`RunPhase::Done`].
    pub fn result(&self) -> Option<&Result<PaddleCalibration, String>> {
        self.result.as_ref()
    }

    /// The checkpoints taken, `(count sums, known pose)`.
    pub fn samples(&self) -> &[([f64; 2], [f64; 2])] {
        self.collector.samples()
    }

    fn moved_since_reference(&self) -> [f64; 2] {
        let s = self.collector.sums();
        self.map.apply_delta([
            (s[0] - self.reference[0]) as f64,
            (s[1] - self.reference[1]) as f64,
        ])
    }

    /// Takes one IN report.
    pub fn push(&mut self, report: &InReport) -> Progress {
        if self.phase == RunPhase::Done {
            return Progress::Nothing;
        }
        self.collector.push(report);
        let still = self.collector.still_ms();
        match self.phase {
            RunPhase::WaitingForPush => {
                let slide = self.moved_since_reference()[0];
                self.lowest_slide_m = self.lowest_slide_m.min(slide);
                if slide - self.lowest_slide_m >= BEGIN_PUSH_M {
                    self.reference = self.collector.sums();
                    self.phase = RunPhase::Step(0);
                    self.moved = true;
                    self.settling = true;
                    return Progress::Began;
                }
                Progress::Nothing
            }
            RunPhase::Step(step) => {
                if still == 0 {
                    self.moved = true;
                }
                if !self.moved || still < HOLD_MS {
                    return Progress::Nothing;
                }
                self.moved = false;
                let moved = self.moved_since_reference();
                let settling = std::mem::take(&mut self.settling);
                if settling && moved[0] > -FIRST_STEP_MIN_M {
                    // The begin push came to rest (the rod pushed on, held, or came
                    // back a little): step 0 starts from here.
                    self.reference = self.collector.sums();
                    return Progress::Nothing;
                }
                if let Err(w) = self.motion.check(step, moved) {
                    self.wrong = Some(w);
                    return Progress::Redo(w);
                }
                self.wrong = None;
                if step == 0 {
                    // Counting starts here, at the first pose.
                    self.collector.start();
                }
                self.collector.checkpoint(self.motion.steps[step].pose);
                self.reference = self.collector.sums();
                if step + 1 < self.motion.steps.len() {
                    self.phase = RunPhase::Step(step + 1);
                    return Progress::Checkpoint(step);
                }
                self.phase = RunPhase::Done;
                self.result = Some(self.collector.fit().map_err(|e| e.to_string()));
                Progress::Finished
            }
            RunPhase::Done => Progress::Nothing,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRAVEL_M: f64 = 0.116;
    const PORT: usize = 2;

    /// Feeds reports to a run as a rod on an ideal sensor (the nominal map) would send
    /// them: moves to `pose` over 100 reports, then holds for `hold_ms`.
    struct Rod {
        run: GuidedRun,
        seq: u16,
        sent: [f64; 2],
        pose: [f64; 2],
        log: Vec<Progress>,
    }

    impl Rod {
        fn new() -> Self {
            let motion = GuidedMotion::standard(TRAVEL_M, 2);
            Self {
                run: GuidedRun::new(motion, PORT, PaddleCalibration::default()),
                seq: 0,
                sent: [0.0; 2],
                pose: [0.0; 2],
                log: Vec::new(),
            }
        }

        fn report(&mut self, counts: [i16; 2]) {
            self.seq = self.seq.wrapping_add(1);
            let mut r = InReport::all_present(self.seq);
            r.paddles[PORT].axial = counts[0];
            r.paddles[PORT].rotation = counts[1];
            let p = self.run.push(&r);
            if p != Progress::Nothing {
                self.log.push(p);
            }
        }

        fn go(&mut self, pose: [f64; 2], hold_ms: u64) {
            let nominal = PaddleCalibration::default();
            let start = self.pose;
            for i in 1..=100 {
                let f = f64::from(i) / 100.0;
                let p = [
                    start[0] + (pose[0] - start[0]) * f,
                    start[1] + (pose[1] - start[1]) * f,
                ];
                let c = nominal.counts_for(p).unwrap();
                let d = [(c[0] - self.sent[0]).round(), (c[1] - self.sent[1]).round()];
                self.sent = [self.sent[0] + d[0], self.sent[1] + d[1]];
                self.report([d[0] as i16, d[1] as i16]);
            }
            self.pose = pose;
            for _ in 0..hold_ms {
                self.report([0, 0]);
            }
        }
    }

    #[test]
    fn waits_for_the_push_checks_each_step_and_fits() {
        let mut rod = Rod::new();
        // Resting, spinning or pulling does not begin.
        rod.go([0.0, 0.0], HOLD_MS + 10);
        rod.go([0.0, 7.0], HOLD_MS + 10);
        rod.go([-0.05, 7.0], HOLD_MS + 10);
        assert_eq!(rod.run.phase(), RunPhase::WaitingForPush);
        // A push begins; where it comes to rest step 0 starts; pushing on to the far
        // stop is then the wrong way.
        let half = 0.5 * TRAVEL_M;
        rod.go([0.0, 7.0], HOLD_MS + 10);
        assert_eq!(rod.run.phase(), RunPhase::Step(0));
        assert_eq!(rod.run.wrong(), None);
        rod.go([half, 7.0], HOLD_MS + 10);
        assert!(matches!(
            rod.run.wrong(),
            Some(WrongMove::WrongWay {
                axis: Axis::Slide,
                ..
            })
        ));
        // Pulled back to the near stop: taken.
        rod.go([-half, 7.0], HOLD_MS + 10);
        assert_eq!(rod.run.phase(), RunPhase::Step(1));
        assert_eq!(rod.run.wrong(), None);
        // Step 1 (far stop): turning instead slides nowhere, pulling is the wrong way, 40 %
        // of the travel is too short.
        rod.go([-half, 7.0 + TAU], HOLD_MS + 10);
        assert!(matches!(rod.run.wrong(), Some(WrongMove::TooShort { moved, .. }) if moved == 0.0));
        rod.go([-half - 0.03, 7.0], HOLD_MS + 10);
        assert!(matches!(rod.run.wrong(), Some(WrongMove::WrongWay { .. })));
        rod.go([-half + 0.4 * TRAVEL_M, 7.0], HOLD_MS + 10);
        assert!(matches!(rod.run.wrong(), Some(WrongMove::TooShort { .. })));
        assert_eq!(rod.run.phase(), RunPhase::Step(1));
        // The rest, in order (angles relative to where counting started).
        let motion = GuidedMotion::standard(TRAVEL_M, 2);
        for step in &motion.steps[1..] {
            rod.go([step.pose[0], 7.0 + step.pose[1]], HOLD_MS + 10);
        }
        assert_eq!(rod.run.phase(), RunPhase::Done, "{:?}", rod.log);
        let fit = rod.run.result().unwrap().as_ref().unwrap();
        let nominal = PaddleCalibration::default();
        for r in 0..2 {
            assert!((fit.matrix[r][r] / nominal.matrix[r][r] - 1.0).abs() < 0.01);
        }
        assert_eq!(rod.run.samples().len(), motion.steps.len());
        let redos = rod
            .log
            .iter()
            .filter(|p| matches!(p, Progress::Redo(_)))
            .count();
        assert_eq!(redos, 4, "{:?}", rod.log);
    }

    #[test]
    fn checks_name_the_wrong_axis() {
        let m = GuidedMotion::standard(TRAVEL_M, 2);
        // Step 2 turns two turns forward at the far stop.
        assert_eq!(m.check(2, [0.0, 2.0 * TAU]), Ok(()));
        assert!(matches!(
            m.check(2, [0.0, -2.0 * TAU]),
            Err(WrongMove::WrongWay {
                axis: Axis::Turn,
                ..
            })
        ));
        assert!(matches!(
            m.check(2, [-0.05, 2.0 * TAU]),
            Err(WrongMove::OffAxis {
                axis: Axis::Slide,
                ..
            })
        ));
        // Step 1 slides to the far stop: turning a full turn on the way is off axis.
        assert!(matches!(
            m.check(1, [TRAVEL_M, TAU]),
            Err(WrongMove::OffAxis {
                axis: Axis::Turn,
                ..
            })
        ));
        let text = m.check(0, [0.03, 0.0]).unwrap_err().to_string();
        assert_eq!(text, "wrong way: the rod slid away from you");
    }
}
