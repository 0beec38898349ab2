//! Calibration mode: guides the player through the standard motion of each rod in turn
//! ([`GuidedMotion::standard`], run by [`GuidedRun`]): the rod waits for a push to
//! begin, each step's motion is checked (a wrong one is named on screen and the step
//! redone), a checkpoint is taken whenever the rod has been held still after a step,
//! and the paddle's map is fitted and rated (RMS residual of the checkpoints, mm and
//! degrees). A fit that is not good repeats the rod. When every rod is done the session
//! saves the file and the screen says where ([`Calibrator::set_saved`]).

use foosball_protocol::InReport;
use space_foosball::input::calibration::{Calibration, PaddleCalibration};
use space_foosball::input::guided::{GuidedMotion, GuidedRun, RunPhase};
use space_foosball::table::{Role, Table};

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

/// One rod of the table to calibrate.
#[derive(Debug, Clone, Copy)]
struct RodToDo {
    /// Index in the table's rods.
    rod: usize,
    port: usize,
    travel_m: f64,
    /// `"HOME GOALKEEPER"`.
    name: &'static str,
    team: &'static str,
}

fn role_name(role: Role) -> &'static str {
    match role {
        Role::Goalkeeper => "GOALKEEPER",
        Role::Defence => "DEFENCE",
        Role::Midfield => "MIDFIELD",
        Role::Attack => "ATTACK",
    }
}

/// Guided calibration of every rod of a table in turn.
#[derive(Debug, Clone)]
pub struct Calibrator {
    rods: Vec<RodToDo>,
    current: usize,
    run: GuidedRun,
    results: Vec<(usize, RodResult)>,
    calibration: Calibration,
    saved: Option<String>,
}

impl Calibrator {
    /// Starts with the first rod of `table`, keeping `calibration` for rods not redone
    /// (and reading each rod's motion through it for the direction checks).
    pub fn new(table: &Table, calibration: Calibration) -> Self {
        let rods: Vec<RodToDo> = table
            .rods
            .iter()
            .enumerate()
            .map(|(i, r)| RodToDo {
                rod: i,
                port: r.port,
                travel_m: r.travel_m,
                name: role_name(r.role),
                team: match r.team {
                    space_foosball::Side::Home => "HOME",
                    space_foosball::Side::Away => "AWAY",
                },
            })
            .collect();
        let run = Self::run_for(rods.first(), &calibration);
        Self {
            rods,
            current: 0,
            run,
            results: Vec::new(),
            calibration,
            saved: None,
        }
    }

    fn run_for(rod: Option<&RodToDo>, calibration: &Calibration) -> GuidedRun {
        let (port, travel) = rod.map_or((0, 0.1), |r| (r.port, r.travel_m));
        let map = calibration.paddles.get(port).copied().unwrap_or_default();
        GuidedRun::new(GuidedMotion::standard(travel, TURNS), port, map)
    }

    /// The table rod being calibrated; `None` when every rod is done.
    pub fn rod(&self) -> Option<usize> {
        self.rods.get(self.current).map(|r| r.rod)
    }

    #[cfg(test)]
    /// Where the current rod's run stands.
    pub fn phase(&self) -> RunPhase {
        self.run.phase()
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

    /// Whether the file has been saved (or saving was tried) since every rod was done.
    pub fn saved(&self) -> bool {
        self.saved.is_some()
    }

    /// The fits to use and save now: once every rod is done, until
    /// [`Calibrator::set_saved`] says where they went.
    pub fn fits_to_save(&self) -> Option<Calibration> {
        (self.is_done() && !self.saved()).then_some(self.calibration)
    }

    /// Leaving calibration mode: the fits, where they differ from `in_use` (good fits
    /// not yet used and saved).
    pub fn fits_on_leaving(self, in_use: &Calibration) -> Option<Calibration> {
        (self.calibration != *in_use).then_some(self.calibration)
    }

    /// What the screen says about saving: `"SAVED TO /path"` or why not.
    pub fn set_saved(&mut self, message: String) {
        self.saved = Some(message);
    }

    /// Takes one IN report.
    pub fn push(&mut self, report: &InReport) {
        if self.is_done() {
            return;
        }
        self.run.push(report);
        if self.run.phase() != RunPhase::Done {
            return;
        }
        let todo = self.rods[self.current];
        let result = match self.run.result() {
            Some(Ok(cal)) => RodResult::Fitted(*cal, FitQuality::of(cal, self.run.samples())),
            Some(Err(e)) => RodResult::Failed(e.clone()),
            None => RodResult::Failed("no fit".into()),
        };
        let good = match &result {
            RodResult::Fitted(cal, q) if q.is_good() => {
                self.calibration.paddles[todo.port] = *cal;
                true
            }
            _ => false,
        };
        self.results.retain(|(rod, _)| *rod != todo.rod);
        self.results.push((todo.rod, result));
        if good {
            self.current += 1;
        }
        // A fit that is not good repeats the rod.
        self.run = Self::run_for(self.rods.get(self.current), &self.calibration);
    }

    /// What to show: which rod, the instruction now (and why a step is redone), the
    /// fits so far; at the end where the file was saved.
    pub fn hud(&self) -> foosball_render::Hud {
        let heading = match self.rods.get(self.current) {
            Some(todo) => {
                let steps = self.run.motion().steps.len();
                let which = format!(
                    "ROD {} OF {}: {} {} (THE GLOWING ROD)",
                    self.current + 1,
                    self.rods.len(),
                    todo.team,
                    todo.name
                );
                match self.run.phase() {
                    RunPhase::WaitingForPush => format!("{which}\nPUSH THIS ROD TO BEGIN"),
                    RunPhase::Step(k) => {
                        let mut h = format!(
                            "{which}\nSTEP {} OF {steps}: {}",
                            k + 1,
                            self.run.motion().steps[k].instruction
                        );
                        if let Some(w) = self.run.wrong() {
                            h.push_str(&format!("\n{w} - REDO THIS STEP"));
                        }
                        h
                    }
                    RunPhase::Done => which,
                }
            }
            None => match &self.saved {
                Some(msg) => format!("ALL RODS DONE\n{msg}\nESC TO LEAVE"),
                None => "ALL RODS DONE - ESC TO LEAVE".into(),
            },
        };
        let mut lines: Vec<String> = self
            .results
            .iter()
            .map(|(rod, r)| match r {
                RodResult::Fitted(_, q) => format!("ROD {}: {}", rod + 1, q.describe()),
                RodResult::Failed(e) => format!("ROD {}: FAILED - {e} - REPEAT", rod + 1),
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
    use space_foosball::input::guided::HOLD_MS;

    /// An ideal sensor on `port` (the nominal map) reporting a rod's motion.
    struct Sensor {
        port: usize,
        seq: u16,
        sent: [f64; 2],
        pose: [f64; 2],
    }

    impl Sensor {
        fn go(&mut self, c: &mut Calibrator, pose: [f64; 2]) {
            let nominal = PaddleCalibration::default();
            let start = self.pose;
            for i in 1..=100 {
                let f = f64::from(i) / 100.0;
                let p = [
                    start[0] + (pose[0] - start[0]) * f,
                    start[1] + (pose[1] - start[1]) * f,
                ];
                let want = nominal.counts_for(p).unwrap();
                let d = [
                    (want[0] - self.sent[0]).round(),
                    (want[1] - self.sent[1]).round(),
                ];
                self.sent = [self.sent[0] + d[0], self.sent[1] + d[1]];
                self.send(c, [d[0] as i16, d[1] as i16]);
            }
            self.pose = pose;
            for _ in 0..HOLD_MS + 5 {
                self.send(c, [0, 0]);
            }
        }

        fn send(&mut self, c: &mut Calibrator, counts: [i16; 2]) {
            self.seq = self.seq.wrapping_add(1);
            let mut r = InReport::all_present(self.seq);
            r.paddles[self.port].axial = counts[0];
            r.paddles[self.port].rotation = counts[1];
            c.push(&r);
        }
    }

    #[test]
    fn a_clean_motion_fits_well_and_moves_to_the_next_rod() {
        let table = Table::standard();
        let mut c = Calibrator::new(&table, Calibration::default());
        let mut rod = Sensor {
            port: table.rods[0].port,
            seq: 0,
            sent: [0.0; 2],
            pose: [0.0; 2],
        };
        let motion = GuidedMotion::standard(table.rods[0].travel_m, TURNS);
        assert!(
            c.hud().heading.contains("PUSH THIS ROD TO BEGIN"),
            "{:?}",
            c.hud()
        );
        // Resting or pulling does not begin.
        rod.go(&mut c, [-0.02, 0.0]);
        assert_eq!(c.phase(), RunPhase::WaitingForPush);
        // Push to begin, then the steps.
        rod.go(&mut c, [0.03, 0.0]);
        assert_eq!(c.phase(), RunPhase::Step(0), "{:?}", c.hud());
        assert!(c.hud().heading.contains("STEP 1 OF 6"), "{:?}", c.hud());
        for step in &motion.steps {
            rod.go(&mut c, step.pose);
        }
        assert_eq!(c.rod(), Some(1), "{:?}", c.results());
        assert_eq!(c.phase(), RunPhase::WaitingForPush);
        match &c.results()[0].1 {
            RodResult::Fitted(_, q) => assert!(q.is_good(), "{q:?}"),
            other => panic!("{other:?}"),
        }
        assert!(c.hud().lines[0].contains("GOOD"));
        assert!(
            c.hud().heading.starts_with("ROD 2 OF 8: HOME DEFENCE"),
            "{:?}",
            c.hud()
        );
    }

    #[test]
    fn a_wrong_step_is_named_and_redone() {
        let table = Table::standard();
        let mut c = Calibrator::new(&table, Calibration::default());
        let mut rod = Sensor {
            port: table.rods[0].port,
            seq: 0,
            sent: [0.0; 2],
            pose: [0.0; 2],
        };
        rod.go(&mut c, [0.03, 0.0]);
        // Step 1 asks for the near stop; pushing on to the far stop is the wrong way.
        rod.go(&mut c, [0.05, 0.0]);
        assert_eq!(c.phase(), RunPhase::Step(0));
        let heading = c.hud().heading;
        assert!(
            heading.contains("wrong way: the rod slid away from you - REDO THIS STEP"),
            "{heading}"
        );
        rod.go(&mut c, [-0.05, 0.0]);
        assert_eq!(c.phase(), RunPhase::Step(1));
        assert!(!c.hud().heading.contains("REDO"), "{:?}", c.hud());
    }
}
