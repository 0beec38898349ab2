//! Preallocated per-body and per-DOF storage for the recursive algorithms.

use super::DynamicsError;
use crate::algebra::{dse3, se3, AInertia, Inertia, SE3};
use crate::model::ArticulatedTree;
use crate::Real;

/// Scratch space sized for one model; reuse it across calls (no allocation per call).
#[derive(Clone, Debug)]
pub struct Workspace<T: Real> {
    pub(crate) nbodies: usize,
    pub(crate) ndofs: usize,
    /// `f_{λ(i),i}`: body frame in the parent frame.
    pub(crate) f: Vec<SE3<T>>,
    /// Body velocities `V_i`.
    pub(crate) v: Vec<se3<T>>,
    /// Velocity-product accelerations `c_i = ad_{V_i} S_i q̇_i + Ṡ_i q̇_i`.
    pub(crate) c: Vec<se3<T>>,
    /// Body accelerations `V̇_i`.
    pub(crate) a: Vec<se3<T>>,
    /// Articulated inertias `Ĵ_i`.
    pub(crate) jhat: Vec<AInertia<T>>,
    /// Composite rigid-body inertias (mass matrix).
    pub(crate) ic: Vec<Inertia<T>>,
    /// Bias wrenches `b_i` (ABA) or transmitted wrenches `F_i` (RNEA).
    pub(crate) b: Vec<dse3<T>>,
    /// Motion subspace columns `S`, one per DOF.
    pub(crate) s: Vec<se3<T>>,
    /// `U = Ĵ S`, one per DOF.
    pub(crate) u: Vec<dse3<T>>,
    /// `u = τ − Sᵀ(Ĵ c + b)`, one per DOF.
    pub(crate) uu: Vec<T>,
    /// `D⁻¹ = (Sᵀ Ĵ S)⁻¹`, `d²` entries per body at `dinv_offset`.
    pub(crate) dinv: Vec<T>,
    pub(crate) dinv_offset: Vec<usize>,
}

impl<T: Real> Workspace<T> {
    /// Storage for `model`.
    pub fn new(model: &ArticulatedTree<T>) -> Self {
        let n = model.len();
        let nv = model.nv();
        let mut dinv_offset = Vec::with_capacity(n);
        let mut off = 0;
        for b in model.bodies() {
            dinv_offset.push(off);
            off += b.nv() * b.nv();
        }
        Self {
            nbodies: n,
            ndofs: nv,
            f: vec![SE3::identity(); n],
            v: vec![se3::zeros(); n],
            c: vec![se3::zeros(); n],
            a: vec![se3::zeros(); n],
            jhat: vec![AInertia::zeros(); n],
            ic: vec![Inertia::zeros(); n],
            b: vec![dse3::zeros(); n],
            s: vec![se3::zeros(); nv],
            u: vec![dse3::zeros(); nv],
            uu: vec![T::zero(); nv],
            dinv: vec![T::zero(); off],
            dinv_offset,
        }
    }

    /// Body frames relative to their parents from the last call (`f_{λ(i),i}`).
    #[cfg_attr(not(feature = "measure"), allow(dead_code))]
    pub fn parent_transforms(&self) -> &[SE3<T>] {
        &self.f
    }

    /// Body velocities from the last call (body frames).
    #[cfg_attr(not(feature = "measure"), allow(dead_code))]
    pub fn velocities(&self) -> &[se3<T>] {
        &self.v
    }

    /// Body accelerations from the last call (body frames, gravity included as `V̇₀ = −g`).
    #[cfg_attr(not(feature = "measure"), allow(dead_code))]
    pub fn accelerations(&self) -> &[se3<T>] {
        &self.a
    }

    pub(crate) fn check(
        &self,
        model: &ArticulatedTree<T>,
        args: &[(&'static str, usize, usize)],
    ) -> Result<(), DynamicsError> {
        if self.nbodies != model.len() || self.ndofs != model.nv() {
            return Err(DynamicsError::Workspace {
                expected: self.nbodies,
                dofs: self.ndofs,
            });
        }
        for &(what, expected, got) in args {
            if expected != got {
                return Err(DynamicsError::Dimension {
                    what,
                    expected,
                    got,
                });
            }
        }
        Ok(())
    }
}
