//! Component-wise 3-vector and 3×3 kernels. Each states its operation count.

use super::{Mat3, Vec3};
use crate::Real;

/// `a · b` — 3×, 2+.
#[inline(always)]
pub(crate) fn dot<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// `a × b` — 6×, 3+.
#[inline(always)]
pub(crate) fn cross<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    Vec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// `a + b` — 3+.
#[inline(always)]
pub(crate) fn add<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    Vec3::new(a.x + b.x, a.y + b.y, a.z + b.z)
}

/// `a − b` — 3+.
#[inline(always)]
pub(crate) fn sub<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    Vec3::new(a.x - b.x, a.y - b.y, a.z - b.z)
}

/// `s a` — 3×.
#[inline(always)]
pub(crate) fn scale<T: Real>(s: T, a: &Vec3<T>) -> Vec3<T> {
    Vec3::new(s * a.x, s * a.y, s * a.z)
}

/// `−a` — sign flips only.
#[inline(always)]
pub(crate) fn neg<T: Real>(a: &Vec3<T>) -> Vec3<T> {
    Vec3::new(-a.x, -a.y, -a.z)
}

/// `R x` — 9×, 6+.
#[inline(always)]
pub(crate) fn mul_mv<T: Real>(r: &Mat3<T>, x: &Vec3<T>) -> Vec3<T> {
    Vec3::new(
        r[(0, 0)] * x.x + r[(0, 1)] * x.y + r[(0, 2)] * x.z,
        r[(1, 0)] * x.x + r[(1, 1)] * x.y + r[(1, 2)] * x.z,
        r[(2, 0)] * x.x + r[(2, 1)] * x.y + r[(2, 2)] * x.z,
    )
}

/// `Rᵀ x` — 9×, 6+.
#[inline(always)]
pub(crate) fn mul_mtv<T: Real>(r: &Mat3<T>, x: &Vec3<T>) -> Vec3<T> {
    Vec3::new(
        r[(0, 0)] * x.x + r[(1, 0)] * x.y + r[(2, 0)] * x.z,
        r[(0, 1)] * x.x + r[(1, 1)] * x.y + r[(2, 1)] * x.z,
        r[(0, 2)] * x.x + r[(1, 2)] * x.y + r[(2, 2)] * x.z,
    )
}

/// `A B` — 27×, 18+.
#[inline(always)]
pub(crate) fn mul_mm<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let c0 = mul_mv(a, &Vec3::new(b[(0, 0)], b[(1, 0)], b[(2, 0)]));
    let c1 = mul_mv(a, &Vec3::new(b[(0, 1)], b[(1, 1)], b[(2, 1)]));
    let c2 = mul_mv(a, &Vec3::new(b[(0, 2)], b[(1, 2)], b[(2, 2)]));
    Mat3::from_columns(&[c0, c1, c2])
}

/// `Aᵀ B` — 27×, 18+.
#[inline(always)]
pub(crate) fn mul_mtm<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let c0 = mul_mtv(a, &Vec3::new(b[(0, 0)], b[(1, 0)], b[(2, 0)]));
    let c1 = mul_mtv(a, &Vec3::new(b[(0, 1)], b[(1, 1)], b[(2, 1)]));
    let c2 = mul_mtv(a, &Vec3::new(b[(0, 2)], b[(1, 2)], b[(2, 2)]));
    Mat3::from_columns(&[c0, c1, c2])
}

/// `A Bᵀ` — 27×, 18+.
#[inline(always)]
pub(crate) fn mul_mmt<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    let c0 = mul_mv(a, &Vec3::new(b[(0, 0)], b[(0, 1)], b[(0, 2)]));
    let c1 = mul_mv(a, &Vec3::new(b[(1, 0)], b[(1, 1)], b[(1, 2)]));
    let c2 = mul_mv(a, &Vec3::new(b[(2, 0)], b[(2, 1)], b[(2, 2)]));
    Mat3::from_columns(&[c0, c1, c2])
}

/// `[a]`, the skew-symmetric matrix with `[a] x = a × x` — no arithmetic.
#[inline(always)]
pub(crate) fn skew<T: Real>(a: &Vec3<T>) -> Mat3<T> {
    let z = T::zero();
    Mat3::new(z, -a.z, a.y, a.z, z, -a.x, -a.y, a.x, z)
}

/// `vee(A − Aᵀ) / 2`-style axial vector without the halving: `(A32 − A23, A13 − A31, A21 − A12)` — 3+.
#[inline(always)]
pub(crate) fn vee_diff<T: Real>(a: &Mat3<T>) -> Vec3<T> {
    Vec3::new(
        a[(2, 1)] - a[(1, 2)],
        a[(0, 2)] - a[(2, 0)],
        a[(1, 0)] - a[(0, 1)],
    )
}
