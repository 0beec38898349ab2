//! `SE3`: rigid transforms (paper §4.3, Appendix B "SE3 class").

mod adjoint;
mod construction;
mod exp_log;
mod ops;

pub(crate) use exp_log::{exp_series, exp_translation, rotation_rows, SERIES_THETA2};
pub use exp_log::{exp_so3, log_so3};

use super::{Mat3, Vec3};
use crate::Real;

/// An element of the special Euclidean group SE(3): 12 scalars, rotation `r` and translation `p`.
///
/// Written `T_ab`, it is the pose of frame `b` relative to frame `a`: a point with coordinates
/// `x_b` in `b` has coordinates `x_a = r x_b + p` in `a` (p in m). The columns of `r` are `b`'s
/// axes in `a` coordinates. Composition follows frames: `T_ac = T_ab * T_bc`.
///
/// `r` must be a rotation matrix (orthonormal, det +1); the constructors and operations keep it so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SE3<T: Real> {
    /// Rotation: `b`'s axes in `a` coordinates.
    pub r: Mat3<T>,
    /// Translation: `b`'s origin in `a` coordinates (m).
    pub p: Vec3<T>,
}
