//! Prismatic joint: translation along a fixed axis.

use super::{axis_f64, Joint};
use crate::algebra::{scale, se3, Vec3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// Translation by `q` (m) along the unit `axis` (joint frame).
/// 1 DOF, screw axis `S = (0, axis)`; `q̇` in m/s, `τ` in N.
#[derive(Clone, Debug)]
pub struct Prismatic<T: Real> {
    axis: Vec3<T>,
}

impl<T: Real> Prismatic<T> {
    /// Along `axis` (normalised here).
    pub fn new(axis: Vec3<T>) -> Self {
        let n = crate::algebra::dot(&axis, &axis).sqrt();
        Self {
            axis: scale(T::one() / n, &axis),
        }
    }
}

impl<T: Real> Joint<T> for Prismatic<T> {
    fn type_name(&self) -> &'static str {
        "prismatic"
    }
    fn nq(&self) -> usize {
        1
    }
    fn nv(&self) -> usize {
        1
    }
    #[inline]
    fn transform(&self, q: &[T]) -> SE3<T> {
        SE3::from_translation(scale(q[0], &self.axis))
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], s: &mut [se3<T>]) {
        s[0] = se3::new(Vec3::zeros(), self.axis);
    }
    fn describe(&self) -> JointDescription {
        JointDescription::with_axis("prismatic", axis_f64(&self.axis))
    }
}
