//! The matrix-form baseline: the same operations as generic 6×6 matrix products with
//! nalgebra's `Matrix6` (spatial-algebra style, Eq. 5 and Eq. 7), generic over the scalar so
//! that they are counted and timed exactly like the geometric form.

use crate::algebra::{se3, skew, AInertia, Inertia, Mat3, SE3};
use crate::Real;
use nalgebra::{Matrix6, Vector6};

/// A twist or wrench as a 6-vector (angular / moment part first).
pub fn vec6_of_twist<T: Real>(v: &se3<T>) -> Vector6<T> {
    Vector6::from_column_slice(&v.to_array())
}

fn blocks<T: Real>(a: &Mat3<T>, b: &Mat3<T>, c: &Mat3<T>, d: &Mat3<T>) -> Matrix6<T> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(a);
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(b);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(c);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(d);
    m
}

/// The 6×6 adjoint matrix `Ad_T = [[R, 0], [[p]R, R]]` (builds `[p] R` with a 3×3 product).
pub fn ad_matrix<T: Real>(t: &SE3<T>) -> Matrix6<T> {
    let pr = skew(&t.p) * t.r;
    blocks(&t.r, &Mat3::zeros(), &pr, &t.r)
}

/// The 6×6 matrix of `Ad_{T⁻¹} = [[Rᵀ, 0], [−Rᵀ[p], Rᵀ]]` (Featherstone's `ᵢX_{i−1}`).
pub(crate) fn ad_inv_matrix<T: Real>(t: &SE3<T>) -> Matrix6<T> {
    let rt = t.r.transpose();
    let rp = -(rt * skew(&t.p));
    blocks(&rt, &Mat3::zeros(), &rp, &rt)
}

/// The 6×6 matrix of `ad_V = [[[w], 0], [[v], [w]]]` (no arithmetic to build).
pub(crate) fn small_ad_matrix<T: Real>(v: &se3<T>) -> Matrix6<T> {
    let w = skew(&v.w);
    blocks(&w, &Mat3::zeros(), &skew(&v.v), &w)
}

/// The 6×6 matrix of an inertia.
pub fn inertia_matrix<T: Real>(j: &Inertia<T>) -> Matrix6<T> {
    AInertia::from(*j).to_matrix6()
}

/// `Ad_T V` as `Ad_T` (built from `T`) times `V`.
pub fn ad<T: Real>(t: &SE3<T>, v: &Vector6<T>) -> Vector6<T> {
    ad_matrix(t) * v
}

/// `ad_V W` as the matrix of `ad_V` times `W`.
pub fn lie_ad<T: Real>(v: &se3<T>, w: &Vector6<T>) -> Vector6<T> {
    small_ad_matrix(v) * w
}

/// `J V` with `J` stored as a 6×6 matrix.
pub fn inertia_mul<T: Real>(j: &Matrix6<T>, v: &Vector6<T>) -> Vector6<T> {
    j * v
}

/// `Ad_Tᵀ J Ad_T` with `Ad_T` built from `T` (both `Inertia.Xform` and `AInertia.Xform`
/// are this product in matrix form).
pub fn xform<T: Real>(j: &Matrix6<T>, t: &SE3<T>) -> Matrix6<T> {
    let x = ad_matrix(t);
    x.transpose() * j * x
}

/// One step of Eq. (7): `I_{i−1} + Xᵀ (I^A − I^A S Sᵀ I^A / (Sᵀ I^A S)) X` with
/// `X = Ad_{f⁻¹}` built from `f = f_{i−1,i}`.
pub fn eq7_step<T: Real>(
    i_parent: &Matrix6<T>,
    ia: &Matrix6<T>,
    s: &Vector6<T>,
    f: &SE3<T>,
) -> Matrix6<T> {
    let u = ia * s;
    let d = s.dot(&u);
    let x = ad_inv_matrix(f);
    i_parent + x.transpose() * (ia - u * u.transpose() * (T::one() / d)) * x
}
