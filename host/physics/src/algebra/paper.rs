//! The Appendix B operations under the paper's own names, as free functions.
//! Each forwards to the method of the same meaning.

#![allow(non_snake_case)]

use super::{dse3, se3, SE3};
use crate::Real;

/// `Inv(T)`: see [`SE3::inverse`].
#[inline]
pub fn Inv<T: Real>(t: &SE3<T>) -> SE3<T> {
    t.inverse()
}

/// `Exp(ξ)`: see [`SE3::exp`].
#[inline]
pub fn Exp<T: Real>(xi: &se3<T>) -> SE3<T> {
    SE3::exp(xi)
}

/// `Log(T)`: see [`SE3::log`].
#[inline]
pub fn Log<T: Real>(t: &SE3<T>) -> se3<T> {
    t.log()
}

/// `Ad(T, V)`: see [`SE3::ad`].
#[inline]
pub fn Ad<T: Real>(t: &SE3<T>, v: &se3<T>) -> se3<T> {
    t.ad(v)
}

/// `Ad(Inv(T), V)` without the inverse: see [`SE3::ad_inv`].
#[inline]
pub fn InvAd<T: Real>(t: &SE3<T>, v: &se3<T>) -> se3<T> {
    t.ad_inv(v)
}

/// `dAd(T, F)`: see [`SE3::dad`].
#[inline]
pub fn dAd<T: Real>(t: &SE3<T>, f: &dse3<T>) -> dse3<T> {
    t.dad(f)
}

/// `dAd(Inv(T), F)` without the inverse: see [`SE3::dad_inv`].
#[inline]
pub fn InvdAd<T: Real>(t: &SE3<T>, f: &dse3<T>) -> dse3<T> {
    t.dad_inv(f)
}

/// `ad(V, W)`: see [`se3::ad`].
#[inline]
pub fn ad<T: Real>(v: &se3<T>, w: &se3<T>) -> se3<T> {
    v.ad(w)
}

/// `dad(V, F)`: see [`se3::dad`].
#[inline]
pub fn dad<T: Real>(v: &se3<T>, f: &dse3<T>) -> dse3<T> {
    v.dad(f)
}
