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
        if !(d > T::zero()) {
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
pub fn cholesky_solve<T: Real>(a: &mut [T], n: usize, b: &mut [T]) -> Result<(), CholeskyError> {
    cholesky_in_place(a, n)?;
    cholesky_substitute(a, n, b);
    Ok(())
}

/// Inverts the symmetric positive-definite row-major `n×n` matrix `a` into `inv`
/// (`a` is overwritten by its factor).
pub(crate) fn spd_inverse<T: Real>(a: &mut [T], n: usize, inv: &mut [T]) -> Result<(), CholeskyError> {
    cholesky_in_place(a, n)?;
    for j in 0..n {
        let mut col = [T::zero(); 6];
        col[j] = T::one();
        cholesky_substitute(a, n, &mut col[..n]);
        for i in 0..n {
            inv[i * n + j] = col[i];
        }
    }
    Ok(())
}
