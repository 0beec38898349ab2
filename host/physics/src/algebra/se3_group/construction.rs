//! Constructors and conversions of `SE3`.

use super::SE3;
use crate::algebra::{Mat3, Vec3};
use crate::Real;

impl<T: Real> SE3<T> {
    /// From a rotation and a translation (m).
    #[inline]
    pub fn new(r: Mat3<T>, p: Vec3<T>) -> Self {
        Self { r, p }
    }

    /// The identity transform.
    #[inline]
    pub fn identity() -> Self {
        Self::new(Mat3::identity(), Vec3::zeros())
    }

    /// A pure translation (m).
    #[inline]
    pub fn from_translation(p: Vec3<T>) -> Self {
        Self::new(Mat3::identity(), p)
    }

    /// A pure rotation.
    #[inline]
    pub(crate) fn from_rotation(r: Mat3<T>) -> Self {
        Self::new(r, Vec3::zeros())
    }

    /// Rotation by `angle` (rad) about a unit `axis`, no translation (Rodrigues).
    pub(crate) fn from_axis_angle(axis: &Vec3<T>, angle: T) -> Self {
        Self::from_rotation(super::exp_log::rotation_about_unit_axis(axis, angle))
    }

    /// The 4×4 homogeneous matrix `[[r, p], [0, 1]]`.
    pub fn to_homogeneous(&self) -> nalgebra::Matrix4<T> {
        let mut m = nalgebra::Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.r);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.p);
        m
    }
}

impl<T: Real> Default for SE3<T> {
    fn default() -> Self {
        Self::identity()
    }
}
