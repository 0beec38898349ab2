//! Free (floating) joint: all six degrees of freedom.

use super::Joint;
use crate::algebra::{exp_so3, se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Unconstrained motion. 6 DOF.
///
/// Configuration: `q = (r, p)`, rotation in exponential coordinates `r` (rad) and translation
/// `p` (m, joint frame): `X_J = (exp([r]), p)`. Velocity: the child's body twist
/// `q̇ = V = (ω, v)` in the child frame, so `S` is the identity (constant), `q̈ = V̇` and
/// `τ` is the wrench `(moment, force)` in the child frame. Pinocchio's free-flyer uses the same
/// velocity with the linear part first.
#[derive(Clone, Copy, Debug, Default)]
pub struct Free;

impl<T: Real> Joint<T> for Free {
    fn type_name(&self) -> &'static str {
        "free"
    }
    fn nq(&self) -> usize {
        6
    }
    fn nv(&self) -> usize {
        6
    }
    #[inline]
    fn transform(&self, q: &[T]) -> SE3<T> {
        SE3::new(
            exp_so3(&Vec3::new(q[0], q[1], q[2])),
            Vec3::new(q[3], q[4], q[5]),
        )
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], s: &mut [se3<T>]) {
        for (k, sk) in s.iter_mut().enumerate().take(6) {
            let mut a = [T::zero(); 6];
            a[k] = T::one();
            *sk = se3::from_array(a);
        }
    }
    fn describe(&self) -> JointDescription {
        JointDescription::new("free")
    }
}
