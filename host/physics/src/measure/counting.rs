//! A scalar that counts its arithmetic.

// The operator impls bump counters with `+=`, which clippy would take for a typo.
#![allow(clippy::suspicious_arithmetic_impl)]

use crate::Real;
use core::cell::Cell;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use num_traits::{One, Zero};

/// Operation tallies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Multiplications.
    pub(crate) mul: u64,
    /// Additions and subtractions.
    pub(crate) add: u64,
    /// Divisions.
    pub(crate) div: u64,
    /// Square roots and trigonometric functions.
    pub(crate) func: u64,
}

thread_local! {
    static COUNTS: Cell<OpCounts> = const { Cell::new(OpCounts { mul: 0, add: 0, div: 0, func: 0 }) };
}

fn bump(f: impl FnOnce(&mut OpCounts)) {
    COUNTS.with(|c| {
        let mut v = c.get();
        f(&mut v);
        c.set(v);
    });
}

/// Runs `f` and returns its result with the operations [`Counted`] performed meanwhile
/// (on this thread).
pub fn count_ops<R>(f: impl FnOnce() -> R) -> (R, OpCounts) {
    let before = COUNTS.with(|c| c.get());
    let r = f();
    let after = COUNTS.with(|c| c.get());
    (
        r,
        OpCounts {
            mul: after.mul - before.mul,
            add: after.add - before.add,
            div: after.div - before.div,
            func: after.func - before.func,
        },
    )
}

/// An `f64` that counts the multiplications (`×`), additions and subtractions (`+`),
/// divisions and elementary functions performed on it.
///
/// Rules: negation and comparisons are free. A multiplication by the literal constant ±1 —
/// what nalgebra's generic `gemm`/`gemv` pass as α and β — is not counted, because compiled
/// `f64` code folds `x · 1.0` away exactly; every other operation counts, including additions
/// of zero (which the compiler cannot fold).
#[derive(Clone, Copy)]
pub struct Counted {
    v: f64,
    unit: bool,
}

impl Counted {
    /// Wraps a value (not a literal: its operations count).
    pub(crate) fn new(v: f64) -> Self {
        Self { v, unit: false }
    }

    /// The value.
    pub fn value(self) -> f64 {
        self.v
    }

    fn lit(v: f64) -> Self {
        Self {
            v,
            unit: v == 1.0 || v == -1.0,
        }
    }
}

impl fmt::Debug for Counted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.v, f)
    }
}

impl fmt::Display for Counted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.v, f)
    }
}

impl PartialEq for Counted {
    fn eq(&self, o: &Self) -> bool {
        self.v == o.v
    }
}

impl PartialOrd for Counted {
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        self.v.partial_cmp(&o.v)
    }
}

impl Add for Counted {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        bump(|c| c.add += 1);
        Self::new(self.v + o.v)
    }
}

impl Sub for Counted {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        bump(|c| c.add += 1);
        Self::new(self.v - o.v)
    }
}

impl Mul for Counted {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        if self.unit {
            return Self::new(self.v * o.v);
        }
        if o.unit {
            return Self::new(self.v * o.v);
        }
        bump(|c| c.mul += 1);
        Self::new(self.v * o.v)
    }
}

impl Div for Counted {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        bump(|c| c.div += 1);
        Self::new(self.v / o.v)
    }
}

impl Neg for Counted {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            unit: self.unit,
        }
    }
}

impl AddAssign for Counted {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Counted {
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl MulAssign for Counted {
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl DivAssign for Counted {
    fn div_assign(&mut self, o: Self) {
        *self = *self / o;
    }
}

impl Zero for Counted {
    fn zero() -> Self {
        Self::lit(0.0)
    }
    fn is_zero(&self) -> bool {
        self.v == 0.0
    }
}

impl One for Counted {
    fn one() -> Self {
        Self::lit(1.0)
    }
}

impl Real for Counted {
    fn from_f64(x: f64) -> Self {
        Self::lit(x)
    }
    fn to_f64(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        bump(|c| c.func += 1);
        Self::new(self.v.sqrt())
    }
    fn sin(self) -> Self {
        bump(|c| c.func += 1);
        Self::new(self.v.sin())
    }
    fn cos(self) -> Self {
        bump(|c| c.func += 1);
        Self::new(self.v.cos())
    }
    fn atan2(self, x: Self) -> Self {
        bump(|c| c.func += 1);
        Self::new(self.v.atan2(x.v))
    }
    fn abs(self) -> Self {
        Self::new(self.v.abs())
    }
    fn epsilon() -> Self {
        Self::lit(f64::EPSILON)
    }
}
