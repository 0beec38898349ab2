//! Joints between bodies through handles: a [`JointBuilder`] states a joint by the model's
//! joint types (`model::joints`: revolute, prismatic, cylindrical, universal, ball, free,
//! fixed) at a joint frame, with a motor, limits and an armature on each coordinate;
//! [`World::insert_joint`] checks it and adds it, [`World::joint`] and [`World::joint_mut`]
//! read it and set its drives, [`World::remove_joint`] takes it out.
//!
//! Coordinates are the model joint's own: the angle about a revolute or cylindrical axis
//! (rad, dof 0), the slide along a prismatic or cylindrical axis (m; dof 0 of a prismatic
//! joint, dof 1 of a cylindrical one), a universal joint's two angles. They are zero when the
//! joint is inserted, and angles count whole turns. Motors and limits integrate over the
//! world's substep `dt / substeps` as it is when the joint is inserted or last reached through
//! [`World::joint_mut`].

use super::world::World;
use crate::dynamics::solver::{DofLimits, DofMotor, FreeJoint, MAX_DRIVEN_DOFS};
pub use crate::dynamics::solver::{FreeJointKind, JointKindError};
use crate::dynamics::BodyKind;
use crate::geometry::{M3, V3};
use crate::model::Joint;
use crate::pipeline::{BodyHandle, JointHandle, Motor};

/// Why a joint could not be inserted or changed.
#[derive(Clone, Debug, PartialEq)]
pub enum JointError {
    /// A body handle names no body of this world (removed, or from another world).
    StaleBody(BodyHandle),
    /// Body A and body B are the same body.
    SameBody,
    /// Neither body is dynamic: the joint could move nothing.
    NoDynamicBody,
    /// The model joint cannot join free bodies (its type, a zero axis, parallel axes).
    Kind(JointKindError),
    /// The anchor is not finite (m, world).
    InvalidAnchor(V3),
    /// The joint axes are not a rotation (orthonormal columns, determinant +1, within 1e-6).
    InvalidAxes,
    /// The joint has no driven coordinate `dof`: it has `driven` (a ball, free or fixed joint
    /// has none).
    NoSuchDof {
        /// The coordinate asked for.
        dof: usize,
        /// The joint's type name.
        joint: &'static str,
        /// How many driven coordinates it has.
        driven: usize,
    },
    /// A motor, limit or armature setting out of its range.
    InvalidValue {
        /// Which setting (`"motor.stiffness"`, `"limits"`, …).
        what: &'static str,
        /// What it must be.
        expected: &'static str,
        /// The value given.
        value: f64,
    },
}

impl core::fmt::Display for JointError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::StaleBody(h) => write!(f, "body handle {h:?} names no body of this world"),
            Self::SameBody => write!(f, "a joint needs two different bodies"),
            Self::NoDynamicBody => write!(f, "at least one of the two bodies must be dynamic"),
            Self::Kind(e) => write!(f, "{e}"),
            Self::InvalidAnchor(p) => write!(f, "the anchor {p:?} is not finite"),
            Self::InvalidAxes => write!(
                f,
                "the joint axes must be a rotation (orthonormal columns, determinant +1)"
            ),
            Self::NoSuchDof { dof, joint, driven } => write!(
                f,
                "a {joint} joint has {driven} driven coordinate(s), no coordinate {dof}"
            ),
            Self::InvalidValue {
                what,
                expected,
                value,
            } => write!(f, "{what} must be {expected}, got {value}"),
        }
    }
}

impl std::error::Error for JointError {}

/// What a builder or a [`JointMut`] sets on one coordinate, checked against the joint.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Setting {
    Motor(Option<Motor>),
    Limits(Option<(f64, f64)>),
    Restitution(f64),
    Armature(f64),
}

/// A joint between two bodies, described before it is inserted.
///
/// ```
/// # use virtual_physics::pipeline::{JointBuilder, Motor, BodyHandle};
/// # use virtual_physics::model::Revolute;
/// # use virtual_physics::algebra::Vec3;
/// # fn f(a: BodyHandle, b: BodyHandle) -> JointBuilder {
/// JointBuilder::new(&Revolute::new(Vec3::z()), a, b)
///     .anchor(Vec3::new(0.0, 0.0, 1.0))
///     .motor(0, Motor { target_position: Some(0.5), target_velocity: 0.0,
///                       stiffness: 100.0, damping: 10.0, max_force: 20.0 })
///     .limits(0, -1.0, 1.0)
///     .armature(0, 0.01)
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct JointBuilder {
    kind: Result<FreeJointKind, JointKindError>,
    body_a: BodyHandle,
    body_b: BodyHandle,
    anchor: Option<V3>,
    axes: M3,
    settings: Vec<(usize, Setting)>,
}

impl JointBuilder {
    /// A joint of the model's type `joint` (its axes are in the joint frame) between
    /// `body_a` and `body_b`. By default the joint frame's origin is body B's centre of mass
    /// and its axes are the world axes.
    pub fn new(joint: &dyn Joint<f64>, body_a: BodyHandle, body_b: BodyHandle) -> Self {
        Self {
            kind: FreeJointKind::from_joint(joint),
            body_a,
            body_b,
            anchor: None,
            axes: M3::identity(),
            settings: Vec::new(),
        }
    }

    /// The joint frame's origin (m, world, at the bodies' current poses).
    pub fn anchor(mut self, world_point: V3) -> Self {
        self.anchor = Some(world_point);
        self
    }

    /// The joint frame's axes (world from joint frame rotation: its columns are the joint
    /// frame's axes in world coordinates).
    pub fn axes(mut self, world_rotation: M3) -> Self {
        self.axes = world_rotation;
        self
    }

    /// A motor on coordinate `dof`.
    pub fn motor(mut self, dof: usize, motor: Motor) -> Self {
        self.settings.push((dof, Setting::Motor(Some(motor))));
        self
    }

    /// Limits `lower ≤ q ≤ upper` (rad or m) on coordinate `dof`.
    pub fn limits(mut self, dof: usize, lower: f64, upper: f64) -> Self {
        self.settings
            .push((dof, Setting::Limits(Some((lower, upper)))));
        self
    }

    /// Restitution (0 … 1) of coordinate `dof` at its limits (default 0).
    pub(crate) fn limit_restitution(mut self, dof: usize, restitution: f64) -> Self {
        self.settings.push((dof, Setting::Restitution(restitution)));
        self
    }

    /// An armature on coordinate `dof` (kg·m² on an angle, kg on a slide).
    pub fn armature(mut self, dof: usize, value: f64) -> Self {
        self.settings.push((dof, Setting::Armature(value)));
        self
    }
}

fn check(
    what: &'static str,
    expected: &'static str,
    ok: bool,
    value: f64,
) -> Result<(), JointError> {
    if ok {
        Ok(())
    } else {
        Err(JointError::InvalidValue {
            what,
            expected,
            value,
        })
    }
}

/// Applies `setting` to coordinate `dof` of `joint`, after checking it.
fn apply_setting(joint: &mut FreeJoint, dof: usize, setting: Setting) -> Result<(), JointError> {
    let kind = joint.kind();
    let no_dof = JointError::NoSuchDof {
        dof,
        joint: kind.type_name(),
        driven: kind.driven_dofs(),
    };
    if dof >= kind.driven_dofs().min(MAX_DRIVEN_DOFS) {
        return Err(no_dof);
    }
    let range = |x: f64| x.is_finite() && x.abs() <= 1e9;
    match setting {
        Setting::Motor(m) => {
            if let Some(m) = &m {
                let p = m.target_position.unwrap_or(0.0);
                check("motor.target_position", "finite, within ±1e9", range(p), p)?;
                let v = m.target_velocity;
                check("motor.target_velocity", "finite, within ±1e9", range(v), v)?;
                for (what, x) in [
                    ("motor.stiffness", m.stiffness),
                    ("motor.damping", m.damping),
                    ("motor.max_force", m.max_force),
                ] {
                    check(what, "finite, 0 … 1e9", range(x) && x >= 0.0, x)?;
                }
            }
            let d = joint.drive_mut(dof).ok_or(no_dof)?;
            d.motor = m.map(|m| DofMotor {
                target_position: m.target_position,
                target_velocity: m.target_velocity,
                stiffness: m.stiffness,
                damping: m.damping,
                max_force: m.max_force,
            });
        }
        Setting::Limits(l) => {
            if let Some((lo, hi)) = l {
                check("limits.lower", "finite, within ±1e9", range(lo), lo)?;
                check(
                    "limits.upper",
                    "finite, within ±1e9 and ≥ lower",
                    range(hi) && hi >= lo,
                    hi,
                )?;
            }
            let d = joint.drive_mut(dof).ok_or(no_dof)?;
            let restitution = d.limits.map_or(0.0, |x| x.restitution);
            d.limits = l.map(|(lower, upper)| DofLimits {
                lower,
                upper,
                restitution,
            });
        }
        Setting::Restitution(e) => {
            check(
                "limits.restitution",
                "within 0 … 1",
                (0.0..=1.0).contains(&e),
                e,
            )?;
            let d = joint.drive_mut(dof).ok_or(no_dof)?;
            if let Some(l) = d.limits.as_mut() {
                l.restitution = e;
            } else {
                d.limits = Some(DofLimits {
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    restitution: e,
                });
            }
        }
        Setting::Armature(x) => {
            check("armature", "finite, 0 … 1e9", range(x) && x >= 0.0, x)?;
            joint.drive_mut(dof).ok_or(no_dof)?.armature = x;
        }
    }
    Ok(())
}

fn is_rotation(r: &M3) -> bool {
    r.iter().all(|x| x.is_finite())
        && (r.transpose() * r - M3::identity()).abs().max() <= 1e-6
        && (r.determinant() - 1.0).abs() <= 1e-6
}

impl World {
    /// The substep motors and limits integrate over (s).
    fn joint_substep(&self) -> f64 {
        self.dt / self.settings.substeps.max(1) as f64
    }

    /// Inserts a joint (contacts between its two bodies are disabled while it exists).
    /// Errors: a stale body handle, the same body twice, no dynamic body, a model joint that
    /// cannot join free bodies (a zero or non-finite axis, a universal joint's parallel
    /// axes), a non-finite anchor, axes that are not a rotation, a coordinate the joint does
    /// not have, a setting out of range; nothing is inserted then.
    pub fn insert_joint(&mut self, builder: JointBuilder) -> Result<JointHandle, JointError> {
        let a = self
            .body_slots
            .index(builder.body_a)
            .ok_or(JointError::StaleBody(builder.body_a))?;
        let b = self
            .body_slots
            .index(builder.body_b)
            .ok_or(JointError::StaleBody(builder.body_b))?;
        if a == b {
            return Err(JointError::SameBody);
        }
        if self.bodies.kind[a] != BodyKind::Dynamic && self.bodies.kind[b] != BodyKind::Dynamic {
            return Err(JointError::NoDynamicBody);
        }
        let kind = builder.kind.map_err(JointError::Kind)?;
        let anchor = builder.anchor.unwrap_or(self.bodies.pos[b]);
        if !anchor.iter().all(|x| x.is_finite()) {
            return Err(JointError::InvalidAnchor(anchor));
        }
        if !is_rotation(&builder.axes) {
            return Err(JointError::InvalidAxes);
        }
        let mut joint = FreeJoint::new(
            &self.bodies,
            a,
            b,
            kind,
            anchor,
            builder.axes,
            self.joint_substep(),
        );
        for (dof, s) in builder.settings {
            apply_setting(&mut joint, dof, s)?;
        }
        Ok(self.add_joint(joint))
    }

    /// Removes a joint; false when the handle is stale. Contacts between its bodies are
    /// enabled again (unless another joint joins them).
    pub fn remove_joint(&mut self, h: JointHandle) -> bool {
        let Some(i) = self.joint_slots.index(h) else {
            return false;
        };
        self.remove_joint_at(i);
        true
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Every joint's handle, in storage order.
    pub fn joint_handles(&self) -> impl ExactSizeIterator<Item = JointHandle> + '_ {
        (0..self.joints.len()).map(|i| self.joint_slots.handle(i))
    }

    /// A joint's state; `None` when the handle is stale.
    pub fn joint(&self, h: JointHandle) -> Option<JointRef<'_>> {
        let index = self.joint_slots.index(h)?;
        Some(JointRef { world: self, index })
    }

    /// A joint, to set its motors, limits and armature (each step if need be); `None` when
    /// the handle is stale. It takes the world's current substep for its motors and limits.
    pub fn joint_mut(&mut self, h: JointHandle) -> Option<JointMut<'_>> {
        let index = self.joint_slots.index(h)?;
        let substep = self.joint_substep();
        self.joints[index].set_substep(substep);
        Some(JointMut { world: self, index })
    }
}

/// A joint of a world, read through [`World::joint`].
#[derive(Clone, Copy)]
pub struct JointRef<'w> {
    world: &'w World,
    index: usize,
}

impl<'w> JointRef<'w> {
    fn j(&self) -> &'w FreeJoint {
        &self.world.joints[self.index]
    }

    /// The joint's type.
    pub fn kind(&self) -> FreeJointKind {
        self.j().kind()
    }

    /// Body A and body B.
    pub fn bodies(&self) -> (BodyHandle, BodyHandle) {
        let (a, b) = self.j().bodies();
        let s = &self.world.body_slots;
        (s.handle(a), s.handle(b))
    }

    /// Number of driven coordinates (those with motors, limits and armature).
    pub fn driven_dofs(&self) -> usize {
        self.kind().driven_dofs()
    }

    /// Coordinate `dof` at the bodies' current poses (rad or m; angles count whole turns).
    pub fn position(&self, dof: usize) -> Option<f64> {
        self.j().position(&self.world.bodies, dof)
    }

    /// Rate of coordinate `dof` at the bodies' current velocities (rad/s or m/s).
    pub fn rate(&self, dof: usize) -> Option<f64> {
        self.j().rate(&self.world.bodies, dof)
    }

    /// The torque or force the motor of `dof` gave in the last substep (N·m or N, along the
    /// coordinate, on body B; body A takes the opposite).
    pub fn motor_force(&self, dof: usize) -> Option<f64> {
        self.j().motor_force(dof)
    }

    /// The torque or force the limits of `dof` gave in the last substep (N·m or N, on body
    /// B; positive away from the lower limit).
    pub fn limit_force(&self, dof: usize) -> Option<f64> {
        self.j().limit_force(dof)
    }

    /// The motor of `dof`, if any.
    pub(crate) fn motor(&self, dof: usize) -> Option<Motor> {
        self.j().drive(dof)?.motor.map(|m| Motor {
            target_position: m.target_position,
            target_velocity: m.target_velocity,
            stiffness: m.stiffness,
            damping: m.damping,
            max_force: m.max_force,
        })
    }

    /// The limits `(lower, upper)` of `dof` (rad or m), if any.
    pub fn limits(&self, dof: usize) -> Option<(f64, f64)> {
        self.j().drive(dof)?.limits.map(|l| (l.lower, l.upper))
    }

    /// The armature of `dof` (kg·m² or kg).
    pub fn armature(&self, dof: usize) -> Option<f64> {
        self.j().drive(dof).map(|d| d.armature)
    }

    /// Distance (m) by which the constrained linear directions have come apart.
    pub fn gap(&self) -> f64 {
        self.j().gap(&self.world.bodies)
    }

    /// Angle (rad) by which the constrained rotations have drifted.
    pub fn angular_gap(&self) -> f64 {
        self.j().angular_gap(&self.world.bodies)
    }
}

/// A joint of a world, to change through [`World::joint_mut`].
pub struct JointMut<'w> {
    world: &'w mut World,
    index: usize,
}

impl JointMut<'_> {
    /// Reads the joint.
    pub(crate) fn get(&self) -> JointRef<'_> {
        JointRef {
            world: self.world,
            index: self.index,
        }
    }

    fn set(&mut self, dof: usize, s: Setting) -> Result<(), JointError> {
        apply_setting(&mut self.world.joints[self.index], dof, s)
    }

    /// Sets (or with `None` removes) the motor of `dof`.
    pub(crate) fn set_motor(&mut self, dof: usize, motor: Option<Motor>) -> Result<(), JointError> {
        self.set(dof, Setting::Motor(motor))
    }

    /// Sets the targets of the motor of `dof` (rad or m; rad/s or m/s); an error when it has
    /// no motor.
    pub fn set_motor_target(
        &mut self,
        dof: usize,
        position: Option<f64>,
        velocity: f64,
    ) -> Result<(), JointError> {
        let Some(mut m) = self.get().motor(dof) else {
            return Err(JointError::InvalidValue {
                what: "motor",
                expected: "set before its targets (the coordinate has no motor)",
                value: dof as f64,
            });
        };
        m.target_position = position;
        m.target_velocity = velocity;
        self.set_motor(dof, Some(m))
    }

    /// Sets (or with `None` removes) the limits `(lower, upper)` of `dof` (rad or m).
    pub fn set_limits(&mut self, dof: usize, limits: Option<(f64, f64)>) -> Result<(), JointError> {
        self.set(dof, Setting::Limits(limits))
    }

    /// Sets the armature of `dof` (kg·m² or kg; 0 removes it).
    pub fn set_armature(&mut self, dof: usize, value: f64) -> Result<(), JointError> {
        self.set(dof, Setting::Armature(value))
    }
}
