//! Calibration mode: guides the player through the standard motion of each rod
//! ([`GuidedMotion::standard`]), records a checkpoint whenever the rod has been held
//! still after a step, fits the paddle's map ([`GuidedCollector::fit`]) and shows how
//! well it fits (RMS residual of the checkpoints, mm and degrees).
//!
//! A step's checkpoint is taken once the rod has moved since the previous checkpoint
//! (for the first step: since the rod was called, so a rod is never checkpointed where
//! it happened to rest) and then stayed still for [`HOLD_MS`] ms of reports.

use foosball_protocol::InReport;
use space_foosball::input::calibration::{Calibration, PaddleCalibration};
use space_foosball::input::guided::{GuidedCollector, GuidedMotion};
use space_foosball::table::Table;

/// How long a rod must be held still to end a step, ms of reports.
pub const HOLD_MS: u64 = 600;
/// Full turns per turning step.
pub const TURNS: u32 = 2;
/// A fit is called good under this RMS slide residual, m.
pub const GOOD_SLIDE_RMS_M: f64 = 0.001;
/// A fit is called good under this RMS angle residual, rad.
pub const GOOD_ANGLE_RMS_RAD: f64 = 0.035;

/// How well a fitted map reproduces its checkpoints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitQuality {
    /// RMS slide error, m.
    pub slide_rms_m: f64,
    /// RMS angle error, rad.
    pub angle_rms_rad: f64,
}

impl FitQuality {
    /// The residuals of `cal` on `samples` (count sums, true pose).
    pub fn of(cal: &PaddleCalibration, samples: &[([f64; 2], [f64; 2])]) -> Self {
        let n = samples.len().max(1) as f64;
        let (mut s, mut a) = (0.0, 0.0);
        for (counts, pose) in samples {
            let p = cal.apply(*counts);
            s += (p[0] - pose[0]).powi(2);
            a += (p[1] - pose[1]).powi(2);
        }
        Self {
            slide_rms_m: (s / n).sqrt(),
            angle_rms_rad: (a / n).sqrt(),
        }
    }

    /// Whether both residuals are under the "good" limits.
    pub fn is_good(&self) -> bool {
        self.slide_rms_m < GOOD_SLIDE_RMS_M && self.angle_rms_rad < GOOD_ANGLE_RMS_RAD
    }

    /// `"RMS 0.31 MM 0.52 DEG - GOOD"`.
    pub fn describe(&self) -> String {
        format!(
            "RMS {:.2} MM {:.2} DEG - {}",
            self.slide_rms_m * 1e3,
            self.angle_rms_rad.to_degrees(),
            if self.is_good() { "GOOD" } else { "REPEAT" }
        )
    }
}

/// The outcome for one rod.
#[derive(Debug, Clone, PartialEq)]
pub enum RodResult {
    /// Fitted, with its quality.
    Fitted(PaddleCalibration, FitQuality),
    /// The fit failed (why).
    Failed(String),
}

/// Guided calibration of every rod of a table in turn.
#[derive(Debug, Clone)]
pub struct Calibrator {
    /// `(table rod, port, travel_m)` in order.
    rods: Vec<(usize, usize, f64)>,
    current: usize,
    motion: GuidedMotion,
    step: usize,
    collector: GuidedCollector,
    moved: bool,
    results: Vec<(usize, RodResult)>,
    calibration: Calibration,
}

impl Calibrator {
    /// Starts with the first rod of `table`, keeping `calibration` for rods not redone.
    pub fn new(table: &Table, calibration: Calibration) -> Self {
        let rods: Vec<(usize, usize, f64)> = table
            .rods
            .iter()
            .enumerate()
            .map(|(i, r)| (i, r.port, r.travel_m))
            .collect();
        let (port, travel) = rods.first().map_or((0, 0.1), |r| (r.1, r.2));
        Self {
            rods,
            current: 0,
            motion: GuidedMotion::standard(travel, TURNS),
            step: 0,
            collector: GuidedCollector::new(port),
            moved: false,
            results: Vec::new(),
            calibration,
        }
    }

    /// The table rod being calibrated; `None` when every rod is done.
    pub fn rod(&self) -> Option<usize> {
        self.rods.get(self.current).map(|r| r.0)
    }

    #[cfg(test)]
    /// The step being done (0-based) and how many there are.
    pub fn step(&self) -> (usize, usize) {
        (self.step, self.motion.steps.len())
    }

    /// Whether every rod is done.
    pub fn is_done(&self) -> bool {
        self.current >= self.rods.len()
    }

    #[cfg(test)]
    /// The results so far, `(table rod, result)`.
    pub fn results(&self) -> &[(usize, RodResult)] {
        &self.results
    }

    /// The calibration with every good fit so far applied.
    pub fn calibration(&self) -> Calibration {
        self.calibration
    }

    /// Takes one IN report.
    pub fn push(&mut self, report: &InReport) {
        if self.is_done() {
            return;
        }
        self.collector.push(report);
        if self.collector.still_ms() == 0 {
            self.moved = true;
        }
        if self.moved && self.collector.still_ms() >= HOLD_MS {
            self.checkpoint();
        }
    }

    fn checkpoint(&mut self) {
        let pose = self.motion.steps[self.step].pose;
        if self.step == 0 {
            self.collector.start();
        }
        self.collector.checkpoint(pose);
        self.moved = false;
        self.step += 1;
        if self.step < self.motion.steps.len() {
            return;
        }
        let (rod, port, _) = self.rods[self.current];
        let result = match self.collector.fit() {
            Ok(cal) => {
                let q = FitQuality::of(&cal, self.collector.samples());
                if q.is_good() {
                    self.calibration.paddles[port] = cal;
                }
                RodResult::Fitted(cal, q)
            }
            Err(e) => RodResult::Failed(e.to_string()),
        };
        self.results.push((rod, result));
        self.current += 1;
        if let Some(&(_, port, travel)) = self.rods.get(self.current) {
            self.motion = GuidedMotion::standard(travel, TURNS);
            self.collector = GuidedCollector::new(port);
            self.step = 0;
            self.moved = false;
        }
    }

    /// What to show: the instruction now, and the fits so far.
    pub fn hud(&self) -> foosball_render::Hud {
        let heading = match self.rod() {
            Some(rod) => format!(
                "ROD {} - STEP {} OF {}\n{}",
                rod + 1,
                self.step + 1,
                self.motion.steps.len(),
                self.motion.steps[self.step].instruction
            ),
            None => "ALL RODS DONE - ESC TO SAVE AND LEAVE".into(),
        };
        let mut lines: Vec<String> = self
            .results
            .iter()
            .map(|(rod, r)| match r {
                RodResult::Fitted(_, q) => format!("ROD {}: {}", rod + 1, q.describe()),
                RodResult::Failed(e) => format!("ROD {}: FAILED - {e}", rod + 1),
            })
            .collect();
        lines.push(
            "KEYS: W/S SLIDE TO THE STOPS - T/G ONE TURN FORWARD/BACK - ESC SAVE AND LEAVE".into(),
        );
        foosball_render::Hud {
            heading,
            lines,
            ..foosball_render::Hud::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(seq: u16, port: usize, counts: [i16; 2]) -> InReport {
        let mut r = InReport::all_present(seq);
        r.paddles[port].axial = counts[0];
        r.paddles[port].rotation = counts[1];
        r
    }

    #[test]
    fn a_clean_motion_fits_well_and_moves_to_the_next_rod() {
        let table = Table::standard();
        let mut c = Calibrator::new(&table, Calibration::default());
        let port = table.rods[0].port;
        let nominal = PaddleCalibration::default();
        let motion = GuidedMotion::standard(table.rods[0].travel_m, TURNS);
        let mut seq = 0u16;
        let mut sums = [0.0f64; 2];
        let mut send = |c: &mut Calibrator, counts: [i16; 2]| {
            seq = seq.wrapping_add(1);
            c.push(&report(seq, port, counts));
        };
        // Resting where it was does not count: the first step needs motion.
        for _ in 0..HOLD_MS + 5 {
            send(&mut c, [0, 0]);
        }
        assert_eq!(c.step().0, 0);
        // Pull to the near stop (counts before the first checkpoint do not matter),
        // hold, then move to each next pose and hold.
        for _ in 0..20 {
            send(&mut c, [-30, 0]);
        }
        for _ in 0..HOLD_MS + 5 {
            send(&mut c, [0, 0]);
        }
        assert_eq!(c.step().0, 1);
        for k in 1..motion.steps.len() {
            let target = nominal.counts_for(motion.steps[k].pose).unwrap();
            let base = nominal.counts_for(motion.steps[0].pose).unwrap();
            let want = [target[0] - base[0], target[1] - base[1]];
            // Move in 100 reports.
            for i in 1..=100 {
                let f = i as f64 / 100.0;
                let next = [want[0] * f, want[1] * f];
                let d = [(next[0] - sums[0]).round(), (next[1] - sums[1]).round()];
                sums = [sums[0] + d[0], sums[1] + d[1]];
                send(&mut c, [d[0] as i16, d[1] as i16]);
            }
            for _ in 0..HOLD_MS + 5 {
                send(&mut c, [0, 0]);
            }
        }
        assert_eq!(c.rod(), Some(1), "{:?}", c.results());
        // The next rod, resting, is not checkpointed where it happens to be.
        for _ in 0..HOLD_MS + 5 {
            send(&mut c, [0, 0]);
        }
        assert_eq!(c.step().0, 0);
        match &c.results()[0].1 {
            RodResult::Fitted(_, q) => assert!(q.is_good(), "{q:?}"),
            other => panic!("{other:?}"),
        }
        assert!(c.hud().lines[0].contains("GOOD"));
    }
}
