//! Joints between free bodies, solved as soft constraints in the same substeps as the
//! contacts. A joint is one of the model's joint types ([`FreeJointKind`], read from a
//! `model::Joint`) at a joint frame — an anchor point and three axes, given in world
//! coordinates when the joint is made and stored in each body's frame. At that moment the
//! joint's coordinates are zero; afterwards body B's joint frame moves relative to body A's as
//! the joint type allows.
//!
//! The constrained directions are the complement of the joint's motion subspace:
//!
//! | type | linear rows | angular rows |
//! |---|---|---|
//! | revolute | 3 (anchors coincide) | 2 (⊥ the axis: `u_A × u_B = 0`) |
//! | prismatic | 2 (⊥ the axis, measured in A) | 3 (relative rotation stays) |
//! | cylindrical | 2 | 2 |
//! | universal | 3 | 1 (`u₁ · u₂` stays) |
//! | ball | 3 | 0 |
//! | fixed | 3 | 3 |
//! | free | 0 | 0 |
//!
//! The angular errors of revolute and cylindrical joints do not depend on the angle about the
//! axis, so any number of turns keeps them aligned. Each coordinate of a revolute, prismatic,
//! cylindrical or universal joint can carry a motor, limits and an armature
//! ([`super::joint_dofs`]); its value is continuous across turns.
//!
//! A kinematic or fixed body on one side makes a joint to the world or to a driven part (the
//! foosball rod).

use super::joint_dofs::{DofDrive, DofState};
use super::joint_kind::FreeJointKind;
use super::Softness;
use crate::algebra::log_so3;
use crate::dynamics::BodySet;
use crate::geometry::{M3, V3};

type M6 = nalgebra::Matrix6<f64>;
type V6 = nalgebra::Vector6<f64>;

/// Driven coordinates a joint holds at most (cylindrical and universal joints have two).
pub(crate) const MAX_DRIVEN_DOFS: usize = 2;

/// A joint between bodies `a` and `b` and its solver state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FreeJoint {
    /// Body A (storage index).
    pub(crate) a: usize,
    /// Body B (storage index).
    pub(crate) b: usize,
    kind: FreeJointKind,
    /// Anchor in A's frame (m).
    local_a: V3,
    /// Anchor in B's frame (m).
    local_b: V3,
    /// Joint axes in A's frame (columns).
    frame_a: M3,
    /// Joint axes in B's frame (columns).
    frame_b: M3,
    /// The substep the motors and limits integrate over (s).
    substep: f64,
    dofs: [DofState; MAX_DRIVEN_DOFS],
    ima: f64,
    imb: f64,
    ia: M3,
    ib: M3,
    /// The constraint rows (the first `n_rows`), their inverse block `K⁻¹ = (J M⁻¹ Jᵀ)⁻¹`
    /// and their accumulated impulses (N·s or N·m·s along each row's unit direction).
    rows: [Row; 6],
    n_rows: usize,
    k_inv: M6,
    lambda: [f64; 6],
    /// The accumulated impulses as vectors (world), linear and angular, expressed in each
    /// substep's rows (whose directions may turn with body A).
    lin_impulse: V3,
    ang_impulse: V3,
}

/// `x` wrapped into (−π, π].
fn wrap(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let y = x - TAU * (x / TAU).round();
    if y <= -PI {
        y + TAU
    } else {
        y
    }
}

/// The angle about unit `n` that takes `v` to `w` (both projected onto the plane ⊥ `n`).
fn angle_about(n: &V3, v: &V3, w: &V3) -> f64 {
    let vp = v - n * n.dot(v);
    let wp = w - n * n.dot(w);
    crate::transcendental::atan2(n.dot(&vp.cross(&wp)), vp.dot(&wp))
}

/// A unit vector ⊥ unit `u`.
fn perpendicular(u: &V3) -> V3 {
    let t = if u.x.abs() < 0.6 { V3::x() } else { V3::y() };
    u.cross(&t).normalize()
}

/// One row: its rate is `lin·(v_B − v_A) + ang_b·ω_B − ang_a·ω_A`; a constraint row also
/// has its unit direction `dir` (world), linear or angular.
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    lin: V3,
    ang_a: V3,
    ang_b: V3,
    dir: V3,
    linear: bool,
}

impl Row {
    fn linear(n: V3, arm_a: &V3, rb: &V3) -> Self {
        Self {
            lin: n,
            ang_a: arm_a.cross(&n),
            ang_b: rb.cross(&n),
            dir: n,
            linear: true,
        }
    }

    fn angular(g: V3) -> Self {
        Self {
            lin: V3::zeros(),
            ang_a: g,
            ang_b: g,
            dir: g,
            linear: false,
        }
    }
}

/// The joint frames in world coordinates for the current poses.
struct Frames {
    ra: V3,
    rb: V3,
    /// Anchor of B − anchor of A (m, world).
    d: V3,
    /// Joint axes of A and of B (world, columns).
    rot_a: M3,
    rot_b: M3,
}

impl FreeJoint {
    /// A joint of type `kind` between bodies `a` and `b` (storage indices, valid, distinct)
    /// whose joint frame has its origin at `anchor` (m, world) and the columns of `axes`
    /// (a rotation, world) as axes, at the bodies' current poses. `substep` is the substep
    /// the motors and limits integrate over (s).
    pub(crate) fn new(
        bodies: &BodySet,
        a: usize,
        b: usize,
        kind: FreeJointKind,
        anchor: V3,
        axes: M3,
        substep: f64,
    ) -> Self {
        let (rot_a, rot_b) = (&bodies.rot[a], &bodies.rot[b]);
        Self {
            a,
            b,
            kind,
            local_a: rot_a.tr_mul(&(anchor - bodies.pos[a])),
            local_b: rot_b.tr_mul(&(anchor - bodies.pos[b])),
            frame_a: rot_a.tr_mul(&axes),
            frame_b: rot_b.tr_mul(&axes),
            substep,
            dofs: [DofState::default(); MAX_DRIVEN_DOFS],
            ima: 0.0,
            imb: 0.0,
            ia: M3::zeros(),
            ib: M3::zeros(),
            rows: [Row::default(); 6],
            n_rows: 0,
            k_inv: M6::zeros(),
            lambda: [0.0; 6],
            lin_impulse: V3::zeros(),
            ang_impulse: V3::zeros(),
        }
    }

    /// The joint type.
    pub(crate) fn kind(&self) -> FreeJointKind {
        self.kind
    }

    /// The two bodies (storage indices).
    pub(crate) fn bodies(&self) -> (usize, usize) {
        (self.a, self.b)
    }

    /// The substep the motors and limits integrate over (s).
    pub(crate) fn set_substep(&mut self, h: f64) {
        self.substep = h;
    }

    /// What drives coordinate `dof` (`None` past the driven coordinates).
    pub(crate) fn drive(&self, dof: usize) -> Option<&DofDrive> {
        (dof < self.kind.driven_dofs()).then(|| &self.dofs[dof].drive)
    }

    /// What drives coordinate `dof`, to change it (`None` past the driven coordinates).
    pub(crate) fn drive_mut(&mut self, dof: usize) -> Option<&mut DofDrive> {
        (dof < self.kind.driven_dofs()).then(|| &mut self.dofs[dof].drive)
    }

    /// The torque or force the motor of `dof` gave in the last substep (N·m or N, along the
    /// coordinate, on B; A takes the opposite).
    pub(crate) fn motor_force(&self, dof: usize) -> Option<f64> {
        (dof < self.kind.driven_dofs() && self.substep > 0.0)
            .then(|| self.dofs[dof].motor_impulse / self.substep)
    }

    /// The torque or force the limits of `dof` gave in the last substep (N·m or N, along the
    /// coordinate, on B: positive pushes away from the lower limit).
    pub(crate) fn limit_force(&self, dof: usize) -> Option<f64> {
        (dof < self.kind.driven_dofs() && self.substep > 0.0).then(|| {
            let l = self.dofs[dof].limit_impulse;
            (l[0] - l[1]) / self.substep
        })
    }

    /// The value of coordinate `dof` at the bodies' current poses (rad or m; angles count
    /// whole turns), `None` past the driven coordinates.
    pub(crate) fn position(&self, bodies: &BodySet, dof: usize) -> Option<f64> {
        (dof < self.kind.driven_dofs())
            .then(|| self.coordinate(&self.frames(bodies), dof, self.dofs[dof].q))
    }

    /// The rate of coordinate `dof` at the bodies' current velocities (rad/s or m/s).
    pub(crate) fn rate(&self, bodies: &BodySet, dof: usize) -> Option<f64> {
        (dof < self.kind.driven_dofs()).then(|| {
            let f = self.frames(bodies);
            let arm_a = f.ra + f.d;
            self.row_rate(bodies, &self.dof_row(&f, &arm_a, dof))
        })
    }

    fn frames(&self, bodies: &BodySet) -> Frames {
        let (a, b) = (self.a, self.b);
        let ra = bodies.rot[a] * self.local_a;
        let rb = bodies.rot[b] * self.local_b;
        Frames {
            ra,
            rb,
            d: bodies.pos[b] + rb - bodies.pos[a] - ra,
            rot_a: bodies.rot[a] * self.frame_a,
            rot_b: bodies.rot[b] * self.frame_b,
        }
    }

    /// Coordinate `dof` from the frames; angles continue from `prev` (within half a turn).
    fn coordinate(&self, f: &Frames, dof: usize, prev: f64) -> f64 {
        let rel = f.rot_a.tr_mul(&f.rot_b);
        let raw = match (self.kind, dof) {
            (FreeJointKind::Prismatic { axis }, _) | (FreeJointKind::Cylindrical { axis }, 1) => {
                return (f.rot_a * axis).dot(&f.d);
            }
            (FreeJointKind::Revolute { axis }, _) | (FreeJointKind::Cylindrical { axis }, _) => {
                let v = perpendicular(&axis);
                angle_about(&axis, &v, &(rel * v))
            }
            (FreeJointKind::Universal { axis1, axis2 }, 0) => {
                angle_about(&axis1, &axis2, &(rel * axis2))
            }
            (FreeJointKind::Universal { axis1, axis2 }, _) => {
                -angle_about(&axis2, &axis1, &rel.tr_mul(&axis1))
            }
            _ => return 0.0,
        };
        prev + wrap(raw - prev)
    }

    /// The row of coordinate `dof`; `arm_a` is A's lever arm for slides (`ra + d`).
    fn dof_row(&self, f: &Frames, arm_a: &V3, dof: usize) -> Row {
        match (self.kind, dof) {
            (FreeJointKind::Prismatic { axis }, _) | (FreeJointKind::Cylindrical { axis }, 1) => {
                Row::linear(f.rot_a * axis, arm_a, &f.rb)
            }
            (FreeJointKind::Revolute { axis }, _) | (FreeJointKind::Cylindrical { axis }, _) => {
                Row::angular(f.rot_a * axis)
            }
            (FreeJointKind::Universal { axis1, axis2 }, k) => {
                // ω_rel = q̇₁ u₁ + q̇₂ u₂ + c n: the rates are the dual basis' components.
                let (u1, u2) = (f.rot_a * axis1, f.rot_b * axis2);
                let n = u1.cross(&u2);
                let g = if k == 0 {
                    let g = u2.cross(&n);
                    g / u1.dot(&g)
                } else {
                    let g = n.cross(&u1);
                    g / u2.dot(&g)
                };
                Row::angular(g)
            }
            _ => Row::angular(V3::zeros()),
        }
    }

    fn row_rate(&self, bodies: &BodySet, r: &Row) -> f64 {
        let (a, b) = (self.a, self.b);
        r.lin.dot(&(bodies.vel[b] - bodies.vel[a])) + r.ang_b.dot(&bodies.omega[b])
            - r.ang_a.dot(&bodies.omega[a])
    }

    /// `J₁ M⁻¹ J₂ᵀ` of two rows.
    fn coupling(&self, r1: &Row, r2: &Row) -> f64 {
        (self.ima + self.imb) * r1.lin.dot(&r2.lin)
            + r1.ang_a.dot(&(self.ia * r2.ang_a))
            + r1.ang_b.dot(&(self.ib * r2.ang_b))
    }

    /// A coordinate row's inverse effective mass with the constraint rows holding:
    /// `a − bᵀ K⁻¹ b`, `b_i = J_i M⁻¹ J_qᵀ` (the Schur complement), so that an impulse on
    /// the coordinate followed by the constraint block changes its rate by exactly `a λ`.
    fn reduced_inv_mass(&self, r: &Row) -> f64 {
        let mut b = nalgebra::Vector6::zeros();
        for i in 0..self.n_rows {
            b[i] = self.coupling(&self.rows[i], r);
        }
        self.coupling(r, r) - b.dot(&(self.k_inv * b))
    }

    fn apply_row(&self, bodies: &mut BodySet, r: &Row, lambda: f64) {
        let (a, b) = (self.a, self.b);
        bodies.vel[a] -= r.lin * (self.ima * lambda);
        bodies.omega[a] -= self.ia * (r.ang_a * lambda);
        bodies.vel[b] += r.lin * (self.imb * lambda);
        bodies.omega[b] += self.ib * (r.ang_b * lambda);
    }

    fn has_drives(&self) -> bool {
        self.dofs[..self.kind.driven_dofs()]
            .iter()
            .any(|d| d.drive.is_active())
    }

    /// The constraint rows at the frames `f` and how many there are.
    fn build_rows(&self, f: &Frames) -> ([Row; 6], usize) {
        use FreeJointKind as K;
        let mut rows = [Row::default(); 6];
        let mut n = 0;
        let mut push = |r: Row| {
            rows[n] = r;
            n += 1;
        };
        // Linear rows: the anchors coincide, or (slides) coincide ⊥ the axis fixed in A.
        match self.kind {
            K::Free => {}
            K::Prismatic { axis } | K::Cylindrical { axis } => {
                let u = f.rot_a * axis;
                let p1 = perpendicular(&u);
                let arm_a = f.ra + f.d;
                push(Row::linear(p1, &arm_a, &f.rb));
                push(Row::linear(u.cross(&p1), &arm_a, &f.rb));
            }
            _ => {
                for e in [V3::x(), V3::y(), V3::z()] {
                    push(Row::linear(e, &f.ra, &f.rb));
                }
            }
        }
        // Angular rows.
        match self.kind {
            K::Fixed | K::Prismatic { .. } => {
                for e in [V3::x(), V3::y(), V3::z()] {
                    push(Row::angular(e));
                }
            }
            K::Revolute { axis } | K::Cylindrical { axis } => {
                let u = f.rot_a * axis;
                let p1 = perpendicular(&u);
                push(Row::angular(p1));
                push(Row::angular(u.cross(&p1)));
            }
            K::Universal { axis1, axis2 } => {
                let g = (f.rot_b * axis2).cross(&(f.rot_a * axis1));
                push(Row::angular(g.try_normalize(1e-12).unwrap_or(V3::z())));
            }
            K::Ball | K::Free => {}
        }
        (rows, n)
    }

    /// The accumulated impulses along `rows`.
    fn impulses_along(&self, rows: &[Row]) -> [f64; 6] {
        let mut l = [0.0; 6];
        for (x, r) in l.iter_mut().zip(rows) {
            *x = r.dir.dot(if r.linear {
                &self.lin_impulse
            } else {
                &self.ang_impulse
            });
        }
        l
    }

    /// Jacobians and effective masses from the current poses (called at the start of each
    /// step and of each substep's solve, so that fast-turning bodies keep exact anchors).
    fn refresh(&mut self, bodies: &BodySet) {
        let (a, b) = (self.a, self.b);
        self.ima = if bodies.awake[a] {
            bodies.inv_mass[a]
        } else {
            0.0
        };
        self.imb = if bodies.awake[b] {
            bodies.inv_mass[b]
        } else {
            0.0
        };
        self.ia = if self.ima > 0.0 {
            bodies.inv_inertia_world[a]
        } else {
            M3::zeros()
        };
        self.ib = if self.imb > 0.0 {
            bodies.inv_inertia_world[b]
        } else {
            M3::zeros()
        };
        let f = self.frames(bodies);
        let (rows, n) = self.build_rows(&f);
        let mut k = M6::identity();
        for i in 0..n {
            for j in 0..n {
                k[(i, j)] = self.coupling(&rows[i], &rows[j]);
            }
        }
        self.k_inv = k.try_inverse().unwrap_or(M6::zeros());
        // The accumulated impulses in the new rows.
        self.lambda = self.impulses_along(&rows[..n]);
        self.rows = rows;
        self.n_rows = n;
        for k in 0..self.kind.driven_dofs() {
            self.dofs[k].q = self.coordinate(&f, k, self.dofs[k].q);
        }
    }

    /// Prepares the step: Jacobians and effective masses from the current poses, and the
    /// coordinates' rates at the step's start.
    pub(crate) fn prepare(&mut self, bodies: &BodySet) {
        self.refresh(bodies);
        self.record_rates(bodies);
    }

    fn record_rates(&mut self, bodies: &BodySet) {
        if !self.has_drives() {
            return;
        }
        let f = self.frames(bodies);
        let arm_a = f.ra + f.d;
        for k in 0..self.kind.driven_dofs() {
            self.dofs[k].rate_end = self.row_rate(bodies, &self.dof_row(&f, &arm_a, k));
        }
    }

    /// Applies the accumulated impulses of the constraint rows.
    pub(crate) fn warm_start(&self, bodies: &mut BodySet) {
        if self.n_rows == 0 {
            return;
        }
        let (rows, n) = self.build_rows(&self.frames(bodies));
        let lambda = self.impulses_along(&rows[..n]);
        for i in 0..n {
            self.apply_row(bodies, &rows[i], lambda[i]);
        }
    }

    /// The constraint errors for the current poses: linear (m) and angular (rad) vectors
    /// (world) whose components along the rows' directions are the rows' errors.
    fn errors(&self, bodies: &BodySet) -> (V3, V3) {
        use FreeJointKind as K;
        let f = self.frames(bodies);
        let ang = match self.kind {
            K::Fixed | K::Prismatic { .. } => log_so3(&(f.rot_b * f.rot_a.transpose())),
            K::Revolute { axis } | K::Cylindrical { axis } => {
                (f.rot_a * axis).cross(&(f.rot_b * axis))
            }
            K::Universal { axis1, axis2 } => {
                // C = u₁·u₂ − its value at the start; Ċ = |n| ĝ·ω_rel, so the row's error
                // along ĝ is C / |n|.
                let (u1, u2) = (f.rot_a * axis1, f.rot_b * axis2);
                let n = u2.cross(&u1);
                let c = u1.dot(&u2) - axis1.dot(&axis2);
                let len = n.norm();
                if len > 1e-12 {
                    n * (c / (len * len))
                } else {
                    V3::zeros()
                }
            }
            K::Ball | K::Free => V3::zeros(),
        };
        (f.d, ang)
    }

    /// The constraint rows' rates.
    fn block_rates(&self, bodies: &BodySet) -> [f64; 6] {
        let mut r = [0.0; 6];
        for (x, row) in r.iter_mut().zip(&self.rows[..self.n_rows]) {
            *x = self.row_rate(bodies, row);
        }
        r
    }

    /// Brings the constraint rows' rates back to `target` (rigidly), after the coordinates'
    /// rows changed them.
    fn restore_block(&mut self, bodies: &mut BodySet, target: &[f64; 6]) {
        let n = self.n_rows;
        let mut rhs = nalgebra::Vector6::zeros();
        for i in 0..n {
            rhs[i] = self.row_rate(bodies, &self.rows[i]) - target[i];
        }
        let dl = -(self.k_inv * rhs);
        let (mut lin, mut ang) = (V3::zeros(), V3::zeros());
        for i in 0..n {
            self.lambda[i] += dl[i];
            let r = self.rows[i];
            self.apply_row(bodies, &r, dl[i]);
            if r.linear {
                lin += r.dir * self.lambda[i];
            } else {
                ang += r.dir * self.lambda[i];
            }
        }
        self.lin_impulse = lin;
        self.ang_impulse = ang;
    }

    /// How many constraint rows the joint has.
    pub(crate) fn row_count(&self) -> usize {
        self.n_rows
    }

    /// The constraint rows' Jacobian against body `i`'s velocity `(v, ω)` (world), one row
    /// per constraint row and zero rows below them; zero for a body the joint does not join.
    pub(crate) fn jacobian(&self, i: usize) -> M6 {
        let sign = if i == self.b {
            1.0
        } else if i == self.a {
            -1.0
        } else {
            return M6::zeros();
        };
        let mut j = M6::zeros();
        for (k, r) in self.rows[..self.n_rows].iter().enumerate() {
            let ang = if i == self.b { r.ang_b } else { r.ang_a };
            for d in 0..3 {
                j[(k, d)] = sign * r.lin[d];
                j[(k, 3 + d)] = sign * ang[d];
            }
        }
        j
    }

    /// The right-hand side of the block's solve: each row's rate plus `rate` times its
    /// position error (with `use_bias`); zeros below the rows.
    pub(crate) fn block_rhs(&self, bodies: &BodySet, rate: f64, use_bias: bool) -> V6 {
        let mut rhs = if use_bias {
            self.block_errors(bodies) * rate
        } else {
            V6::zeros()
        };
        for i in 0..self.n_rows {
            rhs[i] += self.row_rate(bodies, &self.rows[i]);
        }
        rhs
    }

    /// Each row's position error (m or rad) at the current poses; zeros below the rows.
    pub(crate) fn block_errors(&self, bodies: &BodySet) -> V6 {
        let mut c = V6::zeros();
        if self.n_rows == 0 {
            return c;
        }
        let (lin_err, ang_err) = self.errors(bodies);
        for (x, r) in c.iter_mut().zip(&self.rows[..self.n_rows]) {
            *x = r.dir.dot(if r.linear { &lin_err } else { &ang_err });
        }
        c
    }

    /// Moves the bodies as an impulse `dl` on the rows would move them in unit time (a
    /// displacement `M⁻¹ Jᵀ dl`, m and rad), adding it to their `dp` and `dtheta`.
    pub(crate) fn displace(&self, bodies: &mut BodySet, dl: &V6) {
        let (a, b) = (self.a, self.b);
        let (mut pa, mut ta, mut pb, mut tb) = (V3::zeros(), V3::zeros(), V3::zeros(), V3::zeros());
        for (r, &l) in self.rows[..self.n_rows].iter().zip(dl.iter()) {
            pa -= r.lin * (self.ima * l);
            ta -= self.ia * (r.ang_a * l);
            pb += r.lin * (self.imb * l);
            tb += self.ib * (r.ang_b * l);
        }
        for (i, dp, dt, moves) in [(a, pa, ta, self.ima > 0.0), (b, pb, tb, self.imb > 0.0)] {
            if moves {
                bodies.pos[i] += dp;
                bodies.rot[i] = crate::algebra::exp_so3(&dt) * bodies.rot[i];
                bodies.dp[i] += dp;
                bodies.dtheta[i] += dt;
            }
        }
    }

    /// Applies `dl − s_i λ` to the rows' accumulated impulses and to the bodies.
    pub(crate) fn apply_block(&mut self, bodies: &mut BodySet, dl: &V6, impulse_scale: f64) {
        let n = self.n_rows;
        if n == 0 {
            return;
        }
        let (mut lin, mut ang) = (V3::zeros(), V3::zeros());
        for i in 0..n {
            let d = dl[i] - impulse_scale * self.lambda[i];
            self.lambda[i] += d;
            let r = self.rows[i];
            self.apply_row(bodies, &r, d);
            if r.linear {
                lin += r.dir * self.lambda[i];
            } else {
                ang += r.dir * self.lambda[i];
            }
        }
        self.lin_impulse = lin;
        self.ang_impulse = ang;
    }

    /// The pass's block coefficients `(bias rate, mass scale, impulse scale)`: the soft ones
    /// with the position correction, rigid without.
    pub(crate) fn block_softness(soft: &Softness, use_bias: bool) -> (f64, f64, f64) {
        if use_bias {
            (soft.bias_rate, soft.mass_scale, soft.impulse_scale)
        } else {
            (0.0, 1.0, 0.0)
        }
    }

    /// Starts a pass: with `use_bias` (a substep's first pass) the rows and effective masses
    /// from the current poses, otherwise the driven coordinates' values.
    pub(crate) fn begin_pass(&mut self, bodies: &BodySet, use_bias: bool) {
        if use_bias {
            self.refresh(bodies);
            for d in &mut self.dofs {
                d.begin_substep();
            }
        } else if self.has_drives() {
            let f = self.frames(bodies);
            for k in 0..self.kind.driven_dofs() {
                self.dofs[k].q = self.coordinate(&f, k, self.dofs[k].q);
            }
        }
    }

    /// One pass over this joint's block alone: `Δλ = −K⁻¹ (J V + β C) s_m − s_i λ`. A pass
    /// over a joint is [`Self::begin_pass`], its block (this, or the joints' forest at once),
    /// then [`Self::solve_driven`]; `use_bias` adds the soft position correction (a
    /// substep's first pass), without it the pass only removes velocity errors (the relax
    /// pass).
    pub(crate) fn solve_block(&mut self, bodies: &mut BodySet, soft: &Softness, use_bias: bool) {
        let (rate, ms, is) = Self::block_softness(soft, use_bias);
        let rhs = self.block_rhs(bodies, rate, use_bias);
        let dl = -(self.k_inv * rhs) * ms;
        self.apply_block(bodies, &dl, is);
    }

    /// The driven coordinates' part of a pass, after the block: their rows, then the block's
    /// rates restored to what the block chose (with its position correction).
    pub(crate) fn solve_driven(&mut self, bodies: &mut BodySet, soft: &Softness, use_bias: bool) {
        if !self.has_drives() {
            return;
        }
        if self.n_rows > 0 {
            let target = self.block_rates(bodies);
            self.solve_dofs(bodies, soft, use_bias);
            self.restore_block(bodies, &target);
        } else {
            self.solve_dofs(bodies, soft, use_bias);
        }
        self.record_rates(bodies);
    }

    /// One pass over the driven coordinates' rows (motors, limits, armature).
    fn solve_dofs(&mut self, bodies: &mut BodySet, soft: &Softness, use_bias: bool) {
        let f = self.frames(bodies);
        let arm_a = f.ra + f.d;
        let limit_soft = use_bias.then_some((soft.bias_rate, soft.mass_scale, soft.impulse_scale));
        for k in 0..self.kind.driven_dofs() {
            if !self.dofs[k].drive.is_active() {
                continue;
            }
            let row = self.dof_row(&f, &arm_a, k);
            let inv_mass = self.reduced_inv_mass(&row);
            let rate = self.row_rate(bodies, &row);
            let mut state = self.dofs[k];
            let this = &*self;
            state.solve(rate, inv_mass, self.substep, limit_soft, |lambda| {
                this.apply_row(bodies, &row, lambda);
                this.row_rate(bodies, &row)
            });
            self.dofs[k] = state;
        }
    }

    /// Current anchor gap (m): how far the joint's constrained directions have drifted
    /// apart (the distance between the anchors, less any slide a prismatic or cylindrical
    /// joint allows).
    pub(crate) fn gap(&self, bodies: &BodySet) -> f64 {
        let f = self.frames(bodies);
        match self.kind {
            FreeJointKind::Free => 0.0,
            FreeJointKind::Prismatic { axis } | FreeJointKind::Cylindrical { axis } => {
                let u = f.rot_a * axis;
                (f.d - u * u.dot(&f.d)).norm()
            }
            _ => f.d.norm(),
        }
    }

    /// The largest angle (rad) by which the joint's constrained rotations have drifted: the
    /// relative rotation of a fixed or prismatic joint, the misalignment of a revolute or
    /// cylindrical joint's axes, the change of a universal joint's axis angle; 0 for ball and
    /// free joints.
    pub(crate) fn angular_gap(&self, bodies: &BodySet) -> f64 {
        let f = self.frames(bodies);
        match self.kind {
            FreeJointKind::Fixed | FreeJointKind::Prismatic { .. } => {
                log_so3(&(f.rot_b * f.rot_a.transpose())).norm()
            }
            FreeJointKind::Revolute { axis } | FreeJointKind::Cylindrical { axis } => {
                (f.rot_a * axis).angle(&(f.rot_b * axis))
            }
            FreeJointKind::Universal { axis1, axis2 } => {
                let now = (f.rot_a * axis1).angle(&(f.rot_b * axis2));
                (now - axis1.angle(&axis2)).abs()
            }
            FreeJointKind::Ball | FreeJointKind::Free => 0.0,
        }
    }
}
