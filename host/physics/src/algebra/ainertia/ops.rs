//! Arithmetic of `AInertia`: products with twists, sums, scalar products, the cast from
//! `Inertia`, and the 6×6 matrix view.

use super::AInertia;
use crate::algebra::{add, mul_mtv, mul_mv, dse3, se3, skew, Inertia, Mat3, Sym3};
use crate::Real;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};
use nalgebra::Matrix6;

impl<T: Real> AInertia<T> {
    /// From the three blocks.
    #[inline(always)]
    pub fn new(a: Sym3<T>, b: Mat3<T>, c: Sym3<T>) -> Self {
        Self { a, b, c }
    }

    /// The zero articulated inertia.
    #[inline]
    pub fn zeros() -> Self {
        Self::new(Sym3::zeros(), Mat3::zeros(), Sym3::zeros())
    }

    /// `Ĵ V = (a w + b v, bᵀ w + c v)` — 36×, 30+.
    #[inline(always)]
    pub fn mul_twist(&self, v: &se3<T>) -> dse3<T> {
        dse3::new(
            add(&self.a.mul_vec(&v.w), &mul_mv(&self.b, &v.v)),
            add(&mul_mtv(&self.b, &v.w), &self.c.mul_vec(&v.v)),
        )
    }

    /// As a full 6×6 nalgebra matrix (twist `(w, v)` → wrench `(m, f)` ordering).
    pub fn to_matrix6(&self) -> Matrix6<T> {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.a.to_matrix());
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&self.b);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&self.b.transpose());
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.c.to_matrix());
        m
    }

    /// From a 6×6 matrix, taking its symmetric part.
    pub fn from_matrix6(m: &Matrix6<T>) -> Self {
        let h = T::from_f64(0.5);
        let a: Mat3<T> = m.fixed_view::<3, 3>(0, 0).into_owned();
        let c: Mat3<T> = m.fixed_view::<3, 3>(3, 3).into_owned();
        let b: Mat3<T> = m.fixed_view::<3, 3>(0, 3).into_owned();
        let bt: Mat3<T> = m.fixed_view::<3, 3>(3, 0).into_owned();
        let b = (b + bt.transpose()).map(|x| x * h);
        Self::new(Sym3::from_matrix(&a), b, Sym3::from_matrix(&c))
    }
}

impl<T: Real> From<Inertia<T>> for AInertia<T> {
    /// The cast `Inertia → AInertia`: `[[i, [h]], [[h]ᵀ, m 1]]` — no arithmetic.
    #[inline]
    fn from(j: Inertia<T>) -> Self {
        AInertia::new(j.i, skew(&j.h), Sym3::scalar(j.m))
    }
}

impl<T: Real> Mul<se3<T>> for AInertia<T> {
    type Output = dse3<T>;
    /// `Ĵ V` — 36×, 30+.
    #[inline(always)]
    fn mul(self, v: se3<T>) -> dse3<T> {
        self.mul_twist(&v)
    }
}

impl<T: Real> Mul<&se3<T>> for &AInertia<T> {
    type Output = dse3<T>;
    #[inline(always)]
    fn mul(self, v: &se3<T>) -> dse3<T> {
        self.mul_twist(v)
    }
}

impl<T: Real> Add for AInertia<T> {
    type Output = Self;
    /// 21+.
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        AInertia::new(self.a + o.a, self.b + o.b, self.c + o.c)
    }
}

impl<T: Real> Sub for AInertia<T> {
    type Output = Self;
    /// 21+.
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        AInertia::new(self.a - o.a, self.b - o.b, self.c - o.c)
    }
}

impl<T: Real> AddAssign for AInertia<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> SubAssign for AInertia<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<T: Real> Neg for AInertia<T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        AInertia::new(-self.a, -self.b, -self.c)
    }
}

impl<T: Real> Mul<T> for AInertia<T> {
    type Output = Self;
    /// Scalar product — 21×.
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        AInertia::new(self.a * s, self.b.map(|x| x * s), self.c * s)
    }
}

impl<T: Real> Add<AInertia<T>> for Inertia<T> {
    type Output = AInertia<T>;
    /// `J + Ĵ` (step 7 of Table 1): only the 10 parameters of `J` are added — 15+.
    #[inline(always)]
    fn add(self, o: AInertia<T>) -> AInertia<T> {
        let (h, b) = (&self.h, &o.b);
        let nb = Mat3::new(
            b[(0, 0)],
            b[(0, 1)] - h.z,
            b[(0, 2)] + h.y,
            b[(1, 0)] + h.z,
            b[(1, 1)],
            b[(1, 2)] - h.x,
            b[(2, 0)] - h.y,
            b[(2, 1)] + h.x,
            b[(2, 2)],
        );
        let c = Sym3::new(
            o.c.xx + self.m,
            o.c.yy + self.m,
            o.c.zz + self.m,
            o.c.xy,
            o.c.xz,
            o.c.yz,
        );
        AInertia::new(self.i + o.a, nb, c)
    }
}

impl<T: Real> Add<Inertia<T>> for AInertia<T> {
    type Output = AInertia<T>;
    /// `Ĵ + J` — 15+.
    #[inline(always)]
    fn add(self, j: Inertia<T>) -> AInertia<T> {
        j + self
    }
}
