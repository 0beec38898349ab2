//! The constraint solver: a soft step in the manner of Box2D v3 and Rapier's small steps.
//!
//! Each step splits into `substeps`; each substep integrates velocities, warm-starts, solves
//! the constraints with soft (spring-damper) position bias, integrates positions, then relaxes
//! (solves again without bias so that the push-out does not stay as velocity). After the
//! substeps a restitution pass applies bounce, and the accumulated impulses are stored in the
//! manifolds for the next step's warm start.
//!
//! Jacobians and effective masses are computed once per step ([`ContactConstraint::prepare`]);
//! the substeps update each contact's separation from the bodies' linearised motion
//! (`dp + dθ × r`) instead of re-running collision.

pub(crate) mod contact_batch;
pub(crate) mod contact_constraint;
pub(crate) mod joint_constraint;
pub(crate) mod joint_dofs;
pub(crate) mod joint_graph;
pub(crate) mod joint_kind;
pub(crate) mod lanes;
pub(crate) mod softness;

pub(crate) use contact_batch::ContactBatches;
pub(crate) use contact_constraint::LINEAR_SLOP;
pub(crate) use contact_constraint::{ContactConstraint, ContactSettings, SolvePass};
pub(crate) use joint_constraint::{FreeJoint, MAX_DRIVEN_DOFS};
pub(crate) use joint_dofs::{DofLimits, DofMotor};
pub(crate) use joint_graph::{JointGraph, JointSoftness};
pub use joint_kind::{FreeJointKind, JointKindError};
pub(crate) use softness::{ContactStiffness, Softness};
