//! The drives' rows on a tree's coordinates, solved in the contacts' passes (the rows
//! themselves are described in `pipeline/drives.rs`).

use super::ArticulatedSystem;
use crate::dynamics::solver::{Softness, SolvePass};
use crate::dynamics::DynamicsError;
use crate::pipeline::drives::{Drive, DriveGroup, DriveKind, Motor, Trajectory};

fn apply(qd: &mut [f64], w: &[f64], lambda: f64) {
    for (v, x) in qd.iter_mut().zip(w) {
        *v += x * lambda;
    }
}

impl ArticulatedSystem {
    /// Starts a step of the drives: no impulse given yet.
    pub(crate) fn prepare_drives(&mut self) {
        for d in &mut self.drives {
            d.impulse = [0.0; 2];
            d.step_total = 0.0;
        }
    }

    /// The drives' responses `M⁻¹ e_k` at the current `q`, refreshed every substep: a
    /// prescribed coordinate's impulse is the whole driving force, and a response from an
    /// older configuration would feed the rest of the tree energy it does not have (a chain
    /// under a shaken anchor blew up within 1.5 s with once-a-step responses).
    pub(crate) fn refresh_drive_responses(&mut self) -> Result<(), DynamicsError> {
        let nv = self.qd.len();
        // The drives and one unit vector, taken out and put back: no allocation once warm.
        let mut drives = std::mem::take(&mut self.drives);
        let mut e = std::mem::take(&mut self.unit_impulse);
        e.clear();
        e.resize(nv, 0.0);
        let mut result = Ok(());
        for d in &mut drives {
            d.response.resize(nv, 0.0);
            e.iter_mut().for_each(|x| *x = 0.0);
            if d.dof < nv {
                e[d.dof] = 1.0;
            }
            result = self.apply_inverse_mass(&e, &mut d.response);
            if result.is_err() {
                break;
            }
        }
        self.drives = drives;
        self.unit_impulse = e;
        result
    }

    /// The velocity the motors give the tree within one substep `h` if nothing stops them,
    /// into `out`: `q̇ + Σ_k M⁻¹ e_k λ_k`, each `λ_k` the motor's implicit PD impulse over `h`
    /// limited to `τ_max h`, in one pass as the solve takes them. A servo reaches its target
    /// speed within a substep or two, so this, not the velocity at the start of the step, is
    /// how far a driven link moves over the step: what continuous collision sweeps (a rod
    /// that kicks from rest turns 0.03 rad in its first millisecond).
    pub(crate) fn motor_predicted_velocity(
        &mut self,
        h: f64,
        out: &mut Vec<f64>,
    ) -> Result<(), DynamicsError> {
        out.clear();
        out.extend_from_slice(&self.qd);
        let nv = self.qd.len();
        // The drives' own response buffers (refreshed again each substep) and one unit
        // vector: no allocation once warm.
        let mut e = std::mem::take(&mut self.unit_impulse);
        e.clear();
        e.resize(nv, 0.0);
        let result = self.predict_motors(h, out, &mut e);
        self.unit_impulse = e;
        result
    }

    fn predict_motors(
        &mut self,
        h: f64,
        out: &mut [f64],
        e: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let nv = self.qd.len();
        for i in 0..self.drives.len() {
            let (k, m) = match &self.drives[i].kind {
                DriveKind::Motor(m) if self.drives[i].dof < nv => (self.drives[i].dof, *m),
                _ => continue,
            };
            let Some(q) = self.q_of_dof(k) else {
                continue;
            };
            e.iter_mut().for_each(|x| *x = 0.0);
            e[k] = 1.0;
            let mut response = std::mem::take(&mut self.drives[i].response);
            response.resize(nv, 0.0);
            let r = self.apply_inverse_mass(e, &mut response);
            let a = response[k];
            self.drives[i].response = response;
            r?;
            if a <= 0.0 {
                continue;
            }
            let (kp, q_err) = match m.target_position {
                Some(qt) => (m.stiffness, qt - q),
                None => (0.0, 0.0),
            };
            let g = h * (h * kp + m.damping);
            let lambda =
                (h * kp * q_err + h * m.damping * m.target_velocity - g * out[k]) / (1.0 + a * g);
            let max = m.max_force * h;
            apply(out, &self.drives[i].response, lambda.clamp(-max, max));
        }
        Ok(())
    }

    /// Ends a substep of the drives: their impulses join the step's totals and start again
    /// from zero (a motor's limit holds per substep).
    pub(crate) fn end_substep_drives(&mut self) {
        for d in &mut self.drives {
            d.step_total += d.impulse[0] - d.impulse[1];
            d.impulse = [0.0; 2];
        }
    }

    /// Adds to the step's totals what the prescribed coordinates took in a step outside the
    /// solve (`impulses` in the order of the prescribed drives, N·s or N·m·s).
    pub(crate) fn add_prescribed_impulses(&mut self, impulses: &[f64]) {
        let prescribed = self
            .drives
            .iter_mut()
            .filter(|d| matches!(d.kind, DriveKind::Prescribed(_)));
        for (d, j) in prescribed.zip(impulses) {
            d.step_total += j;
        }
    }

    /// One Gauss–Seidel pass over the drives of `group`. `t_end` is the time at the end of
    /// the substep (s), `h` the substep (s); `soft` softens violated limits in the solve pass.
    pub(crate) fn solve_drives(
        &mut self,
        h: f64,
        t_end: f64,
        soft: &Softness,
        pass: SolvePass,
        group: DriveGroup,
    ) {
        let mut drives = std::mem::take(&mut self.drives);
        for d in &mut drives {
            if DriveGroup::of(&d.kind) != group {
                continue;
            }
            let k = d.dof;
            if k >= self.qd.len() {
                continue;
            }
            let a = d.response[k];
            if a <= 0.0 {
                continue;
            }
            let Some(q) = self.q_of_dof(k) else {
                continue;
            };
            let v = self.qd[k];
            match &d.kind {
                DriveKind::Motor(m) => {
                    let (kp, q_err) = match m.target_position {
                        Some(qt) => (m.stiffness, qt - q),
                        None => (0.0, 0.0),
                    };
                    let g = h * (h * kp + m.damping);
                    let dl =
                        (h * kp * q_err + h * m.damping * m.target_velocity - g * v - d.impulse[0])
                            / (1.0 + a * g);
                    let max = m.max_force * h;
                    let new = (d.impulse[0] + dl).clamp(-max, max);
                    apply(&mut self.qd, &d.response, new - d.impulse[0]);
                    d.impulse[0] = new;
                }
                DriveKind::Limits { lower, upper } => {
                    for (side, gap, sign) in [(0, q - lower, 1.0), (1, upper - q, -1.0)] {
                        // Velocity along the row (towards the free side) and its bias.
                        let vel = sign * self.qd[k];
                        let (bias, ms, is) = if gap > 0.0 {
                            (gap / h, 1.0, 0.0)
                        } else if pass.use_bias {
                            (soft.bias_rate * gap, soft.mass_scale, soft.impulse_scale)
                        } else {
                            (0.0, 1.0, 0.0)
                        };
                        let dl = -(vel + bias) * ms / a - is * d.impulse[side];
                        let new = (d.impulse[side] + dl).max(0.0);
                        apply(&mut self.qd, &d.response, sign * (new - d.impulse[side]));
                        d.impulse[side] = new;
                    }
                }
                DriveKind::Prescribed(traj) => {
                    // The solve pass lands the coordinate on the trajectory; the relax pass
                    // (after the positions moved) keeps the trajectory's velocity.
                    let target = if pass.use_bias {
                        (traj.at(t_end) - q) / h
                    } else {
                        (traj.at(t_end) - traj.at(t_end - h)) / h
                    };
                    let dl = (target - v) / a;
                    apply(&mut self.qd, &d.response, dl);
                    d.impulse[0] += dl;
                }
            }
        }
        self.drives = drives;
    }

    /// The motor of coordinate `dof`, to set its targets each step.
    pub fn motor_mut(&mut self, dof: usize) -> Option<&mut Motor> {
        self.drives.iter_mut().find_map(|d| match &mut d.kind {
            DriveKind::Motor(m) if d.dof == dof => Some(m),
            _ => None,
        })
    }

    /// The mean force or torque the drives on `dof` gave over the last step of `dt` seconds
    /// (N or N·m, signed along the coordinate).
    pub fn drive_force(&self, dof: usize, dt: f64) -> f64 {
        self.drives
            .iter()
            .filter(|d| d.dof == dof)
            .map(|d| d.step_total)
            .sum::<f64>()
            / dt
    }

    /// Adds a motor on velocity coordinate `dof`.
    pub fn with_motor(mut self, dof: usize, motor: Motor) -> Self {
        self.drives.push(Drive::new(dof, DriveKind::Motor(motor)));
        self
    }

    /// Adds travel limits `lower ≤ q ≤ upper` (rad or m) on coordinate `dof`.
    pub fn with_limits(mut self, dof: usize, lower: f64, upper: f64) -> Self {
        self.drives
            .push(Drive::new(dof, DriveKind::Limits { lower, upper }));
        self
    }

    /// Makes coordinate `dof` follow `trajectory` (a kinematic root or a driven joint).
    pub fn with_prescribed(mut self, dof: usize, trajectory: Trajectory) -> Self {
        self.drives
            .push(Drive::new(dof, DriveKind::Prescribed(trajectory)));
        self
    }

    /// Whether any coordinate is driven.
    pub(crate) fn has_drives(&self) -> bool {
        !self.drives.is_empty()
    }

    /// Whether every velocity coordinate has a motor or prescribed motion (a servo-driven
    /// foosball rod): the tree moves where its drives take it.
    pub(crate) fn fully_driven(&self) -> bool {
        (0..self.qd.len()).all(|dof| {
            self.drives.iter().any(|d| {
                d.dof == dof && matches!(d.kind, DriveKind::Motor(_) | DriveKind::Prescribed(_))
            })
        })
    }
}
