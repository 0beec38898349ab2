//! The accuracy report's reference problems: what each integrator's error costs in CPU time.
//!
//! Every problem runs through the engine's [`World`](crate::pipeline::World) with the
//! integrator selected, so the cost is the cost of the product's step. Error is measured
//! against an analytic solution where one exists and otherwise against a converged reference
//! (RKMK4 at [`REFERENCE_DT`]). Problems (one module each):
//!
//! * [`free_body`] — the torque-free tumbling box (Dzhanibekov effect): energy and
//!   angular-momentum drift, flips, body angular velocity against the reference;
//!   [`free_body::step_cost`] times one free-body step of each integrator;
//! * [`articulated`] — the heavy symmetric top in steady precession (analytic), a double
//!   pendulum and a 10-link chain (against the reference);
//! * [`contact`] — a ball bouncing on cloth (rebound height `e² h₀`) and rolling to a stop
//!   (distance `v₀² / (2 · 5/7 μ_r g)`); towers of boxes (sink and drift against substeps).
//!
//! `vphys accuracy` runs the sweep and writes the table and the chart.

pub mod articulated;
pub mod contact;
pub mod free_body;

use std::collections::BTreeMap;

use serde::Serialize;

use crate::pipeline::IntegratorKind;

/// Step of the converged references (s).
pub const REFERENCE_DT: f64 = 1.0 / 64000.0;

/// Steps of the full sweep (s): 1/30 … 1/16000.
pub const SWEEP: [f64; 10] = [
    1.0 / 30.0,
    1.0 / 60.0,
    1.0 / 120.0,
    1.0 / 250.0,
    1.0 / 500.0,
    1.0 / 1000.0,
    1.0 / 2000.0,
    1.0 / 4000.0,
    1.0 / 8000.0,
    1.0 / 16000.0,
];

/// Steps of the quick sweep (s).
pub const QUICK_SWEEP: [f64; 5] = [
    1.0 / 30.0,
    1.0 / 120.0,
    1.0 / 500.0,
    1.0 / 1000.0,
    1.0 / 4000.0,
];

/// The problems of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Problem {
    /// Torque-free tumbling box 0.1 × 0.2 × 0.4 m, 1 kg, ω₀ = (0, 5, 0.05) rad/s, 10 s.
    TumblingBox,
    /// Heavy symmetric top in steady precession against the analytic motion, 5 s.
    HeavyTop,
    /// Double pendulum (articulated) against the converged reference, 5 s.
    DoublePendulum,
    /// 10-link chain (articulated) against the converged reference, 3 s.
    Chain10,
    /// Ball bouncing and rolling on cloth against the analytic rebound and stopping distance.
    BallOnCloth,
    /// Towers of boxes: sink and drift against substeps.
    Towers,
}

impl Problem {
    /// Every problem, in report order.
    pub const ALL: [Problem; 6] = [
        Problem::TumblingBox,
        Problem::HeavyTop,
        Problem::DoublePendulum,
        Problem::Chain10,
        Problem::BallOnCloth,
        Problem::Towers,
    ];

    /// Report name.
    pub fn name(self) -> &'static str {
        match self {
            Problem::TumblingBox => "tumbling-box",
            Problem::HeavyTop => "heavy-top",
            Problem::DoublePendulum => "double-pendulum",
            Problem::Chain10 => "chain-10",
            Problem::BallOnCloth => "ball-on-cloth",
            Problem::Towers => "towers",
        }
    }

    /// What the `error` column measures.
    pub fn error_meaning(self) -> &'static str {
        match self {
            Problem::TumblingBox => "max |ω_b − ω_ref| / |ω₀| at 0.1 s samples",
            Problem::HeavyTop => "max angle (rad) between the symmetry axis and the analytic axis",
            Problem::DoublePendulum | Problem::Chain10 => "max |q − q_ref|∞ (rad) at 0.1 s samples",
            Problem::BallOnCloth => "max relative error of rebound height and rolling distance",
            Problem::Towers => "max sink or horizontal drift of any box (m)",
        }
    }
}

/// One row of the report: a problem run with one integrator at one step.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Problem name.
    pub problem: &'static str,
    /// Integrator name.
    pub integrator: &'static str,
    /// Integrator step (s): the world step over its substeps.
    pub dt: f64,
    /// The problem's error measure (see [`Problem::error_meaning`]); `inf` when it diverged.
    pub error: f64,
    /// CPU seconds per simulated second (stepping only).
    pub cpu_s_per_sim_s: f64,
    /// Relative energy change over the run (tumbling box, pendulum, chain, top).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_drift: Option<f64>,
    /// Relative change of the world angular momentum (tumbling box).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub momentum_drift: Option<f64>,
    /// Sign changes of the intermediate-axis angular velocity (tumbling box; reference 3).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flips: Option<u32>,
    /// Solver substeps (towers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub substeps: Option<usize>,
    /// Deepest overlap at the end (m) (towers, ball).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) penetration: Option<f64>,
    /// Problem-specific detail: name → value (units in the name: `_m`, …).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub(crate) detail: BTreeMap<&'static str, f64>,
}

impl Row {
    /// A row with only the common fields set.
    pub(crate) fn new(problem: Problem, integrator: IntegratorKind, dt: f64) -> Self {
        Self {
            problem: problem.name(),
            integrator: integrator.name(),
            dt,
            error: f64::INFINITY,
            cpu_s_per_sim_s: 0.0,
            energy_drift: None,
            momentum_drift: None,
            flips: None,
            substeps: None,
            penetration: None,
            detail: BTreeMap::new(),
        }
    }
}

/// Maps NaN to `inf` (a diverged run's error).
pub(crate) fn finite_or_inf(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        f64::INFINITY
    }
}

/// The clock the cost columns read, s: set once by the program that reports them
/// ([`set_clock`]); wall-clock seconds since the first reading otherwise.
static CLOCK: std::sync::OnceLock<fn() -> f64> = std::sync::OnceLock::new();

/// Sets the clock of the cost columns (seconds, any origin: they difference two
/// readings), e.g. the thread's CPU time, so that time the scheduler gives to other
/// processes on a shared machine does not count (`vphys accuracy` does). Only the first
/// call counts; returns whether it did.
pub fn set_clock(clock: fn() -> f64) -> bool {
    CLOCK.set(clock).is_ok()
}

/// A reading of the cost columns' clock (s; see [`set_clock`]).
pub fn cpu_seconds() -> f64 {
    match CLOCK.get() {
        Some(clock) => clock(),
        None => wall_seconds(),
    }
}

/// Wall-clock seconds since the first call.
fn wall_seconds() -> f64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}

/// Number of steps of `dt` in `t` seconds (rounded).
pub(crate) fn steps_in(t: f64, dt: f64) -> usize {
    (t / dt).round() as usize
}
