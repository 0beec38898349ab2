//! Products of `Inertia`: momentum `J V`, sums, scalar products.

use super::Inertia;
use crate::algebra::{add, cross, dse3, scale, se3, sub};
use crate::Real;
use core::ops::{Add, Mul};

impl<T: Real> Inertia<T> {
    /// Generalised momentum `J V = (i w + h × v, m v − h × w)` — 24×, 18+.
    #[inline(always)]
    pub fn mul_twist(&self, v: &se3<T>) -> dse3<T> {
        dse3::new(
            add(&self.i.mul_vec(&v.w), &cross(&self.h, &v.v)),
            sub(&scale(self.m, &v.v), &cross(&self.h, &v.w)),
        )
    }
}

impl<T: Real> Mul<se3<T>> for Inertia<T> {
    type Output = dse3<T>;
    /// `J V` — 24×, 18+.
    #[inline(always)]
    fn mul(self, v: se3<T>) -> dse3<T> {
        self.mul_twist(&v)
    }
}

impl<T: Real> Mul<&se3<T>> for &Inertia<T> {
    type Output = dse3<T>;
    #[inline(always)]
    fn mul(self, v: &se3<T>) -> dse3<T> {
        self.mul_twist(v)
    }
}

impl<T: Real> Add for Inertia<T> {
    type Output = Self;
    /// Sum of two inertias in the same frame (composite body) — 10+.
    #[inline]
    fn add(self, o: Self) -> Self {
        Inertia::new(self.m + o.m, add(&self.h, &o.h), self.i + o.i)
    }
}

impl<T: Real> Mul<T> for Inertia<T> {
    type Output = Self;
    /// Scalar product — 10×.
    #[inline]
    fn mul(self, s: T) -> Self {
        Inertia::new(self.m * s, scale(s, &self.h), self.i * s)
    }
}
