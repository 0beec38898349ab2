//! `AInertia`: articulated inertia, a symmetric 6×6 in block form (paper §4.3).

mod ops;
mod xform;

use super::{Mat3, Sym3};
use crate::Real;

/// An articulated-body inertia, the symmetric 6×6 `[[a, b], [bᵀ, c]]` mapping twists `(w, v)`
/// to wrenches `(m, f)`: `m = a w + b v`, `f = bᵀ w + c v`. 21 scalars (6 + 9 + 6).
/// Units: `a` kg·m², `b` kg·m, `c` kg; expressed in one body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AInertia<T: Real> {
    /// Angular–angular block (kg·m²).
    pub(crate) a: Sym3<T>,
    /// Angular–linear block (kg·m).
    pub(crate) b: Mat3<T>,
    /// Linear–linear block (kg).
    pub(crate) c: Sym3<T>,
}
