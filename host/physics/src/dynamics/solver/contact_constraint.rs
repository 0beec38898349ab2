//! Contact constraints: non-penetration (soft, speculative), Coulomb friction on the cone,
//! restitution above a velocity threshold, and rolling resistance.
//!
//! One constraint per manifold, up to 4 points. Everything in world coordinates: anchors
//! `ra`, `rb` from each centre of mass to the contact (m), normal from A to B. Effective masses
//! (kg) and the angular responses `I⁻¹ (r × n)` are precomputed in [`ContactConstraint::prepare`].

use super::{ContactStiffness, Softness};
use crate::dynamics::BodySet;
use crate::geometry::{Manifold, Shape, M3, MAX_MANIFOLD_POINTS, V3};

/// Overlap allowed without position correction (m): keeps resting contacts from jittering.
pub const LINEAR_SLOP: f64 = 1e-4;

/// Solver settings for contacts (from the scene's effects).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSettings {
    /// Friction on.
    pub friction: bool,
    /// Restitution on.
    pub restitution: bool,
    /// Rolling resistance on.
    pub rolling: bool,
    /// Approach speed below which no bounce is applied (m/s).
    pub restitution_threshold: f64,
    /// Largest push-out speed of the position bias (m/s).
    pub max_push_velocity: f64,
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            friction: true,
            restitution: false,
            rolling: false,
            restitution_threshold: 0.5,
            max_push_velocity: 3.0,
        }
    }
}

/// What one Gauss–Seidel pass over the contacts does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SolvePass {
    /// Push overlapping points out with the soft position bias (the substep's solve pass);
    /// false in the relax pass, which removes the push-out velocity again.
    pub use_bias: bool,
    /// Walk the points backwards: alternating the direction between passes keeps the
    /// Gauss–Seidel order from tilting a resting box one way step after step.
    pub reverse: bool,
}

/// One row along a direction `d` at a point: each body's `I⁻¹ (r × d)` and the effective mass.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Row {
    pub(super) ia: V3,
    pub(super) ib: V3,
    pub(super) mass: f64,
}

impl Row {
    #[inline]
    fn new(ra: &V3, rb: &V3, d: &V3, ima: f64, imb: f64, ia: &M3, ib: &M3) -> Self {
        let ra_x = ra.cross(d);
        let rb_x = rb.cross(d);
        let iax = ia * ra_x;
        let ibx = ib * rb_x;
        let k = ima + imb + ra_x.dot(&iax) + rb_x.dot(&ibx);
        Self {
            ia: iax,
            ib: ibx,
            mass: if k > 0.0 { 1.0 / k } else { 0.0 },
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PointConstraint {
    pub(super) ra: V3,
    pub(super) rb: V3,
    pub(super) n: Row,
    pub(super) t: [Row; 2],
    /// Separation at the start of the step (m).
    pub(super) separation: f64,
    /// Normal relative velocity at the start of the step (m/s), for restitution.
    pub(super) relative_velocity: f64,
    pub(super) normal_impulse: f64,
    pub(super) tangent_impulse: [f64; 2],
    pub(super) max_normal_impulse: f64,
}

/// The constraint of one manifold.
#[derive(Clone, Copy, Debug)]
pub struct ContactConstraint {
    /// Body A.
    pub a: usize,
    /// Body B.
    pub b: usize,
    /// Index of the manifold it came from.
    pub manifold: usize,
    pub(super) normal: V3,
    pub(super) tangents: [V3; 2],
    pub(super) ima: f64,
    pub(super) imb: f64,
    ia: M3,
    ib: M3,
    pub(super) friction: f64,
    restitution: f64,
    /// Largest rolling-resistance torque per unit normal impulse (m): coefficient × radius.
    pub(super) rolling_arm: f64,
    rolling_mass: M3,
    rolling_impulse: V3,
    /// Whether one body cannot move (stiffer softness).
    pub against_static: bool,
    /// The soft coefficients of the normal rows ([`ContactConstraint::stiffen`]); until set,
    /// rigid without position bias.
    pub(super) softness: Softness,
    pub(super) len: usize,
    pub(super) points: [PointConstraint; MAX_MANIFOLD_POINTS],
}

/// A unit vector orthogonal to `n` and a second completing the right-handed basis.
#[inline]
pub fn tangent_basis(n: &V3) -> [V3; 2] {
    let t1 = if n.x.abs() < 0.57 {
        V3::new(0.0, n.z, -n.y)
    } else {
        V3::new(n.y, -n.x, 0.0)
    }
    .normalize();
    [t1, n.cross(&t1)]
}

fn rolling_radius(s: &Shape) -> f64 {
    match *s {
        Shape::Sphere { radius }
        | Shape::Capsule { radius, .. }
        | Shape::Cylinder { radius, .. } => radius,
        _ => 0.0,
    }
}

impl ContactConstraint {
    /// Builds the constraint of manifold `mi` from the bodies' current state.
    pub fn prepare(bodies: &BodySet, m: &Manifold, mi: usize, settings: &ContactSettings) -> Self {
        let (a, b) = (m.a as usize, m.b as usize);
        let ima = if bodies.awake[a] {
            bodies.inv_mass[a]
        } else {
            0.0
        };
        let imb = if bodies.awake[b] {
            bodies.inv_mass[b]
        } else {
            0.0
        };
        let ia = if ima > 0.0 {
            bodies.inv_inertia_world[a]
        } else {
            M3::zeros()
        };
        let ib = if imb > 0.0 {
            bodies.inv_inertia_world[b]
        } else {
            M3::zeros()
        };
        let (ma, mb) = (
            &bodies.part_material(a, m.part_a),
            &bodies.part_material(b, m.part_b),
        );
        let n = m.normal;
        let tangents = tangent_basis(&n);
        let (va, wa, vb, wb) = (
            bodies.vel[a],
            bodies.omega[a],
            bodies.vel[b],
            bodies.omega[b],
        );
        let mut points = [PointConstraint::default(); MAX_MANIFOLD_POINTS];
        for (pc, cp) in points.iter_mut().zip(m.points()) {
            let ra = cp.point - bodies.pos[a];
            let rb = cp.point - bodies.pos[b];
            let dv = vb + wb.cross(&rb) - va - wa.cross(&ra);
            *pc = PointConstraint {
                ra,
                rb,
                n: Row::new(&ra, &rb, &n, ima, imb, &ia, &ib),
                t: [
                    Row::new(&ra, &rb, &tangents[0], ima, imb, &ia, &ib),
                    Row::new(&ra, &rb, &tangents[1], ima, imb, &ia, &ib),
                ],
                separation: cp.separation,
                relative_velocity: n.dot(&dv),
                normal_impulse: cp.normal_impulse,
                tangent_impulse: if settings.friction {
                    cp.tangent_impulse
                } else {
                    [0.0; 2]
                },
                max_normal_impulse: 0.0,
            };
        }
        let rr = if settings.rolling {
            ma.rolling_resistance.max(mb.rolling_resistance)
                * rolling_radius(bodies.part_shape(a, m.part_a))
                    .max(rolling_radius(bodies.part_shape(b, m.part_b)))
        } else {
            0.0
        };
        let rolling_mass = if rr > 0.0 {
            (ia + ib).try_inverse().unwrap_or(M3::zeros())
        } else {
            M3::zeros()
        };
        Self {
            a,
            b,
            manifold: mi,
            normal: n,
            tangents,
            ima,
            imb,
            ia,
            ib,
            friction: if settings.friction {
                ma.pair_friction(mb)
            } else {
                0.0
            },
            restitution: if settings.restitution {
                ma.pair_restitution(mb)
            } else {
                0.0
            },
            rolling_arm: rr,
            rolling_mass,
            rolling_impulse: if rr > 0.0 {
                m.rolling_impulse
            } else {
                V3::zeros()
            },
            against_static: ima == 0.0 || imb == 0.0,
            softness: Softness::rigid(0.0),
            len: m.len,
            points,
        }
    }

    /// Takes its stiffness from the bodies' mass ratio ([`ContactStiffness`]).
    pub fn stiffen(&mut self, k: &ContactStiffness) {
        self.softness = k.softness(self.against_static, self.mass_ratio());
    }

    /// Ratio of the heavier to the lighter moving body (1 against a body that does not move).
    pub fn mass_ratio(&self) -> f64 {
        if self.against_static {
            1.0
        } else {
            self.ima.max(self.imb) / self.ima.min(self.imb)
        }
    }

    /// Sets the soft coefficients of the normal rows.
    pub fn set_softness(&mut self, s: Softness) {
        self.softness = s;
    }

    #[inline]
    fn apply(&self, bodies: &mut BodySet, p: &V3, ia_ang: &V3, ib_ang: &V3, s: f64) {
        let (a, b) = (self.a, self.b);
        bodies.vel[a] -= p * (self.ima * s);
        bodies.omega[a] -= ia_ang * s;
        bodies.vel[b] += p * (self.imb * s);
        bodies.omega[b] += ib_ang * s;
    }

    /// Applies the accumulated impulses (warm start).
    pub fn warm_start(&self, bodies: &mut BodySet) {
        for pc in &self.points[..self.len] {
            if pc.normal_impulse == 0.0 && pc.tangent_impulse == [0.0; 2] {
                continue;
            }
            let p = self.normal * pc.normal_impulse
                + self.tangents[0] * pc.tangent_impulse[0]
                + self.tangents[1] * pc.tangent_impulse[1];
            let ia = pc.n.ia * pc.normal_impulse
                + pc.t[0].ia * pc.tangent_impulse[0]
                + pc.t[1].ia * pc.tangent_impulse[1];
            let ib = pc.n.ib * pc.normal_impulse
                + pc.t[0].ib * pc.tangent_impulse[0]
                + pc.t[1].ib * pc.tangent_impulse[1];
            self.apply(bodies, &p, &ia, &ib, 1.0);
        }
        if self.rolling_arm > 0.0 {
            let r = self.rolling_impulse;
            bodies.omega[self.a] -= self.ia * r;
            bodies.omega[self.b] += self.ib * r;
        }
    }

    /// One pass over the points: normal (with the position bias of its
    /// [`ContactConstraint::softness`] in the substep's solve pass), friction, rolling
    /// resistance. `inv_h` = 1 / substep (1/s).
    pub fn solve(&mut self, bodies: &mut BodySet, inv_h: f64, max_push: f64, pass: SolvePass) {
        let SolvePass { use_bias, reverse } = pass;
        let soft = self.softness;
        let (a, b) = (self.a, self.b);
        let n = self.normal;
        let (ima, imb) = (self.ima, self.imb);
        // Work on local copies of the two bodies' velocities; write back once.
        let (mut va, mut wa, mut vb, mut wb) = (
            bodies.vel[a],
            bodies.omega[a],
            bodies.vel[b],
            bodies.omega[b],
        );
        let d_lin = bodies.dp[b] - bodies.dp[a];
        let (dta, dtb) = (bodies.dtheta[a], bodies.dtheta[b]);
        let mut total = 0.0;
        let len = self.len;
        let idx = |i: usize| if reverse { len - 1 - i } else { i };
        for i in 0..len {
            let pc = &mut self.points[idx(i)];
            let d = d_lin + dtb.cross(&pc.rb) - dta.cross(&pc.ra);
            let s = n.dot(&d) + pc.separation;
            let (bias, ms, is) = if s > 0.0 {
                (s * inv_h, 1.0, 0.0)
            } else if use_bias {
                let s = (s + LINEAR_SLOP).min(0.0);
                (
                    (soft.bias_rate * s).max(-max_push),
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let dv = vb + wb.cross(&pc.rb) - va - wa.cross(&pc.ra);
            let vn = n.dot(&dv);
            let imp = -pc.n.mass * ms * (vn + bias) - is * pc.normal_impulse;
            let new = (pc.normal_impulse + imp).max(0.0);
            let delta = new - pc.normal_impulse;
            pc.normal_impulse = new;
            pc.max_normal_impulse = pc.max_normal_impulse.max(delta);
            total += new;
            let p = n * delta;
            va -= p * ima;
            wa -= pc.n.ia * delta;
            vb += p * imb;
            wb += pc.n.ib * delta;
        }
        if self.friction > 0.0 {
            let (t0, t1) = (self.tangents[0], self.tangents[1]);
            for i in 0..len {
                let pc = &mut self.points[idx(i)];
                let l0 = pc.tangent_impulse;
                if pc.normal_impulse == 0.0 && l0 == [0.0; 2] {
                    // The cone is a point and nothing is accumulated: the row is a no-op.
                    continue;
                }
                let dv = vb + wb.cross(&pc.rb) - va - wa.cross(&pc.ra);
                let mut l = [
                    l0[0] - pc.t[0].mass * t0.dot(&dv),
                    l0[1] - pc.t[1].mass * t1.dot(&dv),
                ];
                // Coulomb cone: |λt| ≤ μ λn.
                let max = self.friction * pc.normal_impulse;
                let len2 = l[0] * l[0] + l[1] * l[1];
                if len2 > max * max {
                    let sc = if len2 > 0.0 { max / len2.sqrt() } else { 0.0 };
                    l = [l[0] * sc, l[1] * sc];
                }
                let d = [l[0] - l0[0], l[1] - l0[1]];
                pc.tangent_impulse = l;
                let p = t0 * d[0] + t1 * d[1];
                va -= p * ima;
                wa -= pc.t[0].ia * d[0] + pc.t[1].ia * d[1];
                vb += p * imb;
                wb += pc.t[0].ib * d[0] + pc.t[1].ib * d[1];
            }
        }
        if self.rolling_arm > 0.0 {
            let dw = wb - wa;
            let old = self.rolling_impulse;
            let mut l = old - self.rolling_mass * dw;
            let max = self.rolling_arm * total;
            let n2 = l.norm_squared();
            if n2 > max * max {
                l *= max / n2.sqrt();
            }
            let d = l - old;
            self.rolling_impulse = l;
            wa -= self.ia * d;
            wb += self.ib * d;
        }
        bodies.vel[a] = va;
        bodies.omega[a] = wa;
        bodies.vel[b] = vb;
        bodies.omega[b] = wb;
    }

    /// Restitution: points that approached faster than `threshold` (m/s) and carried load
    /// bounce with the material's coefficient.
    pub fn restitution(&mut self, bodies: &mut BodySet, threshold: f64) {
        if self.restitution == 0.0 {
            return;
        }
        let (a, b) = (self.a, self.b);
        let n = self.normal;
        for k in 0..self.len {
            let pc = self.points[k];
            if pc.relative_velocity > -threshold || pc.max_normal_impulse == 0.0 {
                continue;
            }
            let dv = bodies.vel[b] + bodies.omega[b].cross(&pc.rb)
                - bodies.vel[a]
                - bodies.omega[a].cross(&pc.ra);
            let vn = n.dot(&dv);
            let imp = -pc.n.mass * (vn + self.restitution * pc.relative_velocity);
            let new = (pc.normal_impulse + imp).max(0.0);
            let delta = new - pc.normal_impulse;
            self.points[k].normal_impulse = new;
            self.points[k].max_normal_impulse = pc.max_normal_impulse.max(delta);
            self.apply(
                bodies,
                &(n * delta),
                &(pc.n.ia * delta),
                &(pc.n.ib * delta),
                1.0,
            );
        }
    }

    /// Whether this constraint has a restitution coefficient.
    pub fn bounces(&self) -> bool {
        self.restitution > 0.0
    }

    /// Writes the accumulated impulses back into the manifold (warm start of the next step).
    pub fn store(&self, m: &mut Manifold) {
        for (cp, pc) in m.points[..m.len].iter_mut().zip(&self.points) {
            cp.normal_impulse = pc.normal_impulse;
            cp.tangent_impulse = pc.tangent_impulse;
            cp.max_normal_impulse = pc.max_normal_impulse;
        }
        m.rolling_impulse = self.rolling_impulse;
    }
}
