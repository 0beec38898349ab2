//! Revolute joint: rotation about a fixed axis through the joint-frame origin.

use super::{axis_f64, Joint};
use crate::algebra::{se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Rotation by `q` (rad) about the unit `axis` (joint frame) through the origin.
/// 1 DOF, screw axis `S = (axis, 0)`; `q̇` in rad/s, `τ` in N·m.
#[derive(Clone, Debug)]
pub struct Revolute<T: Real> {
    axis: Vec3<T>,
}

impl<T: Real> Revolute<T> {
    /// About `axis` (normalised here).
    pub fn new(axis: Vec3<T>) -> Self {
        let n = crate::algebra::dot(&axis, &axis).sqrt();
        Self {
            axis: crate::algebra::scale(T::one() / n, &axis),
        }
    }
}

impl<T: Real> Joint<T> for Revolute<T> {
    fn type_name(&self) -> &'static str {
        "revolute"
    }
    fn nq(&self) -> usize {
        1
    }
    fn nv(&self) -> usize {
        1
    }
    #[inline]
    fn transform(&self, q: &[T]) -> SE3<T> {
        SE3::from_axis_angle(&self.axis, q[0])
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], s: &mut [se3<T>]) {
        s[0] = se3::new(self.axis, Vec3::zeros());
    }
    fn describe(&self) -> JointDescription {
        JointDescription::with_axis("revolute", axis_f64(&self.axis))
    }
}
