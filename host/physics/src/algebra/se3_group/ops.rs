//! Group operations of `SE3`: composition, inverse, action on points.

use super::SE3;
use crate::algebra::{add, mul_mm, mul_mtv, mul_mv, neg, Vec3};
use crate::Real;
use core::ops::Mul;

impl<T: Real> SE3<T> {
    /// `T⁻¹ = (Rᵀ, −Rᵀ p)` — 9×, 6+.
    #[inline]
    pub fn inverse(&self) -> Self {
        Self::new(self.r.transpose(), neg(&mul_mtv(&self.r, &self.p)))
    }

    /// `T x = R x + p` for a point `x` (m) — 9×, 9+.
    #[inline]
    pub fn transform_point(&self, x: &Vec3<T>) -> Vec3<T> {
        add(&mul_mv(&self.r, x), &self.p)
    }
}

impl<T: Real> Mul for SE3<T> {
    type Output = SE3<T>;
    /// Composition `T_ac = T_ab * T_bc` — 36×, 27+.
    #[inline]
    fn mul(self, o: SE3<T>) -> SE3<T> {
        SE3::new(mul_mm(&self.r, &o.r), add(&mul_mv(&self.r, &o.p), &self.p))
    }
}

impl<T: Real> Mul<&SE3<T>> for &SE3<T> {
    type Output = SE3<T>;
    #[inline]
    fn mul(self, o: &SE3<T>) -> SE3<T> {
        *self * *o
    }
}
