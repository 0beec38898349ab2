//! Articulated trees stepped with part 1's ABA, `q̈ = FD(q, q̇, τ)`, by the world's integrator.
//!
//! Configurations move on each joint's configuration space through a chart at the step's
//! start: `q = q₀ ⊞ θ` with `θ` of the velocity's size — additive for revolute, prismatic,
//! cylindrical and universal joints; `R = R₀ exp(θ)` for ball joints (`q̇` = body angular
//! velocity, so `θ̇ = J_r⁻¹(θ) ω`); rotation as a ball joint and `p = p₀ + θ_p` with
//! `θ̇_p = R v` for free joints (the group `SO(3) × ℝ³`, the centre moving in the parent frame).
//!
//! | kind | tree step |
//! |---|---|
//! | `explicit-euler` | `q ← q ⊞ h q̇`, then `q̇ += h q̈(q₀, q̇₀)` |
//! | `symplectic-euler` (default), `implicit-gyroscopic` | linearly implicit Euler: `(M + h D + h² K) Δq̇ = h (τ − bias)` at `q ⊞ h q̇`, `q̇ += Δq̇`, then `q ← q ⊞ h q̇` — `D`, `K` the velocity and position Jacobians of the bias forces (Coriolis, centrifugal, gyroscopic, gravity), O(n) by an articulated-body recursion (`pipeline/articulated/implicit_step.rs`) |
//! | `rkmk4` | RK4 on `(θ, q̇)` in the chart (Munthe-Kaas), 4 ABA calls |
//! | `energy-momentum` | implicit midpoint `q̇₁ = q̇₀ + h q̈(q₀ ⊞ (h/2) q̇_m, q̇_m)`, `q ← q₀ ⊞ h q̇_m`, fixed-point iterations (symmetric, second order; exact energy is a free-body property) |

mod drive_rows;
mod implicit_step;
mod tree_energy;

use super::drives::{Drive, DriveKind};
use super::integrator::dexp_inv_right;
use super::inverse_mass::InverseMassCache;
use super::IntegratorKind;
use crate::algebra::{exp_so3, log_so3, se3, Vec3, SE3};
use crate::dynamics::{aba, DynamicsError, Workspace};
use crate::geometry::{Material, Shape, M3, V3};
use crate::model::ArticulatedTree;
use implicit_step::{implicit_velocity_update, ImplicitWorkspace};
use tree_energy::EnergyScratch;

/// Fixed-point iterations of the tree's implicit midpoint step: stop when `|Δq̇|∞` is below
/// this (rad/s or m/s) …
const MIDPOINT_TOLERANCE: f64 = 1e-13;
/// … or after this many ABA calls.
const MIDPOINT_MAX_ITERATIONS: usize = 20;

/// How a joint's coordinates move (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Chart {
    /// `q = q₀ + θ`, `nq = nv`.
    Additive(usize),
    /// Ball joint: exponential coordinates.
    Ball,
    /// Free joint: `(r, p)`.
    Free,
    /// No coordinates.
    Fixed,
}

/// A collision shape fixed on a link of a tree.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LinkShape {
    /// The link (body index in the tree).
    pub(crate) link: usize,
    /// The shape, centred on its own frame.
    pub(crate) shape: Shape,
    /// Pose of the shape in the link frame.
    pub(crate) pose: SE3<f64>,
    /// Surface properties.
    pub(crate) material: Material,
}

/// One articulated tree with its state.
#[derive(Clone)]
pub struct ArticulatedSystem {
    /// The model.
    pub(crate) tree: ArticulatedTree<f64>,
    ws: Workspace<f64>,
    /// `M(q)⁻¹` of a small tree, for the rows' responses.
    inverse_mass: InverseMassCache,
    /// Factors of the linearly implicit velocity update.
    iws: ImplicitWorkspace,
    /// Scratch of the linearly implicit step's energy balance.
    energy_scratch: EnergyScratch,
    /// Configuration.
    pub(crate) q: Vec<f64>,
    /// Velocity.
    pub(crate) qd: Vec<f64>,
    /// Joint forces (held constant).
    pub(crate) tau: Vec<f64>,
    /// The integrator (set by the world; see the module docs).
    pub(crate) integrator: IntegratorKind,
    /// Collision shapes fixed on links (link frame): such a tree touches the world's bodies.
    pub(crate) link_shapes: Vec<LinkShape>,
    /// Motors, limits and prescribed coordinates.
    pub(crate) drives: Vec<Drive>,
    qdd: Vec<f64>,
    joints: Vec<(Chart, usize, usize)>,
    /// Per velocity coordinate, its configuration coordinate when the joint moves additively.
    additive_q: Vec<Option<usize>>,
    /// Prescribed coordinate changes of the current implicit step, `(coordinate, Δq̇)`.
    given: Vec<(usize, f64)>,
    /// The impulses those changes took (N·s or N·m·s).
    given_impulses: Vec<f64>,
    // Scratch of the multi-stage integrators (no allocation per step).
    q0: Vec<f64>,
    qd0: Vec<f64>,
    stage_qd: Vec<f64>,
    /// Scratch: a unit generalised impulse (the motors' prediction).
    pub(crate) unit_impulse: Vec<f64>,
    theta: Vec<f64>,
    k_theta: [Vec<f64>; 4],
    k_qd: [Vec<f64>; 4],
}

fn v3(s: &[f64], o: usize) -> Vec3<f64> {
    Vec3::new(s[o], s[o + 1], s[o + 2])
}

impl ArticulatedSystem {
    /// A system at `q`, `qd` (lengths checked by the scene loader).
    pub fn new(tree: ArticulatedTree<f64>, q: Vec<f64>, qd: Vec<f64>) -> Self {
        let ws = Workspace::new(&tree);
        let iws = ImplicitWorkspace::new(&tree);
        let energy_scratch = EnergyScratch::new(&tree);
        let nv = tree.nv();
        let nq = tree.nq();
        let joints: Vec<(Chart, usize, usize)> = tree
            .bodies()
            .iter()
            .map(|b| {
                let chart = match b.joint.describe().kind.as_str() {
                    "ball" => Chart::Ball,
                    "free" => Chart::Free,
                    "fixed" => Chart::Fixed,
                    _ => Chart::Additive(b.nq()),
                };
                (chart, b.q_offset, b.v_offset)
            })
            .collect();
        let mut additive_q = vec![None; nv];
        for &(chart, qo, vo) in &joints {
            if let Chart::Additive(n) = chart {
                for k in 0..n {
                    additive_q[vo + k] = Some(qo + k);
                }
            }
        }
        let z = || vec![0.0; nv];
        Self {
            tree,
            ws,
            inverse_mass: InverseMassCache::default(),
            iws,
            energy_scratch,
            q,
            qd,
            tau: vec![0.0; nv],
            integrator: IntegratorKind::default(),
            link_shapes: Vec::new(),
            drives: Vec::new(),
            qdd: vec![0.0; nv],
            joints,
            additive_q,
            given: Vec::new(),
            given_impulses: Vec::new(),
            q0: vec![0.0; nq],
            qd0: z(),
            stage_qd: z(),
            unit_impulse: z(),
            theta: z(),
            k_theta: [z(), z(), z(), z()],
            k_qd: [z(), z(), z(), z()],
        }
    }

    /// One step of `h` seconds with the selected integrator.
    pub fn step(&mut self, h: f64) -> Result<(), DynamicsError> {
        match self.integrator {
            IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic => {
                self.step_symplectic(h)
            }
            IntegratorKind::ExplicitEuler => self.step_explicit(h),
            IntegratorKind::Rkmk4 => self.step_rkmk4(h),
            IntegratorKind::EnergyMomentum => self.step_midpoint(h),
        }
    }

    fn forward_dynamics(&mut self, q: &[f64], qd: &[f64]) -> Result<(), DynamicsError> {
        aba(
            &self.tree,
            &mut self.ws,
            q,
            qd,
            &self.tau,
            None,
            &mut self.qdd,
        )
    }

    fn step_symplectic(&mut self, h: f64) -> Result<(), DynamicsError> {
        self.implicit_velocity(h)?;
        self.advance_positions(h);
        Ok(())
    }

    /// Whether the tree steps on its own although it has drives: every drive is prescribed
    /// motion of an additive coordinate and the integrator is the linearly implicit step,
    /// which takes the trajectories as given coordinate changes (hybrid dynamics in the
    /// implicit operator). Motors and limits are solved with the contacts instead.
    pub(crate) fn steps_prescribed_alone(&self) -> bool {
        matches!(
            self.integrator,
            IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic
        ) && self
            .drives
            .iter()
            .all(|d| matches!(d.kind, DriveKind::Prescribed(_)) && self.q_of_dof(d.dof).is_some())
    }

    /// One step of `h` seconds ending at world time `t_end` (s): [`step`](Self::step), with
    /// the prescribed coordinates landing on their trajectories at `t_end` (for trees that
    /// [step prescribed alone](Self::steps_prescribed_alone)).
    pub(crate) fn step_until(&mut self, h: f64, t_end: f64) -> Result<(), DynamicsError> {
        if self.drives.is_empty() {
            return self.step(h);
        }
        // A tree under prescribed motion holds the energy balance of its linearly implicit
        // step (`pipeline/articulated/tree_energy.rs`); a tree with no drive is left to the step alone.
        let e0 = matches!(
            self.integrator,
            IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic
        )
        .then(|| self.energy_now());
        let mut given = std::mem::take(&mut self.given);
        given.clear();
        for d in &self.drives {
            if let (DriveKind::Prescribed(traj), Some(q)) = (&d.kind, self.q_of_dof(d.dof)) {
                given.push((d.dof, (traj.at(t_end) - q) / h - self.qd[d.dof]));
            }
        }
        self.given = given;
        self.given_impulses.clear();
        let r = self.implicit_velocity(h);
        self.given.clear();
        r?;
        let impulses = std::mem::take(&mut self.given_impulses);
        self.add_prescribed_impulses(&impulses);
        self.given_impulses = impulses;
        self.advance_positions(h);
        if let Some(e0) = e0 {
            self.hold_energy_balance(e0, h);
        }
        Ok(())
    }

    /// The linearly implicit velocity update (`pipeline/articulated/implicit_step.rs`), linearised at
    /// the predicted configuration `q ⊞ h q̇` (where `q ⊞ h q̇_new` lands to first order):
    /// `(M + h D + h² K) Δq̇ = h (τ − bias)`, `q̇ += Δq̇`; `q` is left where it was. The
    /// coordinates in `self.given` change by the given amounts; what that took is left in
    /// `self.given_impulses`.
    fn implicit_velocity(&mut self, h: f64) -> Result<(), DynamicsError> {
        self.q0.copy_from_slice(&self.q);
        for (t, v) in self.theta.iter_mut().zip(&self.qd) {
            *t = h * v;
        }
        self.chart_point_from_start();
        let mut dqd = std::mem::take(&mut self.qdd);
        self.given_impulses.resize(self.given.len(), 0.0);
        let r = implicit_velocity_update(
            &self.tree,
            &mut self.iws,
            &self.q,
            &self.qd,
            &self.tau,
            h,
            &self.given,
            &mut self.given_impulses,
            &mut dqd,
        );
        self.q.copy_from_slice(&self.q0);
        if r.is_ok() {
            for (v, x) in self.qd.iter_mut().zip(&dqd) {
                *v += x;
            }
        }
        self.qdd = dqd;
        r.map(|_| ())
    }

    fn step_explicit(&mut self, h: f64) -> Result<(), DynamicsError> {
        let (q, qd) = (std::mem::take(&mut self.q), std::mem::take(&mut self.qd));
        let r = self.forward_dynamics(&q, &qd);
        (self.q, self.qd) = (q, qd);
        r?;
        self.advance_positions(h);
        for (v, a) in self.qd.iter_mut().zip(&self.qdd) {
            *v += h * a;
        }
        Ok(())
    }

    /// `q` from `q̇` over `h` on each joint's space: additive, `R ← R·exp(h ω)` (ball),
    /// `T ← T·Exp(h V)` (free).
    fn advance_positions(&mut self, h: f64) {
        for &(chart, qo, vo) in &self.joints {
            match chart {
                Chart::Ball => {
                    let r = exp_so3(&v3(&self.q, qo)) * exp_so3(&(v3(&self.qd, vo) * h));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&r).as_slice());
                }
                Chart::Free => {
                    let t = SE3::new(exp_so3(&v3(&self.q, qo)), v3(&self.q, qo + 3))
                        * SE3::exp(&se3::new(v3(&self.qd, vo) * h, v3(&self.qd, vo + 3) * h));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&t.r).as_slice());
                    self.q[qo + 3..qo + 6].copy_from_slice(t.p.as_slice());
                }
                Chart::Fixed => {}
                Chart::Additive(n) => {
                    for k in 0..n {
                        self.q[qo + k] += h * self.qd[vo + k];
                    }
                }
            }
        }
    }

    /// RKMK4: classical RK4 on `(θ, q̇)` with `θ̇ = chart_rate(θ, q̇)`.
    fn step_rkmk4(&mut self, h: f64) -> Result<(), DynamicsError> {
        self.q0.copy_from_slice(&self.q);
        self.qd0.copy_from_slice(&self.qd);
        let nv = self.qd.len();
        let c = [0.0, 0.5 * h, 0.5 * h, h];
        for (s, &cs) in c.iter().enumerate() {
            // Stage state: θ = c_s k_θ(s−1), q̇ = q̇₀ + c_s k_q̇(s−1).
            for k in 0..nv {
                let (kt, kq) = if s == 0 {
                    (0.0, 0.0)
                } else {
                    (self.k_theta[s - 1][k], self.k_qd[s - 1][k])
                };
                self.theta[k] = cs * kt;
                self.stage_qd[k] = self.qd0[k] + cs * kq;
            }
            self.chart_point_from_start();
            let (q, sqd) = (
                std::mem::take(&mut self.q),
                std::mem::take(&mut self.stage_qd),
            );
            let r = self.forward_dynamics(&q, &sqd);
            let mut kt = std::mem::take(&mut self.k_theta[s]);
            self.chart_rate(&sqd, &mut kt);
            self.k_theta[s] = kt;
            (self.q, self.stage_qd) = (q, sqd);
            r?;
            self.k_qd[s].copy_from_slice(&self.qdd);
        }
        for k in 0..nv {
            let comb = |a: &[Vec<f64>; 4]| a[0][k] + 2.0 * (a[1][k] + a[2][k]) + a[3][k];
            self.theta[k] = h / 6.0 * comb(&self.k_theta);
            self.qd[k] = self.qd0[k] + h / 6.0 * comb(&self.k_qd);
        }
        self.chart_point_from_start();
        Ok(())
    }

    /// Implicit midpoint by fixed-point iteration on `q̇_m`.
    fn step_midpoint(&mut self, h: f64) -> Result<(), DynamicsError> {
        self.q0.copy_from_slice(&self.q);
        self.qd0.copy_from_slice(&self.qd);
        // Predictor: q̇_m = q̇₀ + (h/2) q̈(q₀, q̇₀).
        let (q, qd) = (std::mem::take(&mut self.q), std::mem::take(&mut self.qd));
        let r = self.forward_dynamics(&q, &qd);
        (self.q, self.qd) = (q, qd);
        r?;
        for k in 0..self.qd.len() {
            self.stage_qd[k] = self.qd0[k] + 0.5 * h * self.qdd[k];
        }
        for _ in 0..MIDPOINT_MAX_ITERATIONS {
            let mut rate = std::mem::take(&mut self.theta);
            let sqd = std::mem::take(&mut self.stage_qd);
            self.chart_rate_at_start(&sqd, 0.25 * h, &mut rate);
            for t in rate.iter_mut() {
                *t *= 0.5 * h;
            }
            self.theta = rate;
            self.chart_point_from_start();
            let q = std::mem::take(&mut self.q);
            let r = self.forward_dynamics(&q, &sqd);
            self.q = q;
            self.stage_qd = sqd;
            r?;
            let mut change: f64 = 0.0;
            for k in 0..self.qd.len() {
                let new = self.qd0[k] + 0.5 * h * self.qdd[k];
                change = change.max((new - self.stage_qd[k]).abs());
                self.stage_qd[k] = new;
            }
            if change <= MIDPOINT_TOLERANCE {
                break;
            }
        }
        let sqd = std::mem::take(&mut self.stage_qd);
        let mut rate = std::mem::take(&mut self.theta);
        self.chart_rate_at_start(&sqd, 0.5 * h, &mut rate);
        for t in rate.iter_mut() {
            *t *= h;
        }
        self.theta = rate;
        for ((v, m), v0) in self.qd.iter_mut().zip(&sqd).zip(&self.qd0) {
            *v = 2.0 * m - v0;
        }
        self.stage_qd = sqd;
        self.chart_point_from_start();
        Ok(())
    }

    /// `q ← q₀ ⊞ θ`.
    fn chart_point_from_start(&mut self) {
        for &(chart, qo, vo) in &self.joints {
            match chart {
                Chart::Additive(n) => {
                    for k in 0..n {
                        self.q[qo + k] = self.q0[qo + k] + self.theta[vo + k];
                    }
                }
                Chart::Ball => {
                    let r = exp_so3(&v3(&self.q0, qo)) * exp_so3(&v3(&self.theta, vo));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&r).as_slice());
                }
                Chart::Free => {
                    let r = exp_so3(&v3(&self.q0, qo)) * exp_so3(&v3(&self.theta, vo));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&r).as_slice());
                    for k in 0..3 {
                        self.q[qo + 3 + k] = self.q0[qo + 3 + k] + self.theta[vo + 3 + k];
                    }
                }
                Chart::Fixed => {}
            }
        }
    }

    /// `θ̇` at the current chart point `θ` for velocity `qd` (see the module docs).
    fn chart_rate(&self, qd: &[f64], out: &mut [f64]) {
        for &(chart, qo, vo) in &self.joints {
            match chart {
                Chart::Additive(n) => out[vo..vo + n].copy_from_slice(&qd[vo..vo + n]),
                Chart::Ball | Chart::Free => {
                    let t = v3(&self.theta, vo);
                    let w = dexp_inv_right(&t, &v3(qd, vo));
                    out[vo..vo + 3].copy_from_slice(w.as_slice());
                    if chart == Chart::Free {
                        // ṗ = R v with R = R₀ exp(θ) = the stage rotation, already in q.
                        let r = exp_so3(&v3(&self.q, qo));
                        let pd = r * v3(qd, vo + 3);
                        out[vo + 3..vo + 6].copy_from_slice(pd.as_slice());
                    }
                }
                Chart::Fixed => {}
            }
        }
    }

    /// The chart increment per second for a constant velocity `qd` over a step from the
    /// start: `qd` itself, except the free joint's translation `R₀ exp(t_mid ω) v` (the centre
    /// velocity at the rotation reached after `t_mid` seconds: the midpoint of the step).
    fn chart_rate_at_start(&self, qd: &[f64], t_mid: f64, out: &mut [f64]) {
        for &(chart, qo, vo) in &self.joints {
            match chart {
                Chart::Additive(n) => out[vo..vo + n].copy_from_slice(&qd[vo..vo + n]),
                Chart::Ball => out[vo..vo + 3].copy_from_slice(&qd[vo..vo + 3]),
                Chart::Free => {
                    out[vo..vo + 3].copy_from_slice(&qd[vo..vo + 3]);
                    let r = exp_so3(&v3(&self.q0, qo)) * exp_so3(&(v3(qd, vo) * t_mid));
                    let pd = r * v3(qd, vo + 3);
                    out[vo + 3..vo + 6].copy_from_slice(pd.as_slice());
                }
                Chart::Fixed => {}
            }
        }
    }
}

/// Reading and setting the state.
impl ArticulatedSystem {
    /// The model (bodies, joints, inertias).
    pub(crate) fn model(&self) -> &ArticulatedTree<f64> {
        &self.tree
    }

    /// Generalised coordinates `q` (the model's joint order; `nq` values: rad for revolute,
    /// m for prismatic, a rotation vector (rad) for a ball joint's orientation).
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// Mutable generalised coordinates (the length is fixed by the model).
    pub fn q_mut(&mut self) -> &mut [f64] {
        &mut self.q
    }

    /// Generalised velocities `q̇` (`nv` values, rad/s or m/s; ball and free joints in their
    /// body frame).
    pub fn qd(&self) -> &[f64] {
        &self.qd
    }

    /// Mutable generalised velocities.
    pub fn qd_mut(&mut self) -> &mut [f64] {
        &mut self.qd
    }

    /// Joint forces `τ` (N or N·m per degree of freedom), held constant over steps.
    pub fn tau(&self) -> &[f64] {
        &self.tau
    }

    /// Mutable joint forces; set them each step from Rust to drive the tree by force.
    pub fn tau_mut(&mut self) -> &mut [f64] {
        &mut self.tau
    }

    /// The integrator this tree steps with.
    pub fn integrator(&self) -> IntegratorKind {
        self.integrator
    }

    /// Selects the integrator (the world sets its own on trees it is given).
    pub fn set_integrator(&mut self, kind: IntegratorKind) {
        self.integrator = kind;
    }
}

/// Contact support: shapes on links, link poses and velocities, point Jacobians and the
/// response `M⁻¹ Jᵀ` of the tree to a unit impulse.
impl ArticulatedSystem {
    /// Fixes a collision shape on link `link` at `pose` (link frame), with `material`. Several
    /// shapes on one link make it a compound. A tree with shapes touches the world's bodies
    /// (with the `contacts` effect) and then steps by semi-implicit Euler inside the contact
    /// solve, whatever integrator the world selects.
    pub fn with_link_shape(
        mut self,
        link: usize,
        shape: Shape,
        pose: SE3<f64>,
        material: Material,
    ) -> Self {
        self.link_shapes.push(LinkShape {
            link,
            shape,
            pose,
            material,
        });
        self
    }

    /// Whether any link carries a collision shape.
    pub(crate) fn has_shapes(&self) -> bool {
        !self.link_shapes.is_empty()
    }

    /// World pose of every link at the current `q`.
    pub fn link_poses(&self) -> Vec<SE3<f64>> {
        self.tree.body_poses(&self.q)
    }

    /// World angular velocity and world velocity of each link frame's origin (rad/s, m/s) at
    /// the current `q`, `q̇`, for the given link `poses`.
    pub(crate) fn link_velocities(&self, poses: &[SE3<f64>]) -> Vec<(V3, V3)> {
        let mut out: Vec<(V3, V3)> = Vec::with_capacity(poses.len());
        self.link_velocities_into(poses, &self.qd, &mut out);
        out
    }

    /// [`link_velocities`](Self::link_velocities) for the generalised velocity `qd` instead of
    /// the tree's own, written into `out` (cleared first; no allocation once it holds a
    /// velocity per link).
    pub(crate) fn link_velocities_into(
        &self,
        poses: &[SE3<f64>],
        qd: &[f64],
        out: &mut Vec<(V3, V3)>,
    ) {
        out.clear();
        let mut s = [se3::zeros(); 6];
        for (k, b) in self.tree.bodies().iter().enumerate() {
            let (mut w, mut v) = match b.parent {
                Some(p) => {
                    let (wp, vp) = out[p];
                    (wp, vp + wp.cross(&(poses[k].p - poses[p].p)))
                }
                None => (V3::zeros(), V3::zeros()),
            };
            let qs = &self.q[b.q_offset..b.q_offset + b.nq()];
            b.joint.motion_subspace(qs, &mut s[..b.nv()]);
            let r = &poses[k].r;
            for (c, col) in s[..b.nv()].iter().enumerate() {
                let qd = qd[b.v_offset + c];
                w += r * col.w * qd;
                v += r * col.v * qd;
            }
            out.push((w, v));
        }
    }

    /// The world velocity of the point of link `link` at world point `p` per velocity
    /// coordinate, for link `poses` at the current `q`: `out[c]` (m/s per unit of `q̇_c`),
    /// zero for coordinates that do not move the link. The row along a direction `d` is
    /// `J_c = d · out[c]` (`J q̇` = the point's velocity along `d`).
    pub(crate) fn point_velocity_jacobian(
        &self,
        poses: &[SE3<f64>],
        link: usize,
        p: &V3,
        out: &mut Vec<V3>,
    ) {
        out.clear();
        out.resize(self.qd.len(), V3::zeros());
        let mut s = [se3::zeros(); 6];
        let bodies = self.tree.bodies();
        let mut k = Some(link);
        while let Some(a) = k {
            let b = &bodies[a];
            let qs = &self.q[b.q_offset..b.q_offset + b.nq()];
            b.joint.motion_subspace(qs, &mut s[..b.nv()]);
            let (r, t): (&M3, &V3) = (&poses[a].r, &poses[a].p);
            let arm = p - t;
            for (c, col) in s[..b.nv()].iter().enumerate() {
                out[b.v_offset + c] = r * col.v + (r * col.w).cross(&arm);
            }
            k = b.parent;
        }
    }

    /// `out = M(q)⁻¹ tau`: the change of `q̇` for a generalised impulse `tau`. A small tree
    /// multiplies by its dense inverse, formed once per configuration
    /// (`pipeline/inverse_mass.rs`); a larger one runs ABA at zero velocity and zero gravity,
    /// O(n).
    pub(crate) fn apply_inverse_mass(
        &mut self,
        tau: &[f64],
        out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        if InverseMassCache::applies(self.qd.len()) {
            return self
                .inverse_mass
                .apply(&self.tree, &mut self.ws, &self.q, tau, out);
        }
        let g = self.tree.gravity();
        self.tree.set_gravity(Vec3::zeros());
        let zero = std::mem::take(&mut self.stage_qd);
        let mut zero = zero;
        zero.iter_mut().for_each(|x| *x = 0.0);
        let r = aba(&self.tree, &mut self.ws, &self.q, &zero, tau, None, out);
        self.stage_qd = zero;
        self.tree.set_gravity(g);
        r
    }

    /// The velocity stage of semi-implicit Euler inside the contact solve: `q̇ += h q̈`
    /// (explicit velocity products; the linearly implicit update of the free-standing trees
    /// did not hold a whipping chain under a shaken root here either — `docs/physics/compounds-trees-drives.md`, "Long chains").
    pub(crate) fn velocity_stage(&mut self, h: f64) -> Result<(), DynamicsError> {
        let (q, qd) = (std::mem::take(&mut self.q), std::mem::take(&mut self.qd));
        let r = self.forward_dynamics(&q, &qd);
        (self.q, self.qd) = (q, qd);
        r?;
        for (v, a) in self.qd.iter_mut().zip(&self.qdd) {
            *v += h * a;
        }
        Ok(())
    }

    /// The position stage: `q ← q ⊞ h q̇`.
    pub(crate) fn position_stage(&mut self, h: f64) {
        self.advance_positions(h);
    }

    /// The configuration coordinate of velocity coordinate `k`, for joints whose coordinates
    /// move additively (revolute, prismatic, cylindrical, universal); `None` otherwise.
    pub(crate) fn q_of_dof(&self, k: usize) -> Option<f64> {
        self.additive_q.get(k).copied().flatten().map(|i| self.q[i])
    }
}
