//! Universal (Hooke) joint: two revolutions about intersecting axes.

use super::{axis_f64, Joint};
use crate::algebra::{cross, mul_mtv, scale, se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Rotation by `q[0]` about `axis1` (joint frame), then by `q[1]` about `axis2` (the
/// intermediate frame): `X_J = e^{S₁ q₁} e^{S₂ q₂}`. 2 DOF; the motion subspace depends on
/// `q₂`: `S = [(R₂ᵀ a₁, 0), (a₂, 0)]`, and `Ṡ q̇ = (q̇₁ q̇₂ (R₂ᵀ a₁) × a₂, 0)`.
#[derive(Clone, Debug)]
pub struct Universal<T: Real> {
    axis1: Vec3<T>,
    axis2: Vec3<T>,
}

impl<T: Real> Universal<T> {
    /// About `axis1` then `axis2` (both normalised here).
    pub fn new(axis1: Vec3<T>, axis2: Vec3<T>) -> Self {
        let unit = |a: &Vec3<T>| scale(T::one() / crate::algebra::dot(a, a).sqrt(), a);
        Self {
            axis1: unit(&axis1),
            axis2: unit(&axis2),
        }
    }

    fn first_axis_in_child(&self, q: &[T]) -> Vec3<T> {
        let r2 = SE3::from_axis_angle(&self.axis2, q[1]).r;
        mul_mtv(&r2, &self.axis1)
    }
}

impl<T: Real> Joint<T> for Universal<T> {
    fn type_name(&self) -> &'static str {
        "universal"
    }
    fn nq(&self) -> usize {
        2
    }
    fn nv(&self) -> usize {
        2
    }
    fn transform(&self, q: &[T]) -> SE3<T> {
        SE3::from_axis_angle(&self.axis1, q[0]) * SE3::from_axis_angle(&self.axis2, q[1])
    }
    fn motion_subspace(&self, q: &[T], s: &mut [se3<T>]) {
        s[0] = se3::new(self.first_axis_in_child(q), Vec3::zeros());
        s[1] = se3::new(self.axis2, Vec3::zeros());
    }
    fn bias(&self, q: &[T], qd: &[T]) -> se3<T> {
        let a1 = self.first_axis_in_child(q);
        se3::new(
            scale(qd[0] * qd[1], &cross(&a1, &self.axis2)),
            Vec3::zeros(),
        )
    }
    fn describe(&self) -> JointDescription {
        let mut d = JointDescription::with_axis("universal", axis_f64(&self.axis1));
        d.axis2 = Some(axis_f64(&self.axis2));
        d
    }
}
