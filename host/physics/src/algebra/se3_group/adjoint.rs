//! Adjoint maps of `SE3` on twists and wrenches (Appendix B: `Ad`, `dAd`, and inverse forms).

use super::SE3;
use crate::algebra::{add, cross, dse3, mul_mtv, mul_mv, se3, sub};
use crate::Real;

impl<T: Real> SE3<T> {
    /// `Ad_T V = (R w, p × R w + R v)`: a twist in `b` coordinates re-expressed in `a`
    /// coordinates, `T = T_ab` — 24×, 18+.
    #[inline(always)]
    pub fn ad(&self, v: &se3<T>) -> se3<T> {
        let rw = mul_mv(&self.r, &v.w);
        let rv = mul_mv(&self.r, &v.v);
        se3::new(rw, add(&cross(&self.p, &rw), &rv))
    }

    /// `Ad_{T⁻¹} V = (Rᵀ w, Rᵀ (v − p × w))`: a twist in `a` coordinates re-expressed in `b`
    /// coordinates — 24×, 18+ (no inverse is formed).
    #[inline(always)]
    pub fn ad_inv(&self, v: &se3<T>) -> se3<T> {
        se3::new(
            mul_mtv(&self.r, &v.w),
            mul_mtv(&self.r, &sub(&v.v, &cross(&self.p, &v.w))),
        )
    }

    /// `dAd_T F = Ad_Tᵀ F = (Rᵀ (m − p × f), Rᵀ f)`: the dual of [`SE3::ad`],
    /// `⟨dAd_T F, V⟩ = ⟨F, Ad_T V⟩`; a wrench in `a` coordinates re-expressed in `b`
    /// coordinates — 24×, 18+.
    #[inline(always)]
    pub fn dad(&self, f: &dse3<T>) -> dse3<T> {
        dse3::new(
            mul_mtv(&self.r, &sub(&f.m, &cross(&self.p, &f.f))),
            mul_mtv(&self.r, &f.f),
        )
    }

    /// `dAd_{T⁻¹} F = Ad_{T⁻¹}ᵀ F = (R m + p × R f, R f)`: a wrench in `b` coordinates
    /// re-expressed in `a` coordinates (child → parent in Appendix A) — 24×, 18+.
    #[inline(always)]
    pub fn dad_inv(&self, f: &dse3<T>) -> dse3<T> {
        let rf = mul_mv(&self.r, &f.f);
        let rm = mul_mv(&self.r, &f.m);
        dse3::new(add(&rm, &cross(&self.p, &rf)), rf)
    }
}
