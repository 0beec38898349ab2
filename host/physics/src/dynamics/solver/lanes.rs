//! `Lanes`: [`WIDTH`] f64 values that every operation treats alike, so that a loop over four
//! independent contact constraints compiles to vector instructions (two SSE2 registers, or one
//! AVX2 register where [`super::contact_batch`] runs its AVX2 copy). Written as plain per-lane
//! loops for the compiler to vectorise; no `unsafe`, no intrinsics. Rust never fuses a multiply
//! and an add, so every lane computes bit for bit what the scalar code would.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// Number of lanes.
pub(crate) const WIDTH: usize = 4;

/// For each `$name = $features`, `unsafe fn $name(args) { $inner(args) }` compiled with those
/// target features (x86-64 only): the copies of an `#[inline(always)]` kernel for each
/// instruction set ([`KernelIsa`]). The caller must make sure the processor has the features.
macro_rules! compiled_for {
    (fn $args:tt => $inner:ident: $($name:ident = $features:literal),+ $(,)?) => {
        $(compiled_for!(@one $name, $features, $args, $inner);)+
    };
    (@one $name:ident, $features:literal, ($($arg:ident: $ty:ty),* $(,)?), $inner:ident) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $name($($arg: $ty),*) {
            $inner($($arg),*)
        }
    };
}
pub(crate) use compiled_for;

/// The instruction set the four-lane kernels (the contact groups' passes, the pose stage) are
/// compiled for, chosen once per process from what the processor offers. The kernels are the
/// same source in each: the lanes stay four f64 wide, and AVX-512 (with its VL extension)
/// brings its 32 vector registers to 256-bit code, where AVX2 has 16 and the group solve
/// spills the two bodies' velocities and motion to the stack (measured on towers-1120: the
/// solve's stack accesses 596 → 213 instructions, the step 10 % faster, the same bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum KernelIsa {
    /// SSE2 (every x86-64), or another architecture.
    Baseline,
    /// AVX2.
    #[cfg(target_arch = "x86_64")]
    Avx2,
    /// AVX2 with AVX-512F and AVX-512VL.
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl KernelIsa {
    /// The widest the processor runs, asked once per process.
    pub(crate) fn detect() -> Self {
        static ISA: std::sync::OnceLock<KernelIsa> = std::sync::OnceLock::new();
        *ISA.get_or_init(Self::ask)
    }

    fn ask() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl")
                && std::arch::is_x86_feature_detected!("avx2")
            {
                return Self::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Self::Avx2;
            }
        }
        Self::Baseline
    }

    /// Every instruction set the processor runs, the baseline first (the kernels' tests
    /// compare each copy with the scalar code).
    #[cfg(test)]
    pub(crate) fn available() -> Vec<Self> {
        let mut all = vec![Self::Baseline];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                all.push(Self::Avx2);
            }
            if Self::detect() == Self::Avx512 {
                all.push(Self::Avx512);
            }
        }
        all
    }
}

/// The [`Lanes`] whose lane `i` is the expression with `a` (and `b`) bound to lane `i` of the
/// operands. Written out in place rather than through a closure: a closure is inlined at the
/// compiler's judgement, not by `#[inline(always)]`, and how the contact kernels vectorised
/// then varied with the rest of the crate (measured: the AVX2 group solve took 1 399 or 1 700
/// instructions, and 25 % more time, depending on unrelated modules).
macro_rules! lanewise {
    ($x:expr, |$a:ident| $e:expr) => {{
        let mut r = [0.0; WIDTH];
        for (r, &$a) in r.iter_mut().zip(&$x.0) {
            *r = $e;
        }
        Lanes(r)
    }};
    ($x:expr, $y:expr, |$a:ident, $b:ident| $e:expr) => {{
        let mut r = [0.0; WIDTH];
        for ((r, &$a), &$b) in r.iter_mut().zip(&$x.0).zip(&$y.0) {
            *r = $e;
        }
        Lanes(r)
    }};
}

/// Four f64 values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct Lanes(pub [f64; WIDTH]);

/// A per-lane condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Mask([bool; WIDTH]);

impl Lanes {
    /// Every lane `x`.
    #[inline(always)]
    pub(crate) fn splat(x: f64) -> Self {
        Self([x; WIDTH])
    }

    /// Lane-wise maximum.
    #[inline(always)]
    pub(crate) fn max(self, o: Self) -> Self {
        lanewise!(self, o, |a, b| if a > b { a } else { b })
    }

    /// Lane-wise maximum as `f64::max` takes it (a NaN lane gives the other value). Unlike
    /// [`Lanes::max`], it never leaves a lane as it was, so updating a field in memory with it
    /// compiles to a plain store rather than a masked one (slow on some processors).
    #[inline(always)]
    pub(crate) fn max_num(self, o: Self) -> Self {
        lanewise!(self, o, |a, b| a.max(b))
    }

    /// Lane-wise minimum.
    #[inline(always)]
    pub(crate) fn min(self, o: Self) -> Self {
        lanewise!(self, o, |a, b| if a < b { a } else { b })
    }

    /// Lane-wise square root.
    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        lanewise!(self, |a| a.sqrt())
    }

    /// Lane-wise `self > o`.
    #[inline(always)]
    pub(crate) fn gt(self, o: Self) -> Mask {
        let mut m = [false; WIDTH];
        for ((m, a), b) in m.iter_mut().zip(self.0).zip(o.0) {
            *m = a > b;
        }
        Mask(m)
    }
}

impl Mask {
    /// Whether any lane's condition holds.
    #[inline(always)]
    pub(crate) fn any(self) -> bool {
        self.0.iter().any(|&m| m)
    }

    /// `a` where the condition holds, `b` elsewhere.
    #[inline(always)]
    pub(crate) fn select(self, a: Lanes, b: Lanes) -> Lanes {
        let mut r = [0.0; WIDTH];
        for (((r, m), a), b) in r.iter_mut().zip(self.0).zip(a.0).zip(b.0) {
            *r = if m { a } else { b };
        }
        Lanes(r)
    }
}

macro_rules! lanes_binop {
    ($trait:ident, $f:ident, $op:tt) => {
        impl $trait for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $f(self, o: Lanes) -> Lanes {
                lanewise!(self, o, |a, b| a $op b)
            }
        }
    };
}
lanes_binop!(Add, add, +);
lanes_binop!(Sub, sub, -);
lanes_binop!(Mul, mul, *);
lanes_binop!(Div, div, /);

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        lanewise!(self, |a| -a)
    }
}

/// A 3-vector per lane (structure of arrays).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LaneV3 {
    /// x of every lane.
    pub(crate) x: Lanes,
    /// y of every lane.
    pub(crate) y: Lanes,
    /// z of every lane.
    pub(crate) z: Lanes,
}

impl LaneV3 {
    /// Dot product per lane.
    #[inline(always)]
    pub(crate) fn dot(&self, o: &Self) -> Lanes {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product per lane.
    #[inline(always)]
    pub(crate) fn cross(&self, o: &Self) -> Self {
        Self {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Scaled by a value per lane.
    #[inline(always)]
    pub(crate) fn scale(&self, s: Lanes) -> Self {
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> [f64; 3] {
        [self.x.0[l], self.y.0[l], self.z.0[l]]
    }

    /// Sets lane `l`.
    #[inline(always)]
    pub(crate) fn set(&mut self, l: usize, v: [f64; 3]) {
        self.x.0[l] = v[0];
        self.y.0[l] = v[1];
        self.z.0[l] = v[2];
    }
}

impl Add for LaneV3 {
    type Output = LaneV3;
    #[inline(always)]
    fn add(self, o: LaneV3) -> LaneV3 {
        LaneV3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for LaneV3 {
    type Output = LaneV3;
    #[inline(always)]
    fn sub(self, o: LaneV3) -> LaneV3 {
        LaneV3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl AddAssign for LaneV3 {
    #[inline(always)]
    fn add_assign(&mut self, o: LaneV3) {
        *self = *self + o;
    }
}

impl SubAssign for LaneV3 {
    #[inline(always)]
    fn sub_assign(&mut self, o: LaneV3) {
        *self = *self - o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_compute_what_scalars_do() {
        let a = Lanes([1.0, -2.0, 3.5, 0.0]);
        let b = Lanes([0.5, 4.0, -1.0, 0.0]);
        assert_eq!((a + b).0, [1.5, 2.0, 2.5, 0.0]);
        assert_eq!((a * b - a).0, [-0.5, -6.0, -7.0, 0.0]);
        assert_eq!(a.max(b).0, [1.0, 4.0, 3.5, 0.0]);
        assert_eq!(a.min(b).0, [0.5, -2.0, -1.0, 0.0]);
        assert_eq!(a.gt(b).select(a, -b).0, [1.0, -4.0, 3.5, -0.0]);
        assert_eq!(a.max_num(b).0, [1.0, 4.0, 3.5, 0.0]);
        let nan = Lanes([f64::NAN, 1.0, 2.0, 3.0]);
        assert_eq!(nan.max_num(Lanes::splat(1.5)).0, [1.5, 1.5, 2.0, 3.0]);
        assert!(a.gt(b).any());
        assert!(!a.gt(Lanes::splat(10.0)).any());
        let u = LaneV3 {
            x: Lanes::splat(1.0),
            y: Lanes::splat(0.0),
            z: Lanes::splat(0.0),
        };
        let v = LaneV3 {
            x: Lanes::splat(0.0),
            y: a,
            z: Lanes::splat(0.0),
        };
        assert_eq!(u.cross(&v).z.0, a.0);
        assert_eq!(u.cross(&v).dot(&u.cross(&v)).0, (a * a).0);
    }
}
