//! `dse3`: wrenches (generalised forces and momenta), the dual of `se3`.

mod ops;

use super::Vec3;
use crate::Real;

/// A wrench `F = (m, f)`, moment first (Appendix B "dse3 class"), 6 scalars.
///
/// As a force on body `b`: `m` is the moment about `b`'s origin (N·m) and `f` the force (N),
/// both in `b` coordinates. Also used for momenta (`J V`: kg·m²/s, kg·m/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct dse3<T: Real> {
    /// Moment part.
    pub m: Vec3<T>,
    /// Force part.
    pub f: Vec3<T>,
}
