//! Ball (spherical) joint in exponential coordinates.

use super::Joint;
use crate::algebra::{exp_so3, se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Free rotation about the joint-frame origin. 3 DOF.
///
/// Configuration: exponential coordinates `q = r` (rad), `X_J = (exp([r]), 0)`.
/// Velocity: the child's angular velocity in the child frame, `q̇ = ω` (rad/s) — not `ṙ` —
/// so `S = [(e_x, 0), (e_y, 0), (e_z, 0)]` is constant and `q̈ = ω̇`, `τ` = moment (N·m).
/// This is exactly Pinocchio's spherical joint (which stores the rotation as a quaternion).
#[derive(Clone, Copy, Debug, Default)]
pub struct Ball;

impl<T: Real> Joint<T> for Ball {
    fn type_name(&self) -> &'static str {
        "ball"
    }
    fn nq(&self) -> usize {
        3
    }
    fn nv(&self) -> usize {
        3
    }
    #[inline]
    fn transform(&self, q: &[T]) -> SE3<T> {
        SE3::from_rotation(exp_so3(&Vec3::new(q[0], q[1], q[2])))
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], s: &mut [se3<T>]) {
        let (o, z) = (T::one(), T::zero());
        s[0] = se3::new(Vec3::new(o, z, z), Vec3::zeros());
        s[1] = se3::new(Vec3::new(z, o, z), Vec3::zeros());
        s[2] = se3::new(Vec3::new(z, z, o), Vec3::zeros());
    }
    fn describe(&self) -> JointDescription {
        JointDescription::new("ball")
    }
}
