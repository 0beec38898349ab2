//! Joints: one type per file, all behind the [`Joint`] trait.
//!
//! A joint gives the motion `X_J(q)` of its child frame relative to the joint frame (fixed in
//! the parent), `X_J = e^{S q}` for joints whose screw axes commute, and the motion subspace
//! `S(q)` (one twist per degree of freedom, in the child frame) such that the joint's
//! contribution to the child's body velocity is `S(q) q̇`. At `q = 0` the child frame
//! coincides with the joint frame, so `S(0)` are the screw axes in the parent-fixed joint frame.
//!
//! A new joint type is one new file implementing [`Joint`]; to load it from a JSON
//! description, add its `type` name to `from_description`.

mod ball;
mod cylindrical;
mod fixed;
mod free;
mod prismatic;
mod revolute;
mod universal;

pub use ball::Ball;
pub use cylindrical::Cylindrical;
pub use fixed::Fixed;
pub use free::Free;
pub use prismatic::Prismatic;
pub use revolute::Revolute;
pub use universal::Universal;

use super::joint_description::JointDescription;
use super::ModelError;
use crate::algebra::{se3, Vec3, SE3};
use crate::Real;

/// A boxed copy of a joint, so that a tree (and a world) can be cloned whole: implemented
/// for every joint that is `Clone`.
pub trait JointClone<T: Real> {
    /// The joint, copied into a new box.
    fn clone_box(&self) -> Box<dyn Joint<T>>;
}

impl<T: Real, J: Joint<T> + Clone + 'static> JointClone<T> for J {
    fn clone_box(&self) -> Box<dyn Joint<T>> {
        Box::new(self.clone())
    }
}

impl<T: Real> Clone for Box<dyn Joint<T>> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// A joint between a parent frame and a child body.
pub trait Joint<T: Real>: JointClone<T> + core::fmt::Debug + Send + Sync {
    /// The type name used in JSON descriptions (`"revolute"`, …).
    fn type_name(&self) -> &'static str;

    /// Number of configuration coordinates.
    fn nq(&self) -> usize;

    /// Degrees of freedom (number of velocity coordinates).
    fn nv(&self) -> usize;

    /// The exponential map `X_J(q)`: pose of the child frame in the joint frame.
    fn transform(&self, q: &[T]) -> SE3<T>;

    /// Writes the `nv` columns of the motion subspace `S(q)` (child frame) into `s`.
    fn motion_subspace(&self, q: &[T], s: &mut [se3<T>]);

    /// `Ṡ(q, q̇) q̇` in the child frame: the part of the joint's velocity-product acceleration
    /// that comes from `S` changing with `q`. Zero for joints with a constant `S` (default).
    fn bias(&self, _q: &[T], _qd: &[T]) -> se3<T> {
        se3::zeros()
    }

    /// The neutral configuration (default: all zeros).
    fn neutral(&self, q: &mut [T]) {
        q.iter_mut().for_each(|x| *x = T::zero());
    }

    /// Transform, motion subspace and bias in one call (what the recursive algorithms use).
    fn kinematics(&self, q: &[T], qd: &[T], s: &mut [se3<T>]) -> (SE3<T>, se3<T>) {
        self.motion_subspace(q, s);
        (self.transform(q), self.bias(q, qd))
    }

    /// The joint's description (for JSON).
    fn describe(&self) -> JointDescription;
}

/// Builds a joint from its description. Known types: `revolute`, `prismatic`, `cylindrical`,
/// `universal` (need `axis`, universal also `axis2`), `ball`, `free`, `fixed`.
pub(crate) fn from_description<T: Real>(
    d: &JointDescription,
) -> Result<Box<dyn Joint<T>>, ModelError> {
    let axis = |a: Option<[f64; 3]>| -> Result<Vec3<T>, ModelError> {
        let a = a.ok_or(ModelError::InvalidAxis([0.0; 3]))?;
        unit_axis(a)
    };
    Ok(match d.kind.as_str() {
        "revolute" => Box::new(Revolute::new(axis(d.axis)?)),
        "prismatic" => Box::new(Prismatic::new(axis(d.axis)?)),
        "cylindrical" => Box::new(Cylindrical::new(axis(d.axis)?)),
        "universal" => Box::new(Universal::new(axis(d.axis)?, axis(d.axis2)?)),
        "ball" => Box::new(Ball),
        "free" => Box::new(Free),
        "fixed" => Box::new(Fixed),
        other => {
            return Err(ModelError::UnknownJoint(other.to_string()));
        }
    })
}

/// Normalises an axis given as three `f64`.
pub(crate) fn unit_axis<T: Real>(a: [f64; 3]) -> Result<Vec3<T>, ModelError> {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if !(n.is_finite() && n > 0.0) {
        return Err(ModelError::InvalidAxis(a));
    }
    Ok(Vec3::new(
        T::from_f64(a[0] / n),
        T::from_f64(a[1] / n),
        T::from_f64(a[2] / n),
    ))
}

/// An axis as three `f64`.
pub(crate) fn axis_f64<T: Real>(a: &Vec3<T>) -> [f64; 3] {
    [a.x.to_f64(), a.y.to_f64(), a.z.to_f64()]
}
