//! The joint types of joints between free bodies: the model's joint types (`model::joints`),
//! read from a [`Joint`] through its type name and its motion subspace `S(0)` at the joint
//! frame. The directions a joint leaves free are the columns of `S(0)`; the solver
//! constrains their complement.

use crate::geometry::V3;
use crate::model::Joint;

/// A model joint as a joint between two free bodies, with its axes in the joint frame
/// (unit vectors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FreeJointKind {
    /// One rotation about `axis` (coordinate: angle, rad). Constrains 3 linear + 2 angular
    /// directions.
    Revolute {
        /// Hinge axis, joint frame (unit).
        axis: V3,
    },
    /// One translation along `axis` (coordinate: slide, m). Constrains 3 angular + 2 linear
    /// directions.
    Prismatic {
        /// Slide axis, joint frame (unit).
        axis: V3,
    },
    /// Rotation about and translation along `axis` (coordinates: angle rad, slide m).
    /// Constrains 2 linear + 2 angular directions.
    Cylindrical {
        /// Axis, joint frame (unit).
        axis: V3,
    },
    /// Rotation about `axis1` (fixed in body A's joint frame), then about `axis2` (fixed in
    /// body B's) (coordinates: the two angles, rad). Constrains 3 linear + 1 angular
    /// direction.
    Universal {
        /// First axis, joint frame of A (unit).
        axis1: V3,
        /// Second axis, joint frame of B at the start (unit, not parallel to `axis1`).
        axis2: V3,
    },
    /// Free rotation about the anchor (3 rotational degrees of freedom, no coordinates the
    /// drives act on). Constrains 3 linear directions.
    Ball,
    /// No constraint (6 degrees of freedom): the two bodies only stop touching each other.
    Free,
    /// No relative motion. Constrains all 6 directions.
    Fixed,
}

/// Why a model joint cannot join two free bodies.
#[derive(Clone, Debug, PartialEq)]
pub enum JointKindError {
    /// A joint type this solver does not know (its type name).
    Unsupported(String),
    /// An axis of the joint's motion subspace is zero or not finite.
    ZeroAxis,
    /// A universal joint's two axes are parallel.
    ParallelAxes,
}

impl core::fmt::Display for JointKindError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Unsupported(t) => write!(
                f,
                "joint type '{t}' cannot join free bodies (revolute, prismatic, cylindrical, universal, ball, free, fixed)"
            ),
            Self::ZeroAxis => write!(f, "a joint axis is zero or not finite"),
            Self::ParallelAxes => write!(f, "a universal joint's two axes are parallel"),
        }
    }
}

fn unit(a: V3) -> Result<V3, JointKindError> {
    let n = a.norm();
    if !(n.is_finite() && n > 1e-9) {
        return Err(JointKindError::ZeroAxis);
    }
    Ok(a / n)
}

impl FreeJointKind {
    /// The kind of a model joint, its axes read from `S(q₀)` at the neutral configuration.
    pub(crate) fn from_joint(joint: &dyn Joint<f64>) -> Result<Self, JointKindError> {
        let nv = joint.nv();
        let mut q = vec![0.0; joint.nq()];
        joint.neutral(&mut q);
        let mut s = vec![crate::algebra::se3::zeros(); nv];
        joint.motion_subspace(&q, &mut s);
        Ok(match (joint.type_name(), nv) {
            ("revolute", 1) => Self::Revolute {
                axis: unit(s[0].w)?,
            },
            ("prismatic", 1) => Self::Prismatic {
                axis: unit(s[0].v)?,
            },
            ("cylindrical", 2) => Self::Cylindrical {
                axis: unit(s[0].w)?,
            },
            ("universal", 2) => {
                let (axis1, axis2) = (unit(s[0].w)?, unit(s[1].w)?);
                if axis1.cross(&axis2).norm() < 1e-6 {
                    return Err(JointKindError::ParallelAxes);
                }
                Self::Universal { axis1, axis2 }
            }
            ("ball", 3) => Self::Ball,
            ("free", 6) => Self::Free,
            ("fixed", 0) => Self::Fixed,
            (other, _) => return Err(JointKindError::Unsupported(other.to_string())),
        })
    }

    /// The model's type name (`"revolute"`, …).
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Revolute { .. } => "revolute",
            Self::Prismatic { .. } => "prismatic",
            Self::Cylindrical { .. } => "cylindrical",
            Self::Universal { .. } => "universal",
            Self::Ball => "ball",
            Self::Free => "free",
            Self::Fixed => "fixed",
        }
    }

    /// Degrees of freedom (the model joint's `nv`).
    pub(crate) fn dofs(&self) -> usize {
        match self {
            Self::Revolute { .. } | Self::Prismatic { .. } => 1,
            Self::Cylindrical { .. } | Self::Universal { .. } => 2,
            Self::Ball => 3,
            Self::Free => 6,
            Self::Fixed => 0,
        }
    }

    /// Degrees of freedom with a coordinate that moves additively (an angle or a slide), on
    /// which motors, limits and armature act: all of a revolute, prismatic, cylindrical or
    /// universal joint's, none of a ball's, a free joint's or a fixed one's.
    pub(crate) fn driven_dofs(&self) -> usize {
        match self {
            Self::Ball | Self::Free | Self::Fixed => 0,
            k => k.dofs(),
        }
    }
}
