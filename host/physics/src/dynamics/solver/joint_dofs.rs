//! The driven degrees of freedom of a joint between free bodies: a motor, limits and an
//! armature on one coordinate (an angle about, or a slide along, a joint axis), solved as
//! rows along that coordinate in the same passes as the joint's constraint rows.
//!
//! A row acts along the coordinate's Jacobian `J` (`q̇ = J V`, `V` the two bodies' twists);
//! `a = J M⁻¹ Jᵀ` is its inverse effective mass, and an armature `I` makes it
//! `a' = 1 / (1/a + I)`.
//!
//! * **Motor** — the tree drives' implicit PD servo `τ = k (q* − q) + c (v* − q̇)`, limited to
//!   `|τ| ≤ τ_max`: over a substep `h` the impulse solves
//!   `λ = h k (q* − q) + h c v* − h (h k + c) q̇_new`, `q̇_new = q̇ + a' λ`, clamped to
//!   `±τ_max h`. Stable for any stiffness.
//! * **Limits** — `lower ≤ q ≤ upper`: unilateral rows, speculative while apart (the joint may
//!   close the remaining gap in a substep, so it stops at the limit), soft with the solver's
//!   joint softness when violated; with restitution `e` a coordinate reaching a limit faster
//!   than [`LIMIT_BOUNCE_SPEED`] leaves it at `e` times its approach speed.
//! * **Armature** — a rotor of inertia `I` (kg·m² on an angle, kg on a slide) on the
//!   coordinate: the row keeps `q̇` at its start-of-substep value with compliance `1/I`,
//!   `λ = −(q̇ − q̇₀ + λ_acc / I) / (a + 1/I)`, so that a force changes `q̇` as if the row's
//!   effective mass were `1/a + I`. Its reaction acts on both bodies (momentum is kept).
//!
//! The motor's, the limits' and the armature's impulses start from zero each substep (the
//! motor's force limit holds per substep, as the tree drives').

/// Approach speed (rad/s or m/s) below which a limit with restitution does not bounce (a
/// coordinate resting on its limit stays there).
pub(crate) const LIMIT_BOUNCE_SPEED: f64 = 0.05;

/// A PD servo with a force limit on one coordinate of a joint between free bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DofMotor {
    /// Target position (rad or m); `None` drives the velocity only.
    pub(crate) target_position: Option<f64>,
    /// Target velocity (rad/s or m/s).
    pub(crate) target_velocity: f64,
    /// Stiffness `k` (N·m/rad or N/m), used with a target position.
    pub(crate) stiffness: f64,
    /// Damping `c` (N·m·s/rad or N·s/m).
    pub(crate) damping: f64,
    /// Largest torque or force the motor gives (N·m or N).
    pub(crate) max_force: f64,
}

/// Travel limits of one coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DofLimits {
    /// Lower limit (rad or m).
    pub(crate) lower: f64,
    /// Upper limit (rad or m).
    pub(crate) upper: f64,
    /// Restitution at the limits (0 … 1; 0: the coordinate stops).
    pub(crate) restitution: f64,
}

/// What drives one coordinate of a joint between free bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct DofDrive {
    /// A motor, if any.
    pub(crate) motor: Option<DofMotor>,
    /// Limits, if any.
    pub(crate) limits: Option<DofLimits>,
    /// Armature (kg·m² on an angle, kg on a slide); 0: none.
    pub(crate) armature: f64,
}

impl DofDrive {
    /// Whether anything acts on the coordinate.
    pub(crate) fn is_active(&self) -> bool {
        self.motor.is_some() || self.limits.is_some() || self.armature > 0.0
    }
}

/// A coordinate's state in the solver.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct DofState {
    /// What drives it.
    pub(crate) drive: DofDrive,
    /// The coordinate (rad or m), continuous across turns.
    pub(crate) q: f64,
    /// Its rate at the start of the current substep (rad/s or m/s).
    pub(crate) rate_start: f64,
    /// Its rate at the end of the last pass.
    pub(crate) rate_end: f64,
    /// The motor's impulse in the current substep (N·m·s or N·s).
    pub(crate) motor_impulse: f64,
    /// The motor's impulse in the last finished substep.
    pub(crate) motor_last: f64,
    /// The limits' impulses in the current substep: lower, upper (≥ 0).
    pub(crate) limit_impulse: [f64; 2],
    /// The armature's impulse in the current substep.
    pub(crate) armature_impulse: f64,
}

/// The softness a violated limit uses in this pass: `(bias rate 1/s, mass scale, impulse
/// scale)`.
pub(crate) type LimitSoftness = (f64, f64, f64);

impl DofState {
    /// Starts a substep: the rows' impulses start from zero.
    pub(crate) fn begin_substep(&mut self) {
        self.rate_start = self.rate_end;
        self.motor_last = self.motor_impulse;
        self.motor_impulse = 0.0;
        self.limit_impulse = [0.0; 2];
        self.armature_impulse = 0.0;
    }

    /// One pass over the coordinate's rows. `rate` is the coordinate's current rate, `a` the
    /// row's inverse effective mass without armature, `h` the substep (s), `soft` the limits'
    /// softness when violated (`None` in the relax pass). Every impulse is handed to `apply`
    /// (along the coordinate), which returns the new rate.
    pub(crate) fn solve(
        &mut self,
        mut rate: f64,
        a: f64,
        h: f64,
        soft: Option<LimitSoftness>,
        mut apply: impl FnMut(f64) -> f64,
    ) {
        if !(a > 0.0 && a.is_finite() && h > 0.0) {
            return;
        }
        let d = self.drive;
        let arm = d.armature;
        // Inverse effective mass with the armature.
        let a_eff = if arm > 0.0 { 1.0 / (1.0 / a + arm) } else { a };
        if arm > 0.0 {
            let dl = -(rate - self.rate_start + self.armature_impulse / arm) / (a + 1.0 / arm);
            self.armature_impulse += dl;
            rate = apply(dl);
        }
        if let Some(m) = d.motor {
            let (kp, q_err) = match m.target_position {
                Some(qt) => (m.stiffness, qt - self.q),
                None => (0.0, 0.0),
            };
            let g = h * (h * kp + m.damping);
            let dl = (h * kp * q_err + h * m.damping * m.target_velocity
                - g * rate
                - self.motor_impulse)
                / (1.0 + a_eff * g);
            let max = m.max_force.max(0.0) * h;
            let new = (self.motor_impulse + dl).clamp(-max, max);
            rate = apply(new - self.motor_impulse);
            self.motor_impulse = new;
        }
        if let Some(l) = d.limits {
            for (side, gap, sign) in [(0, self.q - l.lower, 1.0), (1, l.upper - self.q, -1.0)] {
                let vel = sign * rate;
                let approach = -sign * self.rate_start;
                let bounce =
                    l.restitution > 0.0 && approach > LIMIT_BOUNCE_SPEED && gap <= h * approach;
                let (bias, ms, is) = if bounce {
                    (-l.restitution * approach, 1.0, 0.0)
                } else if gap > 0.0 {
                    (gap / h, 1.0, 0.0)
                } else if let Some((rate_k, ms, is)) = soft {
                    (rate_k * gap, ms, is)
                } else {
                    (0.0, 1.0, 0.0)
                };
                let imp = self.limit_impulse[side];
                let dl = -(vel + bias) * ms / a_eff - is * imp;
                let new = (imp + dl).max(0.0);
                rate = apply(sign * (new - imp));
                self.limit_impulse[side] = new;
            }
        }
        self.rate_end = rate;
    }
}
