//! Parsing and building a world from a scene.

use super::format::{
    BodyKindDesc, DriveDesc, JointDesc, PartShapeDesc, SceneFile, ShapeDesc, TrajectoryDesc,
};
use super::SceneError;
use crate::algebra::{exp_so3, SE3};
use crate::dynamics::{BodyKind, BodySet, Material};
use crate::geometry::{Compound, CompoundError, CompoundMass, PartDesc, Shape, V3};
use crate::model::description::JointDescription;
use crate::pipeline::ArticulatedSystem;
use crate::pipeline::{
    BodyHandle, Effect, Effects, JointBuilder, Motor, SolverSettings, Trajectory, World,
};

fn v(a: [f64; 3]) -> V3 {
    V3::new(a[0], a[1], a[2])
}

impl ShapeDesc {
    /// The engine shape. A compound's parts get the default material and their stated mass
    /// (or density × volume, else 1 kg/m³ × volume): the geometry and the mass *ratios* of a
    /// scene's compound come from [`SceneFile::build`], which resolves named materials.
    pub fn shape(&self) -> Shape {
        match *self {
            ShapeDesc::Compound { ref parts } => {
                compound(parts, None, |_| Material::default()).map_or_else(
                    // Unvalidated input: fall back to the first part alone.
                    |_| {
                        parts
                            .first()
                            .map_or(Shape::Sphere { radius: 0.0 }, |p| p.shape.shape())
                    },
                    |(shape, _)| shape,
                )
            }
            ShapeDesc::Box { half_extents } => Shape::Cuboid {
                half: v(half_extents),
            },
            ShapeDesc::Sphere { radius } => Shape::Sphere { radius },
            ShapeDesc::Capsule {
                radius,
                half_height,
            } => Shape::Capsule {
                radius,
                half_height,
            },
            ShapeDesc::Cylinder {
                radius,
                half_height,
            } => Shape::Cylinder {
                radius,
                half_height,
            },
            ShapeDesc::HalfSpace { normal } => Shape::HalfSpace {
                normal: v(normal).normalize(),
            },
        }
    }
}

/// Builds a compound from its parts: part masses from `mass`, else `density` (the part's, else
/// `body_density`), else 1 kg/m³; materials through `material`.
fn compound(
    parts: &[PartShapeDesc],
    body_density: Option<f64>,
    material: impl Fn(&Option<String>) -> Material,
) -> Result<(Shape, CompoundMass), CompoundError> {
    let descs: Vec<PartDesc> = parts
        .iter()
        .map(|p| {
            let shape = p.shape.shape();
            let mass = p
                .mass
                .unwrap_or_else(|| p.density.or(body_density).unwrap_or(1.0) * shape.volume());
            PartDesc {
                shape,
                pose: SE3::new(exp_so3(&v(p.rotation)), v(p.position)),
                mass,
                material: material(&p.material),
            }
        })
        .collect();
    let (c, mass) = Compound::new(&descs)?;
    Ok((c.into_shape(), mass))
}

impl SceneFile {
    /// Parses JSON (syntax and type errors: the first, with line and column) and validates
    /// (every problem).
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        super::validate::check_counts(text)?;
        let s: SceneFile =
            serde_json::from_str(text).map_err(|e| SceneError::Syntax(e.to_string()))?;
        s.validate()?;
        Ok(s)
    }

    /// Reads and parses a file.
    pub fn from_path(path: &str) -> Result<Self, SceneError> {
        let text = super::validate::read_file(path)?;
        Self::from_json(&text)
    }

    /// Pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// `Ok` when [`SceneFile::problems`] is empty.
    pub(crate) fn validate(&self) -> Result<(), SceneError> {
        let p = self.problems();
        if p.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid(p))
        }
    }

    /// The declared effects.
    pub(crate) fn effect_set(&self) -> Effects {
        Effects::of(&self.effects)
    }

    /// Validates and builds the world.
    pub fn build(&self) -> Result<World, SceneError> {
        self.validate()?;
        let mut bodies = BodySet::default();
        let named = |name: &Option<String>| {
            name.as_ref()
                .and_then(|m| self.materials.iter().find(|x| &x.name == m))
                .map(|m| Material {
                    friction: m.friction,
                    restitution: m.restitution,
                    rolling_resistance: m.rolling_resistance,
                })
        };
        for (i, b) in self.bodies.iter().enumerate() {
            let material = named(&b.material).unwrap_or_default();
            let mut rot = exp_so3(&v(b.rotation));
            let mut pos = v(b.position);
            let (shape, mass) = match &b.shape {
                ShapeDesc::Compound { parts } => {
                    let (shape, mp) = compound(parts, b.density, |m| named(m).unwrap_or(material))
                        .map_err(|e| {
                            SceneError::Invalid(vec![super::Problem {
                                path: format!("bodies[{i}].shape"),
                                message: e.to_string(),
                            }])
                        })?;
                    // The body moves in its centre-of-mass principal frame: T_wb = T_wr T_rb.
                    let t = mp.body_in_reference;
                    pos += rot * t.p;
                    rot *= t.r;
                    (shape, b.mass.unwrap_or(mp.mass))
                }
                primitive => {
                    let shape = primitive.shape();
                    let mass = b
                        .mass
                        .unwrap_or_else(|| b.density.unwrap_or(0.0) * shape.volume());
                    (shape, mass)
                }
            };
            let kind = match b.kind {
                BodyKindDesc::Dynamic => BodyKind::Dynamic,
                BodyKindDesc::Kinematic => BodyKind::Kinematic,
                BodyKindDesc::Fixed => BodyKind::Fixed,
            };
            bodies.push(
                b.name.clone(),
                kind,
                shape,
                material,
                mass,
                pos,
                rot,
                v(b.velocity),
                v(b.angular_velocity),
            );
        }
        let settings = SolverSettings {
            substeps: self.solver.substeps as usize,
            contact_hertz: self.solver.contact_hertz,
            restitution_threshold: self.solver.restitution_threshold,
            linear_damping: self.damping.linear,
            angular_damping: self.damping.angular,
            ..SolverSettings::default()
        };
        let mut world = World::new(
            bodies,
            self.effect_set(),
            self.dt,
            v(self.gravity),
            settings,
        );
        world.set_integrator(self.integrator);
        for (i, j) in self.joints.iter().enumerate() {
            let handle = |name: &str| {
                world
                    .body_index(name)
                    .and_then(|k| world.body_handles().nth(k))
            };
            let problem = |message: String| {
                SceneError::Invalid(vec![super::Problem {
                    path: format!("joints[{i}]"),
                    message,
                }])
            };
            let (Some(a), Some(b)) = (handle(&j.body1), handle(&j.body2)) else {
                return Err(problem("unknown body".into()));
            };
            let builder = j.builder(a, b).map_err(problem)?;
            world
                .insert_joint(builder)
                .map_err(|e| problem(e.to_string()))?;
        }
        let g = if self.effects.contains(&Effect::Gravity) {
            v(self.gravity)
        } else {
            V3::zeros()
        };
        for a in &self.articulated {
            // Validated above: builds.
            if let Ok(mut tree) = a.model.build::<f64>() {
                tree.set_gravity(g);
                let q = a.q.clone().unwrap_or_else(|| tree.neutral_configuration());
                let qd = a.qd.clone().unwrap_or_else(|| vec![0.0; tree.nv()]);
                let link = |name: &str| tree.bodies().iter().position(|b| b.name == name);
                let mut shapes = Vec::new();
                for ls in &a.shapes {
                    if let Some(l) = link(&ls.link) {
                        let pose = SE3::new(exp_so3(&v(ls.rotation)), v(ls.position));
                        let material = named(&ls.material).unwrap_or_default();
                        shapes.push((l, ls.shape.shape(), pose, material));
                    }
                }
                let mut drives = Vec::new();
                for d in &a.drives {
                    if let Some(l) = link(&d.joint) {
                        drives.push((tree.bodies()[l].v_offset + d.coordinate, d));
                    }
                }
                let mut sys = ArticulatedSystem::new(tree, q, qd);
                for (l, shape, pose, material) in shapes {
                    sys = sys.with_link_shape(l, shape, pose, material);
                }
                for (dof, d) in drives {
                    sys = drive(sys, dof, d);
                }
                world.add_articulated(sys);
            }
        }
        // Bodies overlapping en masse would make the first step's contacts grow as the square
        // of their number: refused here, counted no further than the limit.
        let limit = crate::pipeline::MAX_CONTACT_PAIRS_PER_BODY.saturating_mul(world.body_count());
        if world.has_broad_phase() {
            let pairs = world.overlapping_pairs(limit);
            if pairs > limit {
                return Err(SceneError::TooMany {
                    path: "bodies and tree links".into(),
                    what: "pairs of overlapping bounding boxes at the start (bodies placed on one another)",
                    at_least: pairs,
                    limit,
                });
            }
        }
        Ok(world)
    }
}

/// Adds the drives a scene states on coordinate `dof`.
fn drive(mut sys: ArticulatedSystem, dof: usize, d: &DriveDesc) -> ArticulatedSystem {
    if let Some(m) = &d.motor {
        sys = sys.with_motor(
            dof,
            Motor {
                target_position: m.target_position,
                target_velocity: m.target_velocity,
                stiffness: m.stiffness,
                damping: m.damping,
                max_force: m.max_force,
            },
        );
    }
    if let Some([lower, upper]) = d.limits {
        sys = sys.with_limits(dof, lower, upper);
    }
    if let Some(t) = &d.trajectory {
        let trajectory = match t {
            TrajectoryDesc::ConstantVelocity { start, velocity } => Trajectory::ConstantVelocity {
                start: *start,
                velocity: *velocity,
            },
            TrajectoryDesc::Keyframes { points } => {
                Trajectory::Keyframes(points.iter().map(|p| (p[0], p[1])).collect())
            }
            TrajectoryDesc::Sinusoid {
                offset,
                amplitude,
                frequency,
                phase,
            } => Trajectory::Sinusoid {
                offset: *offset,
                amplitude: *amplitude,
                frequency: *frequency,
                phase: *phase,
            },
        };
        sys = sys.with_prescribed(dof, trajectory);
    }
    sys
}

impl JointDesc {
    /// The joint's builder between bodies `a` and `b`: the model joint from `type`, `axis`
    /// and `axis2` (world axes are the joint frame's), its motors, limits and armature. An
    /// error names what the model rejects (an unknown type, a missing or zero axis).
    pub(crate) fn builder(&self, a: BodyHandle, b: BodyHandle) -> Result<JointBuilder, String> {
        let description = JointDescription {
            kind: self.kind.clone(),
            axis: self.axis,
            axis2: self.axis2,
        };
        let model = crate::model::joints::from_description::<f64>(&description)
            .map_err(|e| e.to_string())?;
        let mut builder = JointBuilder::new(model.as_ref(), a, b).anchor(v(self.anchor));
        for m in &self.motors {
            builder = builder.motor(
                m.coordinate,
                Motor {
                    target_position: m.target_position,
                    target_velocity: m.target_velocity,
                    stiffness: m.stiffness,
                    damping: m.damping,
                    max_force: m.max_force,
                },
            );
        }
        for l in &self.limits {
            builder = builder
                .limits(l.coordinate, l.lower, l.upper)
                .limit_restitution(l.coordinate, l.restitution);
        }
        for (dof, &x) in self.armature.iter().enumerate() {
            builder = builder.armature(dof, x);
        }
        Ok(builder)
    }
}
