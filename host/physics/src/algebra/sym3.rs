//! Symmetric 3×3 matrices stored as their 6 independent entries.

use super::{Mat3, Vec3};
use crate::Real;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A symmetric 3×3 matrix (6 scalars): rotational inertia blocks (kg·m²), the symmetric blocks
/// of the articulated inertia `AInertia`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sym3<T: Real> {
    /// Entry (0,0).
    pub xx: T,
    /// Entry (1,1).
    pub yy: T,
    /// Entry (2,2).
    pub zz: T,
    /// Entries (0,1) = (1,0).
    pub xy: T,
    /// Entries (0,2) = (2,0).
    pub xz: T,
    /// Entries (1,2) = (2,1).
    pub yz: T,
}

impl<T: Real> Sym3<T> {
    /// From the six entries.
    #[inline(always)]
    pub fn new(xx: T, yy: T, zz: T, xy: T, xz: T, yz: T) -> Self {
        Self {
            xx,
            yy,
            zz,
            xy,
            xz,
            yz,
        }
    }

    /// The zero matrix.
    #[inline(always)]
    pub(crate) fn zeros() -> Self {
        let z = T::zero();
        Self::new(z, z, z, z, z, z)
    }

    /// `s · 1`.
    #[inline(always)]
    pub(crate) fn scalar(s: T) -> Self {
        let z = T::zero();
        Self::new(s, s, s, z, z, z)
    }

    /// Diagonal matrix.
    #[inline(always)]
    pub fn diagonal(d: &Vec3<T>) -> Self {
        let z = T::zero();
        Self::new(d.x, d.y, d.z, z, z, z)
    }

    /// As a full nalgebra matrix.
    pub fn to_matrix(&self) -> Mat3<T> {
        Mat3::new(
            self.xx, self.xy, self.xz, self.xy, self.yy, self.yz, self.xz, self.yz, self.zz,
        )
    }

    /// `S x` — 9×, 6+.
    #[inline(always)]
    pub(crate) fn mul_vec(&self, x: &Vec3<T>) -> Vec3<T> {
        Vec3::new(
            self.xx * x.x + self.xy * x.y + self.xz * x.z,
            self.xy * x.x + self.yy * x.y + self.yz * x.z,
            self.xz * x.x + self.yz * x.y + self.zz * x.z,
        )
    }

    /// `Rᵀ S R` (S re-expressed in the frame whose axes are the columns of `R`) — 45×, 30+.
    #[inline(always)]
    pub(crate) fn congruence_t(&self, r: &Mat3<T>) -> Self {
        // A = S R (27×, 18+), then the upper triangle of Rᵀ A (18×, 12+).
        let c0 = self.mul_vec(&Vec3::new(r[(0, 0)], r[(1, 0)], r[(2, 0)]));
        let c1 = self.mul_vec(&Vec3::new(r[(0, 1)], r[(1, 1)], r[(2, 1)]));
        let c2 = self.mul_vec(&Vec3::new(r[(0, 2)], r[(1, 2)], r[(2, 2)]));
        let rc = |j: usize, c: &Vec3<T>| r[(0, j)] * c.x + r[(1, j)] * c.y + r[(2, j)] * c.z;
        Self::new(
            rc(0, &c0),
            rc(1, &c1),
            rc(2, &c2),
            rc(0, &c1),
            rc(0, &c2),
            rc(1, &c2),
        )
    }

    /// `R S Rᵀ` — 45×, 30+.
    #[inline(always)]
    pub fn congruence(&self, r: &Mat3<T>) -> Self {
        // A = S Rᵀ: column j of A is S times row j of R.
        let c0 = self.mul_vec(&Vec3::new(r[(0, 0)], r[(0, 1)], r[(0, 2)]));
        let c1 = self.mul_vec(&Vec3::new(r[(1, 0)], r[(1, 1)], r[(1, 2)]));
        let c2 = self.mul_vec(&Vec3::new(r[(2, 0)], r[(2, 1)], r[(2, 2)]));
        let rc = |j: usize, c: &Vec3<T>| r[(j, 0)] * c.x + r[(j, 1)] * c.y + r[(j, 2)] * c.z;
        Self::new(
            rc(0, &c0),
            rc(1, &c1),
            rc(2, &c2),
            rc(0, &c1),
            rc(0, &c2),
            rc(1, &c2),
        )
    }
}

impl<T: Real> Add for Sym3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(
            self.xx + o.xx,
            self.yy + o.yy,
            self.zz + o.zz,
            self.xy + o.xy,
            self.xz + o.xz,
            self.yz + o.yz,
        )
    }
}

impl<T: Real> Sub for Sym3<T> {
    type Output = Self;
    /// 6+.
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(
            self.xx - o.xx,
            self.yy - o.yy,
            self.zz - o.zz,
            self.xy - o.xy,
            self.xz - o.xz,
            self.yz - o.yz,
        )
    }
}

impl<T: Real> AddAssign for Sym3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> SubAssign for Sym3<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<T: Real> Neg for Sym3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.xx, -self.yy, -self.zz, -self.xy, -self.xz, -self.yz)
    }
}

impl<T: Real> Mul<T> for Sym3<T> {
    type Output = Self;
    /// 6×.
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        Self::new(
            self.xx * s,
            self.yy * s,
            self.zz * s,
            self.xy * s,
            self.xz * s,
            self.yz * s,
        )
    }
}
