//! Cylindrical joint: turn about and slide along one axis (the foosball rod).

use super::{axis_f64, Joint};
use crate::algebra::{scale, se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Rotation by `q[0]` (rad) about, and translation by `q[1]` (m) along, the unit `axis`
/// (joint frame). 2 DOF, screw axes `S = [(axis, 0), (0, axis)]` (they commute, so
/// `X_J = e^{S₀ q₀ + S₁ q₁}`); `τ = (torque N·m, force N)`.
#[derive(Clone, Debug)]
pub struct Cylindrical<T: Real> {
    axis: Vec3<T>,
}

impl<T: Real> Cylindrical<T> {
    /// About and along `axis` (normalised here).
    pub fn new(axis: Vec3<T>) -> Self {
        let n = crate::algebra::dot(&axis, &axis).sqrt();
        Self {
            axis: scale(T::one() / n, &axis),
        }
    }
}

impl<T: Real> Joint<T> for Cylindrical<T> {
    fn type_name(&self) -> &'static str {
        "cylindrical"
    }
    fn nq(&self) -> usize {
        2
    }
    fn nv(&self) -> usize {
        2
    }
    #[inline]
    fn transform(&self, q: &[T]) -> SE3<T> {
        let mut t = SE3::from_axis_angle(&self.axis, q[0]);
        t.p = scale(q[1], &self.axis);
        t
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], s: &mut [se3<T>]) {
        s[0] = se3::new(self.axis, Vec3::zeros());
        s[1] = se3::new(Vec3::zeros(), self.axis);
    }
    fn describe(&self) -> JointDescription {
        JointDescription::with_axis("cylindrical", axis_f64(&self.axis))
    }
}
