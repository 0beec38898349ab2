//! Small dense symmetric positive-definite solves (joint-space matrices).

use crate::Real;
use thiserror::Error;

/// A matrix that is not (numerically) positive definite.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("matrix is not positive definite (pivot {0})")]
pub struct CholeskyError(pub usize);

/// In place Cholesky factorisation `A = L Lᵀ` of the row-major `n×n` matrix `a`
/// (lower triangle overwritten with `L`).
pub(crate) fn cholesky_in_place<T: Real>(a: &mut [T], n: usize) -> Result<(), CholeskyError> {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.partial_cmp(&T::zero()) != Some(core::cmp::Ordering::Greater) {
            return Err(CholeskyError(j));
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ x = b` in place given the factor from [`cholesky_in_place`].
pub(crate) fn cholesky_substitute<T: Real>(l: &[T], n: usize, x: &mut [T]) {
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i * n + k] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
}

/// Solves `A x = b` for a symmetric positive-definite row-major `n×n` matrix `a`
/// (overwritten by its factor); `b` is overwritten by `x`.
#[cfg_attr(not(feature = "measure"), allow(dead_code))]
pub fn cholesky_solve<T: Real>(a: &mut [T], n: usize, b: &mut [T]) -> Result<(), CholeskyError> {
    cholesky_in_place(a, n)?;
    cholesky_substitute(a, n, b);
    Ok(())
}

/// Inverts the symmetric positive-definite row-major `n×n` matrix `a` into `inv`
/// (`a` is overwritten by its factor).
pub fn spd_inverse<T: Real>(a: &mut [T], n: usize, inv: &mut [T]) -> Result<(), CholeskyError> {
    if n == 2 {
        return spd_inverse2(a, inv);
    }
    if n == 3 {
        return spd_inverse3(a, inv);
    }
    cholesky_in_place(a, n)?;
    // Column j of the inverse solved into row j, then the whole transposed into place.
    for j in 0..n {
        let col = &mut inv[j * n..(j + 1) * n];
        col.fill(T::zero());
        col[j] = T::one();
        cholesky_substitute(a, n, col);
    }
    for i in 0..n {
        for j in i + 1..n {
            inv.swap(i * n + j, j * n + i);
        }
    }
    Ok(())
}

/// Closed-form inverse of a symmetric positive-definite 2×2, with Sylvester's test.
fn spd_inverse2<T: Real>(a: &[T], inv: &mut [T]) -> Result<(), CholeskyError> {
    let (a00, a01, a11) = (a[0], a[1], a[3]);
    let det = a00 * a11 - a01 * a01;
    if !(a00 > T::zero() && det > T::zero()) {
        return Err(CholeskyError(0));
    }
    let r = T::one() / det;
    inv[0] = a11 * r;
    inv[1] = -a01 * r;
    inv[2] = inv[1];
    inv[3] = a00 * r;
    Ok(())
}

/// Closed-form inverse of a symmetric positive-definite 3×3 (adjugate / determinant), with
/// the positive-definiteness test of Sylvester's criterion.
fn spd_inverse3<T: Real>(a: &[T], inv: &mut [T]) -> Result<(), CholeskyError> {
    let (a00, a01, a02, a11, a12, a22) = (a[0], a[1], a[2], a[4], a[5], a[8]);
    let c00 = a11 * a22 - a12 * a12;
    let c01 = a02 * a12 - a01 * a22;
    let c02 = a01 * a12 - a02 * a11;
    let det = a00 * c00 + a01 * c01 + a02 * c02;
    let pd = a00 > T::zero() && a00 * a11 - a01 * a01 > T::zero() && det > T::zero();
    if !pd {
        return Err(CholeskyError(0));
    }
    let r = T::one() / det;
    let c11 = a00 * a22 - a02 * a02;
    let c12 = a01 * a02 - a00 * a12;
    let c22 = a00 * a11 - a01 * a01;
    inv[0] = c00 * r;
    inv[1] = c01 * r;
    inv[2] = c02 * r;
    inv[3] = inv[1];
    inv[4] = c11 * r;
    inv[5] = c12 * r;
    inv[6] = inv[2];
    inv[7] = inv[5];
    inv[8] = c22 * r;
    Ok(())
}
