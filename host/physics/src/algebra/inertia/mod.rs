//! `Inertia`: the 10-parameter generalised inertia of a rigid body (paper §4.3).

mod construction;
mod ops;
mod xform;

use super::{Sym3, Vec3};
use crate::Real;

/// The generalised inertia `J` of a rigid body in a frame `b`, 10 scalars:
/// mass `m` (kg), first moment `h = m c` (kg·m, `c` the centre of mass in `b`), and the
/// rotational inertia `i` about `b`'s origin in `b` axes (kg·m²).
///
/// As a 6×6 map from twists `(w, v)` to momenta `(m, f)`:
/// `J = [[i, [h]], [[h]ᵀ, m 1]]`, i.e. `J V = (i w + h × v, m v − h × w)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia<T: Real> {
    /// Mass (kg).
    pub m: T,
    /// First moment of mass `m c` about the frame origin (kg·m).
    pub h: Vec3<T>,
    /// Rotational inertia about the frame origin (kg·m²).
    pub i: Sym3<T>,
}
