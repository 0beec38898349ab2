//! Exponential and logarithm of SE(3) and SO(3), exact near θ = 0 and θ = π.
//!
//! The closed forms lose precision where they divide small differences: near θ = 0 the
//! coefficients `(1 − cos θ)/θ²`, `(θ − sin θ)/θ³` and `(1 − (θ/2) cot(θ/2))/θ²` use their
//! Taylor series (truncated where the next term is below f64 rounding); near θ = π the
//! rotation axis of `Log` comes from the symmetric part of `R` instead of its skew part.

use super::SE3;
use std::ops::{Add, Mul, Sub};

use crate::algebra::{add, cross, dot, scale, se3, vee_diff, Mat3, Vec3};
use crate::Real;

/// θ² below which the series of the Exp coefficients are used (θ < 0.1).
pub(crate) const SERIES_THETA2: f64 = 1e-2;

/// The arithmetic of the Exp kernels below: `f64` (and the other [`Real`] types), and the
/// solver's four-lane values (`pipeline/pose_lanes.rs` moves four bodies at a time with the
/// same kernels, so each lane computes the scalar step's bits).
pub(crate) trait ExpArithmetic:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
{
}

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>> ExpArithmetic for T {}

/// `(A, B, C) = (sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³)` for `θ² = t2 <`
/// [`SERIES_THETA2`], by their alternating series (the first omitted terms are below 1e-19
/// for θ < 0.1); `c` makes a constant.
#[inline(always)]
pub(crate) fn exp_series<T: ExpArithmetic>(t2: T, c: impl Fn(f64) -> T) -> (T, T, T) {
    let a = c(1.0) - t2 * (c(1.0 / 6.0) - t2 * (c(1.0 / 120.0) - t2 * c(1.0 / 5040.0)));
    let b = c(0.5) - t2 * (c(1.0 / 24.0) - t2 * (c(1.0 / 720.0) - t2 * c(1.0 / 40320.0)));
    let cc = c(1.0 / 6.0) - t2 * (c(1.0 / 120.0) - t2 * (c(1.0 / 5040.0) - t2 * c(1.0 / 362880.0)));
    (a, b, cc)
}

/// The rows of `exp([w]) = I + A [w] + B [w]²` (with `[w]² = w wᵀ − θ² I`, `θ² = t2`).
#[inline(always)]
pub(crate) fn rotation_rows<T: ExpArithmetic>(w: [T; 3], t2: T, a: T, b: T, one: T) -> [[T; 3]; 3] {
    let d = one - b * t2; // cos θ
    let (ax, ay, az) = (a * w[0], a * w[1], a * w[2]);
    let (bxy, bxz, byz) = (b * w[0] * w[1], b * w[0] * w[2], b * w[1] * w[2]);
    [
        [d + b * w[0] * w[0], bxy - az, bxz + ay],
        [bxy + az, d + b * w[1] * w[1], byz - ax],
        [bxz - ay, byz + ax, d + b * w[2] * w[2]],
    ]
}

/// The translation of `Exp(w, v)`: `(I + B [w] + C [w]²) v`.
#[inline(always)]
pub(crate) fn exp_translation<T: ExpArithmetic>(w: [T; 3], v: [T; 3], b: T, cc: T) -> [T; 3] {
    let wv = cross_of(w, v);
    let wwv = cross_of(w, wv);
    // Written out: `array::map` and its closure are not inlined into the four-lane AVX2 copy.
    [
        v[0] + b * wv[0] + cc * wwv[0],
        v[1] + b * wv[1] + cc * wwv[1],
        v[2] + b * wv[2] + cc * wwv[2],
    ]
}

/// `a × x` — 6×, 3+ (as the kernels' `cross`, on arrays).
#[inline(always)]
fn cross_of<T: ExpArithmetic>(a: [T; 3], x: [T; 3]) -> [T; 3] {
    [
        a[1] * x[2] - a[2] * x[1],
        a[2] * x[0] - a[0] * x[2],
        a[0] * x[1] - a[1] * x[0],
    ]
}

/// `(A, B, C) = (sin θ/θ, (1 − cos θ)/θ², (θ − sin θ)/θ³)` for `θ² = t2`.
#[inline]
fn exp_coefficients<T: Real>(t2: T) -> (T, T, T) {
    let c = |x: f64| T::from_f64(x);
    if t2 < c(SERIES_THETA2) {
        exp_series(t2, c)
    } else {
        // One sin/cos pair of θ/2 gives all three without cancellation:
        // sin θ = 2 s c, 1 − cos θ = 2 s².
        let th = t2.sqrt();
        let (sh, ch) = (th * c(0.5)).sin_cos();
        let s = c(2.0) * sh * ch;
        let a = s / th;
        let b = c(2.0) * sh * sh / t2;
        let cc = (th - s) / (t2 * th);
        (a, b, cc)
    }
}

/// `R = exp([w]) = I + A [w] + B [w]²` with `[w]² = w wᵀ − θ² I`.
#[inline]
fn rotation_from_coefficients<T: Real>(w: &Vec3<T>, t2: T, a: T, b: T) -> Mat3<T> {
    let [r0, r1, r2] = rotation_rows([w.x, w.y, w.z], t2, a, b, T::one());
    Mat3::new(
        r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2],
    )
}

/// Rotation by `angle` (rad) about the unit vector `axis`.
pub(crate) fn rotation_about_unit_axis<T: Real>(axis: &Vec3<T>, angle: T) -> Mat3<T> {
    let (s, c) = angle.sin_cos();
    let t = T::one() - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    Mat3::new(
        c + t * x * x,
        t * x * y - s * z,
        t * x * z + s * y,
        t * x * y + s * z,
        c + t * y * y,
        t * y * z - s * x,
        t * x * z - s * y,
        t * y * z + s * x,
        c + t * z * z,
    )
}

/// `exp([w])` for exponential coordinates `w` (rad): the rotation by `|w|` about `w/|w|`.
pub fn exp_so3<T: Real>(w: &Vec3<T>) -> Mat3<T> {
    let t2 = dot(w, w);
    let (a, b, _) = exp_coefficients(t2);
    rotation_from_coefficients(w, t2, a, b)
}

/// `log(R)`: exponential coordinates `w` with `|w| = θ ∈ [0, π]` and `exp([w]) = R`.
/// At θ = π both `w` and `−w` are logarithms; the one returned is chosen by the sign of the
/// skew part where that is informative.
pub fn log_so3<T: Real>(r: &Mat3<T>) -> Vec3<T> {
    let c = |x: f64| T::from_f64(x);
    let s2 = vee_diff(r); // 2 sin θ · axis
    let sin2 = dot(&s2, &s2).sqrt(); // 2 sin θ
    let cos2 = r[(0, 0)] + r[(1, 1)] + r[(2, 2)] - T::one(); // 2 cos θ
    let theta = sin2.atan2(cos2);
    let t2 = theta * theta;
    if cos2 > c(0.0) {
        // θ < π/2: w = θ/(2 sin θ) · s2, with the series of θ/sin θ near 0.
        let k = if t2 < c(SERIES_THETA2) {
            c(0.5)
                * (c(1.0)
                    + t2 * (c(1.0 / 6.0)
                        + t2 * (c(7.0 / 360.0)
                            + t2 * (c(31.0 / 15120.0) + t2 * c(127.0 / 604800.0)))))
        } else {
            theta / sin2
        };
        scale(k, &s2)
    } else {
        // θ ≥ π/2: axis from the symmetric part, (R + Rᵀ)/2 − cos θ I = (1 − cos θ) a aᵀ.
        let cos = c(0.5) * cos2;
        let d = [r[(0, 0)] - cos, r[(1, 1)] - cos, r[(2, 2)] - cos];
        let k = if d[0] >= d[1] && d[0] >= d[2] {
            0
        } else if d[1] >= d[2] {
            1
        } else {
            2
        };
        let h = c(0.5);
        let mut col = Vec3::new(
            h * (r[(0, k)] + r[(k, 0)]),
            h * (r[(1, k)] + r[(k, 1)]),
            h * (r[(2, k)] + r[(k, 2)]),
        );
        col[k] = d[k];
        let mut n = dot(&col, &col).sqrt();
        if dot(&col, &s2) < T::zero() {
            n = -n;
        }
        scale(theta / n, &col)
    }
}

impl<T: Real> SE3<T> {
    /// `Exp(ξ)` of a twist `ξ = (w, v)` (w in rad, v in m):
    /// `R = exp([w])`, `p = (I + B [w] + C [w]²) v`.
    pub fn exp(xi: &se3<T>) -> Self {
        let w = &xi.w;
        let t2 = dot(w, w);
        let (a, b, cc) = exp_coefficients(t2);
        let r = rotation_from_coefficients(w, t2, a, b);
        let [x, y, z] = exp_translation([w.x, w.y, w.z], [xi.v.x, xi.v.y, xi.v.z], b, cc);
        Self::new(r, Vec3::new(x, y, z))
    }

    /// `Log(T)`: the twist `ξ = (w, v)` with `|w| ∈ [0, π]` and `Exp(ξ) = T`.
    /// `v = (I − ½[w] + D [w]²) p` with `D = (1 − (θ/2) cot(θ/2))/θ²`.
    pub fn log(&self) -> se3<T> {
        let c = |x: f64| T::from_f64(x);
        let w = log_so3(&self.r);
        let t2 = dot(&w, &w);
        let d = if t2 < c(SERIES_THETA2) {
            c(1.0 / 12.0)
                + t2 * (c(1.0 / 720.0) + t2 * (c(1.0 / 30240.0) + t2 * c(1.0 / 1209600.0)))
        } else {
            let th = t2.sqrt();
            let (sh, ch) = (th * c(0.5)).sin_cos();
            (c(1.0) - c(0.5) * th * ch / sh) / t2
        };
        let wp = cross(&w, &self.p);
        let wwp = cross(&w, &wp);
        let v = add(&add(&self.p, &scale(c(-0.5), &wp)), &scale(d, &wwp));
        se3::new(w, v)
    }
}
