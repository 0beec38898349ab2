//! The scalar trait the whole crate is generic over.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use num_traits::{One, Zero};

/// A real scalar: `f32`, `f64`, or the operation-counting scalar of `measure` (feature `measure`).
///
/// The bounds are exactly what nalgebra needs for its 3-vector / 3×3 arithmetic and for the
/// `Matrix6` baseline (`Scalar + Zero + One + ClosedAdd/Mul…`), plus the handful of elementary
/// functions the algebra uses. (nalgebra's `RealField` would drag in ~100 methods that a
/// counting type would have to forward; this trait keeps the counted code and the timed code
/// literally the same generic code.)
pub trait Real:
    nalgebra::Scalar
    + Copy
    + PartialOrd
    + Zero
    + One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Debug
    + Display
    + Send
    + Sync
    + 'static
{
    /// Converts an `f64` constant (exact for `f64`, rounded for `f32`).
    fn from_f64(x: f64) -> Self;
    /// The value as `f64`.
    fn to_f64(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine (argument in rad).
    fn sin(self) -> Self;
    /// Cosine (argument in rad).
    fn cos(self) -> Self;
    /// Sine and cosine together.
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// Four-quadrant arctangent of `self / x`, in rad.
    fn atan2(self, x: Self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Machine epsilon of the type.
    fn epsilon() -> Self;

    /// π.
    #[inline]
    fn pi() -> Self {
        Self::from_f64(core::f64::consts::PI)
    }
    /// The larger of two values.
    #[inline]
    fn max(self, o: Self) -> Self {
        if self > o {
            self
        } else {
            o
        }
    }
}

macro_rules! impl_real_float {
    ($t:ty, $($m:ident)::+) => {
        impl Real for $t {
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn sin(self) -> Self {
                $($m)::+::sin(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                $($m)::+::cos(self)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                $($m)::+::sin_cos(self)
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                $($m)::+::atan2(self, x)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn epsilon() -> Self {
                <$t>::EPSILON
            }
        }
    };
}

impl_real_float!(f32, crate::transcendental::single);
impl_real_float!(f64, crate::transcendental);
