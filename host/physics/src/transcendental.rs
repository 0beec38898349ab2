//! The transcendental functions the engine steps with, in one place.
//!
//! By default these are the standard library's (the platform's libm on the desktop). With
//! the `enhanced-determinism` feature they are the `libm` crate's, on every target, and
//! nalgebra's own elementary functions are forced onto the same crate
//! (`nalgebra/libm-force`): a desktop build and a `wasm32` build then step the same scene
//! bit for bit alike, as Rapier's feature of the same name does. Arithmetic itself
//! (`+ − × ÷ √`) is IEEE 754 on both and needs nothing.
//!
//! Everything in the crate and the game that moves a body calls these, never `f64::sin`
//! and its kin directly. Arguments in rad where they are angles.

/// The `libm` expression with `enhanced-determinism`, else the standard library's.
macro_rules! pick {
    ($libm:expr, $std:expr) => {{
        #[cfg(feature = "enhanced-determinism")]
        let r = $libm;
        #[cfg(not(feature = "enhanced-determinism"))]
        let r = $std;
        r
    }};
}

/// Sine of `x` (rad).
#[inline]
pub fn sin(x: f64) -> f64 {
    pick!(libm::sin(x), x.sin())
}

/// Cosine of `x` (rad).
#[inline]
pub fn cos(x: f64) -> f64 {
    pick!(libm::cos(x), x.cos())
}

/// Sine and cosine of `x` (rad), together.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    pick!(libm::sincos(x), x.sin_cos())
}

/// Four-quadrant arctangent of `y / x`, rad in `[−π, π]`.
#[inline]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    pick!(libm::atan2(y, x), y.atan2(x))
}

/// Natural logarithm of `x`.
#[inline]
pub(crate) fn ln(x: f64) -> f64 {
    pick!(libm::log(x), x.ln())
}

/// `x` to the power `y`.
#[inline]
pub(crate) fn powf(x: f64, y: f64) -> f64 {
    pick!(libm::pow(x, y), x.powf(y))
}

/// Hyperbolic tangent of `x`.
#[inline]
pub fn tanh(x: f64) -> f64 {
    pick!(libm::tanh(x), x.tanh())
}

/// `√(x² + y²)` without undue overflow.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    pick!(libm::hypot(x, y), x.hypot(y))
}

/// The `f32` functions of [`crate::Real`] for `f32`, chosen the same way.
pub(crate) mod single {
    /// Sine of `x` (rad).
    #[inline]
    pub(crate) fn sin(x: f32) -> f32 {
        pick!(libm::sinf(x), x.sin())
    }

    /// Cosine of `x` (rad).
    #[inline]
    pub(crate) fn cos(x: f32) -> f32 {
        pick!(libm::cosf(x), x.cos())
    }

    /// Sine and cosine of `x` (rad).
    #[inline]
    pub(crate) fn sin_cos(x: f32) -> (f32, f32) {
        pick!(libm::sincosf(x), x.sin_cos())
    }

    /// Four-quadrant arctangent of `y / x`, rad.
    #[inline]
    pub(crate) fn atan2(y: f32, x: f32) -> f32 {
        pick!(libm::atan2f(y, x), y.atan2(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each function against a value known in closed form, to the last few ulps (either
    /// implementation is faithful to well under that).
    #[test]
    fn the_functions_are_the_named_ones() {
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0);
        let pi = std::f64::consts::PI;
        assert!(close(sin(pi / 6.0), 0.5));
        assert!(close(cos(pi / 3.0), 0.5));
        let (s, c) = sin_cos(pi / 4.0);
        assert!(close(s, std::f64::consts::FRAC_1_SQRT_2) && close(c, s));
        assert!(close(atan2(1.0, -1.0), 0.75 * pi));
        assert!(close(ln(std::f64::consts::E), 1.0));
        assert!(close(powf(2.0, 10.0), 1024.0));
        assert!(close(
            tanh(0.5),
            (1.0 - (-1.0f64).exp()) / (1.0 + (-1.0f64).exp())
        ));
        assert!(close(hypot(3.0, 4.0), 5.0));
        assert!((single::sin(0.5) - 0.5f32.sin()).abs() < 1e-6);
        assert!((single::atan2(1.0, 1.0) - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
    }
}
