//! Fixed joint: no motion (welds the child to the parent at the placement).

use super::Joint;
use crate::algebra::{se3, SE3};
use crate::model::joint_description::JointDescription;
use crate::Real;

/// No degree of freedom: `X_J = identity`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Fixed;

impl<T: Real> Joint<T> for Fixed {
    fn type_name(&self) -> &'static str {
        "fixed"
    }
    fn nq(&self) -> usize {
        0
    }
    fn nv(&self) -> usize {
        0
    }
    #[inline]
    fn transform(&self, _q: &[T]) -> SE3<T> {
        SE3::identity()
    }
    #[inline]
    fn motion_subspace(&self, _q: &[T], _s: &mut [se3<T>]) {}
    fn describe(&self) -> JointDescription {
        JointDescription::new("fixed")
    }
}
