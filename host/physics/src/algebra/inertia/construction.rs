//! Constructors of `Inertia`.

use super::Inertia;
use crate::algebra::{dot, scale, Sym3, Vec3};
use crate::Real;

impl<T: Real> Inertia<T> {
    /// From the raw parameters: mass (kg), first moment `m c` (kg·m), rotational inertia about
    /// the frame origin (kg·m²).
    #[inline]
    pub(crate) fn new(m: T, h: Vec3<T>, i: Sym3<T>) -> Self {
        Self { m, h, i }
    }

    /// From mass (kg), centre of mass `com` (m) and the rotational inertia about the centre of
    /// mass, in the frame's axes (kg·m²): `i = i_com + m (|c|² 1 − c cᵀ)`.
    pub fn from_com(m: T, com: Vec3<T>, i_com: Sym3<T>) -> Self {
        let h = scale(m, &com);
        let cc = dot(&com, &com);
        let shift = Sym3::new(
            m * (cc - com.x * com.x),
            m * (cc - com.y * com.y),
            m * (cc - com.z * com.z),
            -m * com.x * com.y,
            -m * com.x * com.z,
            -m * com.y * com.z,
        );
        Self::new(m, h, i_com + shift)
    }

    /// A point-like body of mass `m` (kg) at the origin with diagonal principal moments (kg·m²).
    pub(crate) fn diagonal(m: T, moments: Vec3<T>) -> Self {
        Self::new(m, Vec3::zeros(), Sym3::diagonal(&moments))
    }

    /// The zero inertia (a massless frame).
    pub fn zeros() -> Self {
        Self::new(T::zero(), Vec3::zeros(), Sym3::zeros())
    }

    /// Centre of mass `h / m` (m).
    pub(crate) fn com(&self) -> Vec3<T> {
        scale(T::one() / self.m, &self.h)
    }

    /// Rotational inertia about the centre of mass, in the frame's axes (kg·m²).
    pub(crate) fn i_com(&self) -> Sym3<T> {
        let c = self.com();
        let back = Inertia::from_com(self.m, c, Sym3::zeros());
        self.i - back.i
    }

    /// The 6×6 form as an [`AInertia`](crate::algebra::AInertia) (the cast `Inertia → AInertia` of Appendix B).
    #[inline]
    #[cfg(feature = "measure")]
    pub fn to_ainertia(&self) -> crate::algebra::AInertia<T> {
        crate::algebra::AInertia::from(*self)
    }
}
