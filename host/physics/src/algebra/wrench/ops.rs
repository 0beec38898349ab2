//! Vector-space operations, reciprocal and Kronecker products of `dse3`.

use super::dse3;
use crate::algebra::{add, dot, neg, scale, se3, sub, AInertia, Mat3, Sym3, Vec3};
use crate::Real;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

impl<T: Real> dse3<T> {
    /// From the moment and force parts.
    #[inline(always)]
    pub fn new(m: Vec3<T>, f: Vec3<T>) -> Self {
        Self { m, f }
    }

    /// The zero wrench.
    #[inline(always)]
    pub(crate) fn zeros() -> Self {
        Self::new(Vec3::zeros(), Vec3::zeros())
    }

    /// From six numbers `[mx, my, mz, fx, fy, fz]`.
    #[inline]
    pub fn from_array(a: [T; 6]) -> Self {
        Self::new(Vec3::new(a[0], a[1], a[2]), Vec3::new(a[3], a[4], a[5]))
    }

    /// As six numbers `[mx, my, mz, fx, fy, fz]`.
    #[inline]
    pub fn to_array(&self) -> [T; 6] {
        [self.m.x, self.m.y, self.m.z, self.f.x, self.f.y, self.f.z]
    }

    /// Reciprocal product `⟨F, V⟩ = m·w + f·v` (W) — 6×, 5+.
    #[inline(always)]
    pub fn dot(&self, v: &se3<T>) -> T {
        dot(&self.m, &v.w) + dot(&self.f, &v.v)
    }

    measure_pub_fn! {
        /// Kronecker product `F ⊗ G`, the symmetric 6×6 `½(F Gᵀ + G Fᵀ)` (equal to `F Fᵀ` when
        /// `G = F`) — 63×, 21+. For the rank-one update of Eq. (6) use [`dse3::kron_self`].
        fn kron(&self, g: &dse3<T>) -> AInertia<T> {
            let h = T::from_f64(0.5);
            let (a, b) = (self.to_array(), g.to_array());
            let e = |i: usize, j: usize| h * (a[i] * b[j] + b[i] * a[j]);
            AInertia::new(
                Sym3::new(e(0, 0), e(1, 1), e(2, 2), e(0, 1), e(0, 2), e(1, 2)),
                Mat3::new(
                    e(0, 3),
                    e(0, 4),
                    e(0, 5),
                    e(1, 3),
                    e(1, 4),
                    e(1, 5),
                    e(2, 3),
                    e(2, 4),
                    e(2, 5),
                ),
                Sym3::new(e(3, 3), e(4, 4), e(5, 5), e(3, 4), e(3, 5), e(4, 5)),
            )
        }
    }

    measure_pub_fn! {
        /// `s F ⊗ F = s F Fᵀ`, as `(s F) Fᵀ` on the 21 independent entries — 27×.
        #[inline(always)]
        fn kron_self(&self, s: T) -> AInertia<T> {
            let a = self.to_array();
            let sa = [s * a[0], s * a[1], s * a[2], s * a[3], s * a[4], s * a[5]];
            let e = |i: usize, j: usize| sa[i] * a[j];
            AInertia::new(
                Sym3::new(e(0, 0), e(1, 1), e(2, 2), e(0, 1), e(0, 2), e(1, 2)),
                Mat3::new(
                    e(0, 3),
                    e(0, 4),
                    e(0, 5),
                    e(1, 3),
                    e(1, 4),
                    e(1, 5),
                    e(2, 3),
                    e(2, 4),
                    e(2, 5),
                ),
                Sym3::new(e(3, 3), e(4, 4), e(5, 5), e(3, 4), e(3, 5), e(4, 5)),
            )
        }
    }
}

impl<T: Real> Default for dse3<T> {
    fn default() -> Self {
        Self::zeros()
    }
}

impl<T: Real> Add for dse3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        dse3::new(add(&self.m, &o.m), add(&self.f, &o.f))
    }
}

impl<T: Real> Sub for dse3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        dse3::new(sub(&self.m, &o.m), sub(&self.f, &o.f))
    }
}

impl<T: Real> AddAssign for dse3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> SubAssign for dse3<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<T: Real> Neg for dse3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        dse3::new(neg(&self.m), neg(&self.f))
    }
}

impl<T: Real> Mul<T> for dse3<T> {
    type Output = Self;
    /// Scalar product — 6×.
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        dse3::new(scale(s, &self.m), scale(s, &self.f))
    }
}

impl<T: Real> Mul<se3<T>> for dse3<T> {
    type Output = T;
    /// Reciprocal product `⟨F, V⟩` — 6×, 5+.
    #[inline(always)]
    fn mul(self, v: se3<T>) -> T {
        self.dot(&v)
    }
}

impl<T: Real> Mul<dse3<T>> for dse3<T> {
    type Output = AInertia<T>;
    /// Kronecker product `F ⊗ G` (`dse3::kron`).
    #[inline]
    fn mul(self, g: dse3<T>) -> AInertia<T> {
        self.kron(&g)
    }
}
