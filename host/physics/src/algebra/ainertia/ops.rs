//! Arithmetic of `AInertia`: products with twists, sums, scalar products, the cast from
//! `Inertia`, and the 6×6 matrix view.

use super::AInertia;
use crate::algebra::{add, dse3, mul_mtv, mul_mv, se3, skew, Inertia, Mat3, Sym3};
use crate::Real;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};
use nalgebra::Matrix6;

impl<T: Real> AInertia<T> {
    /// From the three blocks.
    #[inline(always)]
    pub(crate) fn new(a: Sym3<T>, b: Mat3<T>, c: Sym3<T>) -> Self {
        Self { a, b, c }
    }

    /// The zero articulated inertia.
    #[inline]
    pub(crate) fn zeros() -> Self {
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
    pub fn to_matrix6(self) -> Matrix6<T> {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&self.a.to_matrix());
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&self.b);
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&self.b.transpose());
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&self.c.to_matrix());
        m
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

impl<T: Real> AInertia<T> {
    /// `Ĵ − Σ_k U_k W_kᵀ` for wrenches with a symmetric sum (as `U D⁻¹ Uᵀ` with
    /// `W = D⁻¹ U`, the multi-DOF form of Eq. 6): only the 21 independent entries are
    /// formed — `21 d` ×, `21 d` +.
    pub(crate) fn sub_products(&self, u: &[dse3<T>], w: &[dse3<T>]) -> Self {
        let ua: [[T; 6]; 6] = core::array::from_fn(|k| {
            if k < u.len() {
                u[k].to_array()
            } else {
                [T::zero(); 6]
            }
        });
        let wa: [[T; 6]; 6] = core::array::from_fn(|k| {
            if k < w.len() {
                w[k].to_array()
            } else {
                [T::zero(); 6]
            }
        });
        let d = u.len().min(w.len());
        let e = |i: usize, j: usize| {
            let mut s = ua[0][i] * wa[0][j];
            for k in 1..d {
                s += ua[k][i] * wa[k][j];
            }
            s
        };
        let (a, b, c) = (&self.a, &self.b, &self.c);
        AInertia::new(
            Sym3::new(
                a.xx - e(0, 0),
                a.yy - e(1, 1),
                a.zz - e(2, 2),
                a.xy - e(0, 1),
                a.xz - e(0, 2),
                a.yz - e(1, 2),
            ),
            Mat3::new(
                b[(0, 0)] - e(0, 3),
                b[(0, 1)] - e(0, 4),
                b[(0, 2)] - e(0, 5),
                b[(1, 0)] - e(1, 3),
                b[(1, 1)] - e(1, 4),
                b[(1, 2)] - e(1, 5),
                b[(2, 0)] - e(2, 3),
                b[(2, 1)] - e(2, 4),
                b[(2, 2)] - e(2, 5),
            ),
            Sym3::new(
                c.xx - e(3, 3),
                c.yy - e(4, 4),
                c.zz - e(5, 5),
                c.xy - e(3, 4),
                c.xz - e(3, 5),
                c.yz - e(4, 5),
            ),
        )
    }
}
