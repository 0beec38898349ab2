//! Parsing and building a world from a scene.

use super::format::{BodyKindDesc, SceneFile, ShapeDesc};
use super::SceneError;
use crate::algebra::exp_so3;
use crate::dynamics::solver::FreeJoint;
use crate::dynamics::{BodyKind, BodySet, Material};
use crate::geometry::{Shape, V3};
use crate::pipeline::articulated::ArticulatedSystem;
use crate::pipeline::{Effect, Effects, SolverSettings, World};

fn v(a: [f64; 3]) -> V3 {
    V3::new(a[0], a[1], a[2])
}

impl ShapeDesc {
    /// The engine shape.
    pub fn shape(&self) -> Shape {
        match *self {
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

impl SceneFile {
    /// Parses JSON (syntax and type errors: the first, with line and column) and validates
    /// (every problem).
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        let s: SceneFile =
            serde_json::from_str(text).map_err(|e| SceneError::Syntax(e.to_string()))?;
        s.validate()?;
        Ok(s)
    }

    /// Reads and parses a file.
    pub fn from_path(path: &str) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_string(),
            source,
        })?;
        Self::from_json(&text)
    }

    /// Pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// `Ok` when [`SceneFile::problems`] is empty.
    pub fn validate(&self) -> Result<(), SceneError> {
        let p = self.problems();
        if p.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid(p))
        }
    }

    /// The declared effects.
    pub fn effect_set(&self) -> Effects {
        Effects::of(&self.effects)
    }

    /// Validates and builds the world.
    pub fn build(&self) -> Result<World, SceneError> {
        self.validate()?;
        let mut bodies = BodySet::default();
        for b in &self.bodies {
            let shape = b.shape.shape();
            let material = b
                .material
                .as_ref()
                .and_then(|m| self.materials.iter().find(|x| &x.name == m))
                .map_or_else(Material::default, |m| Material {
                    friction: m.friction,
                    restitution: m.restitution,
                    rolling_resistance: m.rolling_resistance,
                });
            let mass = b
                .mass
                .unwrap_or_else(|| b.density.unwrap_or(0.0) * shape.volume());
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
                v(b.position),
                exp_so3(&v(b.rotation)),
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
        for j in &self.joints {
            let a = world.body(&j.body1).unwrap_or(0);
            let b = world.body(&j.body2).unwrap_or(0);
            if let Some(fj) = FreeJoint::new(
                &world.bodies,
                a,
                b,
                v(j.anchor),
                &j.kind,
                v(j.axis.unwrap_or([0.0; 3])),
            ) {
                world.add_joint(fj);
            }
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
                world.add_articulated(ArticulatedSystem::new(tree, q, qd));
            }
        }
        Ok(world)
    }
}
