//! A single rigid body, Eq. (3): `F = J V̇ − ad*_V J V`.
//!
//! `V` is the body velocity and `V̇` its time derivative, both in the body frame; `F` is the
//! total wrench on the body in the body frame; `J` the body's inertia in its frame. With
//! `ad*_V F = (m × w + f × v, f × w)` (Eq. 4) the gyroscopic term enters with a minus sign:
//! for a body at its centre of mass this is `τ = I ω̇ + ω × I ω`, `f = m (v̇ + ω × v)`.

use crate::algebra::{add, cross, dse3, scale, se3, sub, Inertia, Mat3, Sym3, Vec3};
use crate::Real;

/// Eq. (3): the wrench `F = J V̇ − ad*_V (J V)` (N·m, N) that gives the body acceleration `V̇`.
#[inline]
pub fn wrench<T: Real>(j: &Inertia<T>, v: &se3<T>, vdot: &se3<T>) -> dse3<T> {
    j.mul_twist(vdot) - v.dad(&j.mul_twist(v))
}

/// Eq. (3) solved for the acceleration: `V̇ = J⁻¹ (F + ad*_V (J V))`.
#[inline]
pub fn acceleration<T: Real>(j: &Inertia<T>, v: &se3<T>, f: &dse3<T>) -> se3<T> {
    solve(j, &(*f + v.dad(&j.mul_twist(v))))
}

/// `J⁻¹ F` for a body with positive mass and inertia, in block form:
/// `(I_o + [h][h]/m) w = m_F − h × f / m`, then `v = (f + h × w) / m`.
pub(crate) fn solve<T: Real>(j: &Inertia<T>, f: &dse3<T>) -> se3<T> {
    let minv = T::one() / j.m;
    let hc = Inertia::from_com(j.m, scale(minv, &j.h), Sym3::zeros());
    // Rotational inertia about the centre of mass (symmetric positive definite).
    let ic = (j.i - hc.i).to_matrix();
    let rhs = sub(&f.m, &scale(minv, &cross(&j.h, &f.f)));
    let w = solve3(&ic, &rhs);
    let v = scale(minv, &add(&f.f, &cross(&j.h, &w)));
    se3::new(w, v)
}

/// `A⁻¹ b` for a 3×3 matrix by the adjugate.
fn solve3<T: Real>(a: &Mat3<T>, b: &Vec3<T>) -> Vec3<T> {
    let c0 = Vec3::new(a[(0, 0)], a[(1, 0)], a[(2, 0)]);
    let c1 = Vec3::new(a[(0, 1)], a[(1, 1)], a[(2, 1)]);
    let c2 = Vec3::new(a[(0, 2)], a[(1, 2)], a[(2, 2)]);
    let r0 = cross(&c1, &c2);
    let r1 = cross(&c2, &c0);
    let r2 = cross(&c0, &c1);
    let det = crate::algebra::dot(&c0, &r0);
    let inv = T::one() / det;
    Vec3::new(
        inv * crate::algebra::dot(&r0, b),
        inv * crate::algebra::dot(&r1, b),
        inv * crate::algebra::dot(&r2, b),
    )
}
