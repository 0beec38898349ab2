//! Joints between free bodies (ball, revolute, fixed), solved as soft constraints in the same
//! substeps as the contacts. Anchors are stored in each body's frame (m); a revolute axis in
//! each body's frame (unit). A kinematic or fixed body on one side makes a hinge to the world
//! or to a driven part (the foosball rod).

use super::Softness;
use crate::algebra::log_so3;
use crate::dynamics::BodySet;
use crate::geometry::{M3, V3};

/// The kind of a joint between two free bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FreeJointKind {
    /// Point-to-point: the anchors coincide, rotation free.
    Ball,
    /// Hinge: anchors coincide and the two axes stay aligned.
    Revolute {
        /// Axis in body A's frame (unit).
        axis_a: V3,
        /// Axis in body B's frame (unit).
        axis_b: V3,
    },
    /// Weld: anchors coincide and the relative rotation stays `rel = R_aᵀ R_b` (initial).
    Fixed {
        /// Relative rotation to keep.
        rel: M3,
    },
}

/// A joint between bodies `a` and `b` and its solver state.
#[derive(Clone, Copy, Debug)]
pub struct FreeJoint {
    /// Body A.
    pub a: usize,
    /// Body B.
    pub b: usize,
    /// What it constrains.
    pub kind: FreeJointKind,
    /// Anchor in A's frame (m).
    pub local_a: V3,
    /// Anchor in B's frame (m).
    pub local_b: V3,
    ra: V3,
    rb: V3,
    ima: f64,
    imb: f64,
    ia: M3,
    ib: M3,
    lin_mass: M3,
    ang_mass: M3,
    lin_impulse: V3,
    ang_impulse: V3,
}

#[inline]
fn skew(v: &V3) -> M3 {
    M3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

impl FreeJoint {
    /// A joint whose anchor is `anchor` (m, world) with the bodies' current poses; a revolute
    /// axis `axis` is given in world coordinates.
    pub fn new(
        bodies: &BodySet,
        a: usize,
        b: usize,
        anchor: V3,
        kind: &str,
        axis: V3,
    ) -> Option<Self> {
        let (ra, rb) = (&bodies.rot[a], &bodies.rot[b]);
        let kind = match kind {
            "ball" => FreeJointKind::Ball,
            "revolute" => {
                let ax = axis.try_normalize(1e-12)?;
                FreeJointKind::Revolute {
                    axis_a: ra.tr_mul(&ax),
                    axis_b: rb.tr_mul(&ax),
                }
            }
            "fixed" => FreeJointKind::Fixed { rel: ra.tr_mul(rb) },
            _ => return None,
        };
        Some(Self {
            a,
            b,
            kind,
            local_a: ra.tr_mul(&(anchor - bodies.pos[a])),
            local_b: rb.tr_mul(&(anchor - bodies.pos[b])),
            ra: V3::zeros(),
            rb: V3::zeros(),
            ima: 0.0,
            imb: 0.0,
            ia: M3::zeros(),
            ib: M3::zeros(),
            lin_mass: M3::zeros(),
            ang_mass: M3::zeros(),
            lin_impulse: V3::zeros(),
            ang_impulse: V3::zeros(),
        })
    }

    /// Jacobians and effective masses from the current poses (called at the start of each
    /// step and of each substep's solve, so that fast-turning bodies keep exact anchors).
    pub fn prepare(&mut self, bodies: &BodySet) {
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
        self.ra = bodies.rot[a] * self.local_a;
        self.rb = bodies.rot[b] * self.local_b;
        let (sa, sb) = (skew(&self.ra), skew(&self.rb));
        let k = M3::identity() * (self.ima + self.imb) - sa * self.ia * sa - sb * self.ib * sb;
        self.lin_mass = k.try_inverse().unwrap_or(M3::zeros());
        let ka = self.ia + self.ib;
        self.ang_mass = match self.kind {
            FreeJointKind::Ball => M3::zeros(),
            FreeJointKind::Fixed { .. } => ka.try_inverse().unwrap_or(M3::zeros()),
            FreeJointKind::Revolute { axis_a, .. } => {
                let ax = bodies.rot[a] * axis_a;
                let p = M3::identity() - ax * ax.transpose();
                let kp = p * ka * p + ax * ax.transpose();
                p * kp.try_inverse().unwrap_or(M3::zeros()) * p
            }
        };
    }

    fn apply(&self, bodies: &mut BodySet, lin: &V3, ang: &V3) {
        let (a, b) = (self.a, self.b);
        bodies.vel[a] -= lin * self.ima;
        bodies.omega[a] -= self.ia * (self.ra.cross(lin) + ang);
        bodies.vel[b] += lin * self.imb;
        bodies.omega[b] += self.ib * (self.rb.cross(lin) + ang);
    }

    /// Applies the accumulated impulses.
    pub fn warm_start(&self, bodies: &mut BodySet) {
        self.apply(bodies, &self.lin_impulse, &self.ang_impulse);
    }

    /// One pass; `use_bias` adds the soft position correction.
    pub fn solve(&mut self, bodies: &mut BodySet, soft: &Softness, use_bias: bool) {
        if use_bias {
            self.prepare(bodies);
        }
        let (a, b) = (self.a, self.b);
        let (ms, is, rate) = if use_bias {
            (soft.mass_scale, soft.impulse_scale, soft.bias_rate)
        } else {
            (1.0, 0.0, 0.0)
        };
        if !matches!(self.kind, FreeJointKind::Ball) {
            let err = match self.kind {
                FreeJointKind::Fixed { rel } => {
                    log_so3(&(bodies.rot[b] * (bodies.rot[a] * rel).transpose()))
                }
                FreeJointKind::Revolute { axis_a, axis_b } => {
                    (bodies.rot[a] * axis_a).cross(&(bodies.rot[b] * axis_b))
                }
                FreeJointKind::Ball => V3::zeros(),
            };
            let dw = bodies.omega[b] - bodies.omega[a];
            let imp = -(self.ang_mass * (dw + err * rate)) * ms - self.ang_impulse * is;
            self.ang_impulse += imp;
            self.apply(bodies, &V3::zeros(), &imp);
        }
        let c = bodies.pos[b] + bodies.rot[b] * self.local_b
            - bodies.pos[a]
            - bodies.rot[a] * self.local_a;
        let dv = bodies.vel[b] + bodies.omega[b].cross(&self.rb)
            - bodies.vel[a]
            - bodies.omega[a].cross(&self.ra);
        let imp = -(self.lin_mass * (dv + c * rate)) * ms - self.lin_impulse * is;
        self.lin_impulse += imp;
        self.apply(bodies, &imp, &V3::zeros());
    }

    /// Current anchor gap (m): how far the joint has drifted apart.
    pub fn gap(&self, bodies: &BodySet) -> f64 {
        (bodies.pos[self.b] + bodies.rot[self.b] * self.local_b
            - bodies.pos[self.a]
            - bodies.rot[self.a] * self.local_a)
            .norm()
    }
}
