//! Free-body position integration, a pluggable stage: the world calls
//! [`Integrator::integrate_positions`] once per substep after the velocity solve.
//! Part 3 adds further integrators behind the same trait.

use crate::algebra::{se3, SE3};
use crate::dynamics::{BodyKind, BodySet};

/// A position integrator for free (dynamic and kinematic) bodies.
pub trait Integrator: Send + Sync {
    /// Name for reports.
    fn name(&self) -> &'static str;
    /// Advances the poses of the moving bodies by `h` seconds from their velocities, and adds
    /// the change to `dp` (m) and `dtheta` (rad), world frame.
    fn integrate_positions(&self, bodies: &mut BodySet, h: f64);
}

/// `T ← T · Exp(h V)` with the body twist `V = (Rᵀ ω, Rᵀ v)` (paper §4.3): the exact flow of
/// a constant body twist over the substep.
#[derive(Clone, Copy, Debug, Default)]
pub struct LieGroupEuler;

impl Integrator for LieGroupEuler {
    fn name(&self) -> &'static str {
        "lie-group euler"
    }

    fn integrate_positions(&self, bodies: &mut BodySet, h: f64) {
        for i in 0..bodies.len() {
            let moving = match bodies.kind[i] {
                BodyKind::Dynamic => bodies.awake[i],
                BodyKind::Kinematic => true,
                BodyKind::Fixed => false,
            };
            if !moving {
                continue;
            }
            let (w, v) = (bodies.omega[i], bodies.vel[i]);
            if w == crate::geometry::V3::zeros() && v == crate::geometry::V3::zeros() {
                continue;
            }
            let r = bodies.rot[i];
            let t = SE3::new(r, bodies.pos[i])
                * SE3::exp(&se3::new(r.tr_mul(&w) * h, r.tr_mul(&v) * h));
            bodies.dp[i] += t.p - bodies.pos[i];
            bodies.dtheta[i] += w * h;
            bodies.pos[i] = t.p;
            bodies.rot[i] = t.r;
        }
    }
}
