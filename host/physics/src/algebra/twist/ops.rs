//! Vector-space and Lie-bracket operations of `se3`.

use super::se3;
use crate::algebra::{add, cross, dot, dse3, neg, scale, sub, Vec3};
use crate::Real;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

impl<T: Real> se3<T> {
    /// From the angular and linear parts.
    #[inline(always)]
    pub fn new(w: Vec3<T>, v: Vec3<T>) -> Self {
        Self { w, v }
    }

    /// The zero twist.
    #[inline(always)]
    pub(crate) fn zeros() -> Self {
        Self::new(Vec3::zeros(), Vec3::zeros())
    }

    /// From six numbers `[wx, wy, wz, vx, vy, vz]`.
    #[inline]
    pub fn from_array(a: [T; 6]) -> Self {
        Self::new(Vec3::new(a[0], a[1], a[2]), Vec3::new(a[3], a[4], a[5]))
    }

    /// As six numbers `[wx, wy, wz, vx, vy, vz]`.
    #[inline]
    pub fn to_array(&self) -> [T; 6] {
        [self.w.x, self.w.y, self.w.z, self.v.x, self.v.y, self.v.z]
    }

    /// `ad_self V = [self, V] = (w₁ × w₂, w₁ × v₂ + v₁ × w₂)` — 18×, 12+.
    #[inline(always)]
    pub fn ad(&self, o: &se3<T>) -> se3<T> {
        se3::new(
            cross(&self.w, &o.w),
            add(&cross(&self.w, &o.v), &cross(&self.v, &o.w)),
        )
    }

    /// `ad*_self F = ad_selfᵀ F = (m × w + f × v, f × w)` (Eq. 4) — 18×, 12+.
    #[inline(always)]
    pub fn dad(&self, f: &dse3<T>) -> dse3<T> {
        dse3::new(
            add(&cross(&f.m, &self.w), &cross(&f.f, &self.v)),
            cross(&f.f, &self.w),
        )
    }

    /// Reciprocal product `⟨V, F⟩ = w·m + v·f` (power, W) — 6×, 5+.
    #[inline(always)]
    pub fn dot(&self, f: &dse3<T>) -> T {
        dot(&self.w, &f.m) + dot(&self.v, &f.f)
    }
}

impl<T: Real> Default for se3<T> {
    fn default() -> Self {
        Self::zeros()
    }
}

impl<T: Real> Add for se3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        se3::new(add(&self.w, &o.w), add(&self.v, &o.v))
    }
}

impl<T: Real> Sub for se3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        se3::new(sub(&self.w, &o.w), sub(&self.v, &o.v))
    }
}

impl<T: Real> AddAssign for se3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> SubAssign for se3<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<T: Real> Neg for se3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        se3::new(neg(&self.w), neg(&self.v))
    }
}

impl<T: Real> Mul<T> for se3<T> {
    type Output = Self;
    /// Scalar product — 6×.
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        se3::new(scale(s, &self.w), scale(s, &self.v))
    }
}

impl<T: Real> Mul<dse3<T>> for se3<T> {
    type Output = T;
    /// Reciprocal product `⟨V, F⟩` — 6×, 5+.
    #[inline(always)]
    fn mul(self, f: dse3<T>) -> T {
        self.dot(&f)
    }
}
