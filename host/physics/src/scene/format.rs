//! The scene file format (JSON, serde). Unknown fields are errors.

use serde::{Deserialize, Serialize};

use crate::model::description::ModelDescription;
use crate::pipeline::{Effect, IntegratorKind};

fn is_default_integrator(k: &IntegratorKind) -> bool {
    *k == IntegratorKind::default()
}

fn default_dt() -> f64 {
    1.0 / 60.0
}
fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}
fn default_friction() -> f64 {
    0.5
}

measure_pub_fields! {
    /// A whole scene.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct SceneFile {
        /// Name.
        #[serde(default)]
        name: String,
        /// Step (s).
        /// Range 1e-6 … 0.1 s (`scene::limits`; `docs/physics/scenes-contacts-stacking.md` gives the reasons).
        #[serde(default = "default_dt")]
        dt: f64,
        /// Default number of steps for `vphys run`.
        /// Range 1 … 1e8.
        #[serde(default)]
        steps: Option<u64>,
        /// Gravity (m/s², world); used with the `gravity` effect.
        /// Length at most 1e3 m/s².
        #[serde(default = "default_gravity")]
        gravity: [f64; 3],
        /// The declared effects: only these stages run.
        effects: Vec<Effect>,
        /// The integrator of the free bodies and the articulated trees: `explicit-euler`,
        /// `symplectic-euler`, `rkmk4`, `energy-momentum`, `implicit-gyroscopic` (default).
        #[serde(default, skip_serializing_if = "is_default_integrator")]
        integrator: IntegratorKind,
        /// Solver settings.
        #[serde(default)]
        solver: SolverDesc,
        /// Damping rates (with the `damping` effect).
        #[serde(default)]
        damping: DampingDesc,
        /// Named materials.
        /// At most 10 000.
        #[serde(default)]
        materials: Vec<MaterialDesc>,
        /// Free bodies.
        /// At most 100 000.
        #[serde(default)]
        bodies: Vec<BodyDesc>,
        /// Joints between free bodies.
        /// At most 100 000.
        #[serde(default)]
        joints: Vec<JointDesc>,
        /// Articulated trees (part 1's model description).
        /// At most 1 000 trees, 1 000 bodies in one tree, 100 000 in all.
        #[serde(default)]
        articulated: Vec<ArticulatedDesc>,
    }
}

measure_pub_fields! {
    /// Solver settings.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct SolverDesc {
        /// Substeps per step (1 … 64).
        substeps: i64,
        /// Contact stiffness (Hz).
        /// Range 1e-2 … 1e5 Hz.
        contact_hertz: f64,
        /// Approach speed below which no bounce (m/s).
        /// Range 0 … 1e3 m/s.
        restitution_threshold: f64,
    }
}

impl Default for SolverDesc {
    fn default() -> Self {
        Self {
            substeps: 12,
            contact_hertz: 120.0,
            restitution_threshold: 0.5,
        }
    }
}

measure_pub_fields! {
    /// Damping rates (1/s).
    #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct DampingDesc {
        /// Linear (1/s).
        /// Range 0 … 1e6 1/s.
        #[serde(default)]
        linear: f64,
        /// Angular (1/s).
        /// Range 0 … 1e6 1/s.
        #[serde(default)]
        angular: f64,
    }
}

measure_pub_fields! {
    /// A named material.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct MaterialDesc {
        /// Name, referenced by bodies.
        name: String,
        /// Coulomb friction (≥ 0). Pairs mix as `sqrt(μa μb)`.
        /// Range 0 … 10.
        #[serde(default = "default_friction")]
        friction: f64,
        /// Restitution (0 … 1). Pairs take the larger.
        #[serde(default)]
        restitution: f64,
        /// Rolling resistance (≥ 0, torque = coefficient · radius · normal force). Pairs take the larger.
        /// Range 0 … 10.
        #[serde(default)]
        rolling_resistance: f64,
    }
}

/// How a body moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyKindDesc {
    /// Forces and contacts move it.
    #[default]
    Dynamic,
    /// Moves with its given velocity; infinite mass.
    Kinematic,
    /// Never moves.
    Fixed,
}

/// A shape (body frame, centred on the body origin; capsule and cylinder along `z`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeDesc {
    /// Box.
    Box {
        /// Half extents (m).
        /// Range 1e-4 … 1e4 m each.
        half_extents: [f64; 3],
    },
    /// Sphere.
    Sphere {
        /// Radius (m).
        /// Range 1e-4 … 1e4 m.
        radius: f64,
    },
    /// Capsule.
    Capsule {
        /// Radius (m).
        /// Range 1e-4 … 1e4 m.
        radius: f64,
        /// Half length of the core segment (m).
        /// 0 (a sphere) or 1e-4 … 1e4 m.
        half_height: f64,
    },
    /// Cylinder.
    Cylinder {
        /// Radius (m).
        /// Range 1e-4 … 1e4 m.
        radius: f64,
        /// Half height (m).
        /// Range 1e-4 … 1e4 m.
        half_height: f64,
    },
    /// Half-space `{x : n·x ≤ 0}` in the body frame (fixed or kinematic bodies only).
    HalfSpace {
        /// Outward normal, body frame.
        /// Normalised on load: its length must be 1e-6 … 1e6.
        normal: [f64; 3],
    },
    /// Several primitive shapes rigidly joined into one body. The parts are posed in the
    /// body's *reference frame*, which the body's `position` and `rotation` place in the
    /// world; the engine moves the body in its own frame at the centre of mass, along the
    /// principal axes (mass properties from the parts through `Inertia::xform`).
    Compound {
        /// The parts: 1 … 256, each a box, sphere, capsule or cylinder.
        parts: Vec<PartShapeDesc>,
    },
}

measure_pub_fields! {
    /// One part of a compound shape.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct PartShapeDesc {
        /// The part's shape (not a half-space or a compound), centred on the part's frame.
        shape: ShapeDesc,
        /// Centre of the part in the body's reference frame (m).
        /// Each coordinate within ±1e4 m.
        #[serde(default)]
        position: [f64; 3],
        /// Orientation of the part in the reference frame, rotation vector (rad).
        #[serde(default)]
        rotation: [f64; 3],
        /// Mass of the part (kg); or give `density`. Without either the part takes the body's
        /// `density`; with a body `mass`, the parts' masses are scaled to add up to it.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Density of the part (kg/m³).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        density: Option<f64>,
        /// Material name (default: the body's material).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<String>,
    }
}

measure_pub_fields! {
    /// A free body.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct BodyDesc {
        /// Name (unique when given; joints refer to bodies by name).
        #[serde(default)]
        name: String,
        /// Shape.
        shape: ShapeDesc,
        /// Kind.
        #[serde(default)]
        kind: BodyKindDesc,
        /// Mass (kg); give this or `density` for a dynamic body (for a compound: its total mass,
        /// or per-part masses or densities).
        /// Range 1e-6 … 1e6 kg.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Density (kg/m³).
        /// Range 1e-2 … 1e5 kg/m³, and density × volume within the mass range.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        density: Option<f64>,
        /// Centre position (m, world); for a compound, the origin of its reference frame.
        /// Each coordinate within ±1e5 m.
        #[serde(default)]
        position: [f64; 3],
        /// Orientation as a rotation vector (axis × angle, rad).
        /// Angle (length) at most 1e3 rad.
        #[serde(default)]
        rotation: [f64; 3],
        /// Linear velocity of the centre of mass (m/s, world).
        /// Speed at most 1e3 m/s.
        #[serde(default)]
        velocity: [f64; 3],
        /// Angular velocity (rad/s, world).
        /// Angular speed at most 1e4 rad/s.
        #[serde(default)]
        angular_velocity: [f64; 3],
        /// Material name (default material: friction 0.5, no restitution or rolling resistance).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<String>,
    }
}

measure_pub_fields! {
    /// A joint between two bodies, stated by the model's joint types (as in articulated models'
    /// `JointDescription`). The joint frame has its origin at `anchor` and the world axes, so
    /// `axis` and `axis2` are world directions; the joint's coordinates are zero at the initial
    /// poses.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct JointDesc {
        /// `revolute`, `prismatic`, `cylindrical`, `universal`, `ball`, `free` or `fixed`. The
        /// key is `type`; `kind` is read as another name for it.
        #[serde(rename = "type", alias = "kind")]
        kind: String,
        /// First body (name): body A, whose joint frame the coordinates are measured in.
        body1: String,
        /// Second body (name): body B.
        body2: String,
        /// Anchor: the joint frame's origin (m, world, at the initial poses).
        /// Each coordinate within ±1e5 m.
        anchor: [f64; 3],
        /// The joint's axis (world): revolute, prismatic, cylindrical, and a universal joint's
        /// first axis (fixed in body 1).
        /// Normalised on load: its length must be 1e-6 … 1e6.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<[f64; 3]>,
        /// A universal joint's second axis (world, fixed in body 2; not parallel to `axis`).
        /// Normalised on load: its length must be 1e-6 … 1e6.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis2: Option<[f64; 3]>,
        /// Motors on the joint's coordinates (at most one per coordinate).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        motors: Vec<JointMotorDesc>,
        /// Travel limits of the joint's coordinates (at most one per coordinate).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        limits: Vec<JointLimitsDesc>,
        /// Armature of each coordinate in order (kg·m² on an angle, kg on a slide), 0 … 1e9; at
        /// most as many entries as the joint has driven coordinates.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        armature: Vec<f64>,
    }
}

measure_pub_fields! {
    /// A motor on one coordinate of a joint between bodies:
    /// `τ = stiffness (target_position − q) + damping (target_velocity − q̇)`, `|τ| ≤ max_force`.
    /// Coordinates: revolute 0 = angle; prismatic 0 = slide; cylindrical 0 = angle, 1 = slide;
    /// universal 0, 1 = the angles about `axis` and `axis2`. Ball, free and fixed joints have
    /// no driven coordinates.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct JointMotorDesc {
        /// Which coordinate (default 0).
        #[serde(default)]
        coordinate: usize,
        /// Target position (rad or m), within ±1e5; absent: a velocity motor.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        target_position: Option<f64>,
        /// Target velocity (rad/s or m/s), within ±1e5.
        #[serde(default)]
        target_velocity: f64,
        /// Stiffness (N·m/rad or N/m), 0 … 1e9.
        #[serde(default)]
        stiffness: f64,
        /// Damping (N·m·s/rad or N·s/m), 0 … 1e9.
        #[serde(default)]
        damping: f64,
        /// Largest torque or force (N·m or N), 0 … 1e9.
        max_force: f64,
    }
}

measure_pub_fields! {
    /// Travel limits of one coordinate of a joint between bodies.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct JointLimitsDesc {
        /// Which coordinate (default 0).
        #[serde(default)]
        coordinate: usize,
        /// Lower limit (rad or m), within ±1e5.
        lower: f64,
        /// Upper limit (rad or m), within ±1e5, ≥ `lower`.
        upper: f64,
        /// Restitution at the limits, 0 … 1 (default 0: the coordinate stops).
        #[serde(default)]
        restitution: f64,
    }
}

measure_pub_fields! {
    /// An articulated tree and its initial state.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct ArticulatedDesc {
        /// Part 1's model description (its `gravity` is replaced by the scene's).
        model: ModelDescription,
        /// Initial configuration (default: neutral).
        /// Each entry within ±1e5 (m or rad).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        q: Option<Vec<f64>>,
        /// Initial velocity (default: zero).
        /// Each entry within ±1e4 (m/s or rad/s).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        qd: Option<Vec<f64>>,
        /// Collision shapes fixed on links (with the `contacts` effect the links touch the
        /// scene's bodies and other trees' links). Several on one link make it a compound.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        shapes: Vec<LinkShapeDesc>,
        /// Motors, travel limits and prescribed motion of the joints' coordinates.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        drives: Vec<DriveDesc>,
    }
}

measure_pub_fields! {
    /// A collision shape on a link of a tree.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct LinkShapeDesc {
        /// The link (a body name of the model).
        link: String,
        /// The shape (a box, sphere, capsule or cylinder), centred on its own frame.
        shape: ShapeDesc,
        /// Centre of the shape in the link frame (m).
        #[serde(default)]
        position: [f64; 3],
        /// Orientation of the shape in the link frame, rotation vector (rad).
        #[serde(default)]
        rotation: [f64; 3],
        /// Material name (default material when absent).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        material: Option<String>,
    }
}

measure_pub_fields! {
    /// What drives one coordinate of a joint (a revolute, prismatic, cylindrical or universal
    /// joint; give one of `motor`, `limits`, `trajectory`, or `motor` and `limits`).
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct DriveDesc {
        /// The joint, named by its child link.
        joint: String,
        /// Which of the joint's coordinates (0 for one-degree-of-freedom joints).
        #[serde(default)]
        coordinate: usize,
        /// A PD servo with a force limit.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        motor: Option<MotorDesc>,
        /// Travel limits `[lower, upper]` (rad or m).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        limits: Option<[f64; 2]>,
        /// Prescribed motion (a kinematic root or driven joint).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        trajectory: Option<TrajectoryDesc>,
    }
}

measure_pub_fields! {
    /// A motor: `τ = stiffness (target_position − q) + damping (target_velocity − q̇)`, limited to
    /// `|τ| ≤ max_force`.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct MotorDesc {
        /// Target position (rad or m); absent: a velocity motor.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        target_position: Option<f64>,
        /// Target velocity (rad/s or m/s).
        #[serde(default)]
        target_velocity: f64,
        /// Stiffness (N·m/rad or N/m), 0 … 1e9.
        #[serde(default)]
        stiffness: f64,
        /// Damping (N·m·s/rad or N·s/m), 0 … 1e9.
        #[serde(default)]
        damping: f64,
        /// Largest force or torque (N or N·m), 0 … 1e9.
        max_force: f64,
    }
}

/// A trajectory `q*(t)` of a coordinate (rad or m; `t` in s from the scene's start).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum TrajectoryDesc {
    /// `q* = start + velocity t`.
    ConstantVelocity {
        /// Start (rad or m).
        start: f64,
        /// Velocity (rad/s or m/s).
        velocity: f64,
    },
    /// Piecewise linear through `[t, q]` points with increasing `t`, held outside.
    Keyframes {
        /// The points (1 … 10 000).
        points: Vec<[f64; 2]>,
    },
    /// `q* = offset + amplitude sin(2π frequency t + phase)`.
    Sinusoid {
        /// Centre (rad or m).
        #[serde(default)]
        offset: f64,
        /// Amplitude (rad or m).
        amplitude: f64,
        /// Frequency (Hz), 0 … 1e3.
        frequency: f64,
        /// Phase (rad).
        #[serde(default)]
        phase: f64,
    },
}
