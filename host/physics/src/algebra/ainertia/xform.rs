//! Change of frame of `AInertia` in block form: the rotation acts on 3×3 blocks, the
//! translation as skew products.

use super::AInertia;
use crate::algebra::{cross, mul_mm, mul_mmt, mul_mtm, neg, sub, Mat3, Sym3, Vec3, SE3};
use crate::Real;

/// `(x × d)_j` — 2×, 1+.
#[inline(always)]
fn cross_j<T: Real>(x: &Vec3<T>, d: &Vec3<T>, j: usize) -> T {
    match j {
        0 => x.y * d.z - x.z * d.y,
        1 => x.z * d.x - x.x * d.z,
        _ => x.x * d.y - x.y * d.x,
    }
}

impl<T: Real> AInertia<T> {
    /// Re-expresses about a new origin `d` (m, current axes), axes unchanged:
    /// `b' = b − [d] c`, `a' = a + b'[d] + (b[d])ᵀ` (= `a + b[d] − [d]bᵀ − [d]c[d]`) — 42×, 42+.
    #[inline(always)]
    fn shift(&self, d: &Vec3<T>) -> Self {
        let (b, c) = (&self.b, &self.c);
        // Columns of b − [d]c: b_j − d × c_j (18×, 18+).
        let cc = [
            Vec3::new(c.xx, c.xy, c.xz),
            Vec3::new(c.xy, c.yy, c.yz),
            Vec3::new(c.xz, c.yz, c.zz),
        ];
        let col = |j: usize| {
            sub(
                &Vec3::new(b[(0, j)], b[(1, j)], b[(2, j)]),
                &cross(d, &cc[j]),
            )
        };
        let nb = Mat3::from_columns(&[col(0), col(1), col(2)]);
        // Rows: (x[d]) has rows x_i × d.
        let row = |m: &Mat3<T>, i: usize| Vec3::new(m[(i, 0)], m[(i, 1)], m[(i, 2)]);
        let (nb0, nb1, nb2) = (row(&nb, 0), row(&nb, 1), row(&nb, 2));
        let (b0, b1, b2) = (row(b, 0), row(b, 1), row(b, 2));
        let a = &self.a;
        // a'_ij = a_ij + (nb_i × d)_j + (b_j × d)_i for i ≤ j (24×, 24+).
        let na = Sym3::new(
            a.xx + cross_j(&nb0, d, 0) + cross_j(&b0, d, 0),
            a.yy + cross_j(&nb1, d, 1) + cross_j(&b1, d, 1),
            a.zz + cross_j(&nb2, d, 2) + cross_j(&b2, d, 2),
            a.xy + cross_j(&nb0, d, 1) + cross_j(&b1, d, 0),
            a.xz + cross_j(&nb0, d, 2) + cross_j(&b2, d, 0),
            a.yz + cross_j(&nb1, d, 2) + cross_j(&b2, d, 1),
        );
        AInertia::new(na, nb, *c)
    }

    /// `Ĵ.Xform(T) = Ad_Tᵀ Ĵ Ad_T`: with `T = T_ab` and `Ĵ` in frame `a`, returns it in frame
    /// `b` — 186×, 138+.
    #[inline]
    pub fn xform(&self, t: &SE3<T>) -> Self {
        let s = self.shift(&t.p);
        AInertia::new(
            s.a.congruence_t(&t.r),
            mul_mm(&mul_mtm(&t.r, &s.b), &t.r),
            s.c.congruence_t(&t.r),
        )
    }

    /// `Ĵ.Xform(T⁻¹) = Ad_{T⁻¹}ᵀ Ĵ Ad_{T⁻¹}` without forming `T⁻¹`: with `T = T_ab` and `Ĵ` in
    /// frame `b`, returns it in frame `a` (child → parent, Eq. 6) — 186×, 138+.
    #[inline]
    pub fn xform_inv(&self, t: &SE3<T>) -> Self {
        let rotated = AInertia::new(
            self.a.congruence(&t.r),
            mul_mmt(&mul_mm(&t.r, &self.b), &t.r),
            self.c.congruence(&t.r),
        );
        rotated.shift(&neg(&t.p))
    }
}
