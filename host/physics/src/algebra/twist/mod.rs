//! `se3`: twists (generalised velocities), the Lie algebra of SE(3).

mod ops;

use super::Vec3;
use crate::Real;

/// A twist `V = (w, v)`, angular part first (Appendix B "se3 class"), 6 scalars.
///
/// As a body velocity in frame `b`: `w` is the angular velocity (rad/s) and `v` the velocity of
/// the point at `b`'s origin (m/s), both in `b` coordinates. Also used for accelerations
/// (rad/s², m/s²), screw axes of joints (unitless / m per unit of joint coordinate) and
/// exponential coordinates of SE3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct se3<T: Real> {
    /// Angular part.
    pub w: Vec3<T>,
    /// Linear part.
    pub v: Vec3<T>,
}
