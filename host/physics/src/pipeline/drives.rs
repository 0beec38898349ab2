//! Driven degrees of freedom of articulated trees: motors, travel limits and prescribed
//! (kinematic) motion, as rows on single generalised coordinates solved in the same passes as
//! the contacts.
//!
//! Each row acts along `e_k` (one velocity coordinate `k`); the tree's response to an impulse
//! `λ` on it is `q̇ += M⁻¹ e_k λ` (one articulated-body pass per row and step), so the rest of
//! the tree reacts as the dynamics say, and `a = (M⁻¹)_kk` is the row's inverse effective mass.
//!
//! * **Motor** — an implicit PD servo `τ = k (q* − q) + c (v* − q̇)` limited to `|τ| ≤ τ_max`
//!   (N·m or N): over a substep `h` the impulse solves
//!   `λ = h k (q* − q) + h c v* − h (h k + c) q̇_new`, `q̇_new = q̇ + a λ`, then is clamped to
//!   `±τ_max h`. Unconditionally stable for any stiffness.
//! * **Limit** — `lower ≤ q ≤ upper`: unilateral rows, speculative (the joint may approach by
//!   the remaining gap per substep, so it stops at the limit without overshoot) and soft like
//!   contacts when violated.
//! * **Prescribed** — the coordinate follows a trajectory `q*(t)` (a kinematic root, a driven
//!   wheel): a rigid row that sets `q̇ = (q*(t + h) − q) / h` each substep, whatever force that
//!   takes; the reaction moves the rest of the tree (hybrid dynamics at the impulse level).
//!
//! All three apply to coordinates that move additively (revolute, prismatic, cylindrical,
//! universal joints).

/// A PD servo with a force limit on one coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    /// Target position (rad or m); `None` drives the velocity only.
    pub target_position: Option<f64>,
    /// Target velocity (rad/s or m/s).
    pub target_velocity: f64,
    /// Stiffness `k` (N·m/rad or N/m), used with a target position.
    pub stiffness: f64,
    /// Damping `c` (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Largest force or torque the motor gives (N or N·m).
    pub max_force: f64,
}

/// A trajectory `q*(t)` of one coordinate (rad or m, `t` in s).
#[derive(Clone, Debug, PartialEq)]
pub enum Trajectory {
    /// `q* = q0 + v t`.
    ConstantVelocity {
        /// Start (rad or m).
        start: f64,
        /// Velocity (rad/s or m/s).
        velocity: f64,
    },
    /// Piecewise linear through `(t, q)` keyframes (sorted by time), held constant outside.
    Keyframes(Vec<(f64, f64)>),
    /// `q* = offset + amplitude · sin(2π frequency t + phase)`.
    Sinusoid {
        /// Centre (rad or m).
        offset: f64,
        /// Amplitude (rad or m).
        amplitude: f64,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad).
        phase: f64,
    },
}

impl Trajectory {
    /// `q*(t)`.
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Trajectory::ConstantVelocity { start, velocity } => start + velocity * t,
            Trajectory::Keyframes(k) => match k.iter().position(|&(tk, _)| tk > t) {
                None => k.last().map_or(0.0, |&(_, q)| q),
                Some(0) => k[0].1,
                Some(i) => {
                    let ((t0, q0), (t1, q1)) = (k[i - 1], k[i]);
                    q0 + (q1 - q0) * (t - t0) / (t1 - t0)
                }
            },
            Trajectory::Sinusoid {
                offset,
                amplitude,
                frequency,
                phase,
            } => {
                offset
                    + amplitude
                        * crate::transcendental::sin(
                            2.0 * std::f64::consts::PI * frequency * t + phase,
                        )
            }
        }
    }
}

/// What drives one coordinate.
#[derive(Clone, Debug, PartialEq)]
pub enum DriveKind {
    /// A servo.
    Motor(Motor),
    /// Travel limits (rad or m).
    Limits {
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// Prescribed motion.
    Prescribed(Trajectory),
}

/// Which rows of the drives a call solves: a pass solves the motors before the contacts
/// and the hard rows after them.
///
/// A motor is force-limited and must yield to what it pushes against: solved before the
/// contacts, a servo at its limit pressing a link onto a body ends each pass with the
/// contact's answer (no approach, friction within its cone), so a pinned body stays put.
/// Solved after them, its push ended every pass as a velocity into the body, which the
/// position update turned into overlap and the soft push-out into creep along the tilted
/// normal (a ball under a foot pressed at 15 N·m crept out at 0.08 m/s and squirted free
/// within 0.1 s). Limits and prescribed motion are hard: they end each pass on their
/// bounds and trajectories.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DriveGroup {
    /// Force-limited servos.
    Motors,
    /// Travel limits and prescribed motion.
    Hard,
}

impl DriveGroup {
    pub(crate) fn of(kind: &DriveKind) -> Self {
        match kind {
            DriveKind::Motor(_) => DriveGroup::Motors,
            DriveKind::Limits { .. } | DriveKind::Prescribed(_) => DriveGroup::Hard,
        }
    }
}

/// A drive on velocity coordinate `dof` of a tree, with its row state.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Drive {
    pub(crate) dof: usize,
    pub(crate) kind: DriveKind,
    /// `M⁻¹ e_dof` at the start of the step.
    pub(crate) response: Vec<f64>,
    /// Accumulated impulses of the substep (two for limits: lower, upper).
    pub(crate) impulse: [f64; 2],
    /// Impulses of the step's finished substeps (N·s or N·m·s), signed along the coordinate.
    pub(crate) step_total: f64,
}

impl Drive {
    pub(crate) fn new(dof: usize, kind: DriveKind) -> Self {
        Self {
            dof,
            kind,
            response: Vec::new(),
            impulse: [0.0; 2],
            step_total: 0.0,
        }
    }
}
