//! One scene file as a rapier3d world (feature `rapier-peer`): what `peers rapier`,
//! `peers multibody` and the suite step on the Rapier side.
//!
//! Body by body from the same [`SceneFile`]:
//! * free bodies keep their kind, position, rotation (a rotation vector in both engines),
//!   velocity and angular velocity; boxes as cuboids, spheres as balls, capsules along their
//!   z axis as `capsule_z`, half-spaces with their outward normal; a dynamic body's collider
//!   carries its mass (the scene's, or its density times its volume) and Rapier takes the
//!   inertia from the shape, as ours does;
//! * friction is the body's material's (0.5 without one): Rapier averages the pair's, ours
//!   takes the geometric mean, equal for equal materials;
//! * an articulated tree becomes one rigid body per link at its pose in the tree's
//!   configuration, joined by multibody revolute joints with the same axes and anchors, the
//!   root free as our floating base is; each link shape a collider with the link's mass
//!   shared among them. Rapier takes the links' inertia from their colliders where ours is the
//!   model's stated inertia (a small difference in a chain's rotational inertia). Only
//!   revolute joints below a free root translate.
//! * sleeping is `can_sleep` on every body, as asked.

use anyhow::{bail, Result};
use rapier3d::prelude::*;
use virtual_physics::scene::{BodyKindDesc, SceneFile, ShapeDesc};

/// A scene in rapier3d, and the handles the measurements read.
pub(crate) struct RapierScene {
    /// The world, stepped with `step()`.
    pub world: PhysicsWorld,
    /// The dynamic free bodies in scene order (the bodies whose drift is measured; ours
    /// counts the same, without the trees' links).
    pub dynamic: Vec<RigidBodyHandle>,
    /// The colliders of the half-spaces (the ground).
    pub ground: Vec<ColliderHandle>,
}

fn v(a: [f64; 3]) -> Vector {
    Vector::new(a[0] as Real, a[1] as Real, a[2] as Real)
}

fn collider(shape: &ShapeDesc) -> Result<ColliderBuilder> {
    Ok(match *shape {
        ShapeDesc::Box { half_extents: h } => {
            ColliderBuilder::cuboid(h[0] as Real, h[1] as Real, h[2] as Real)
        }
        ShapeDesc::Sphere { radius } => ColliderBuilder::ball(radius as Real),
        ShapeDesc::Capsule {
            radius,
            half_height,
        } => ColliderBuilder::capsule_z(half_height as Real, radius as Real),
        ShapeDesc::HalfSpace { normal } => {
            ColliderBuilder::halfspace(rapier3d::na::Unit::new_unchecked(v(normal).normalize()))
        }
        _ => bail!("the rapier peer translates boxes, spheres, capsules and half-spaces"),
    })
}

/// Builds scene `s` in rapier3d with sleeping on or off.
pub(crate) fn rapier_scene(s: &SceneFile, sleeping: bool) -> Result<RapierScene> {
    let mut world = PhysicsWorld {
        gravity: v(s.gravity),
        ..PhysicsWorld::default()
    };
    world.integration_parameters.dt = s.dt as Real;
    let mut dynamic = Vec::new();
    let mut ground = Vec::new();
    for (i, b) in s.bodies.iter().enumerate() {
        let friction = b
            .material
            .as_ref()
            .and_then(|m| s.materials.iter().find(|x| &x.name == m))
            .map_or(0.5, |m| m.friction);
        let rb = match b.kind {
            BodyKindDesc::Dynamic => RigidBodyBuilder::dynamic(),
            BodyKindDesc::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
            BodyKindDesc::Fixed => RigidBodyBuilder::fixed(),
        }
        .translation(v(b.position))
        .rotation(v(b.rotation))
        .linvel(v(b.velocity))
        .angvel(v(b.angular_velocity))
        .can_sleep(sleeping);
        let mut col = collider(&b.shape)
            .map_err(|e| anyhow::anyhow!("bodies[{i}]: {e}"))?
            .friction(friction as Real);
        if b.kind == BodyKindDesc::Dynamic {
            let m = b
                .mass
                .unwrap_or_else(|| b.density.unwrap_or(1.0) * b.shape.shape().volume());
            col = col.mass(m as Real);
        }
        let (h, c) = world.insert(rb, col);
        if b.kind == BodyKindDesc::Dynamic {
            dynamic.push(h);
        }
        if matches!(b.shape, ShapeDesc::HalfSpace { .. }) {
            ground.push(c);
        }
    }
    for (t, a) in s.articulated.iter().enumerate() {
        let tree = a.model.build::<f64>()?;
        let q = a.q.clone().unwrap_or_else(|| tree.neutral_configuration());
        let poses = tree.body_poses(&q);
        let mut links = Vec::new();
        for (k, body) in tree.bodies().iter().enumerate() {
            let pose = &poses[k];
            let rot = virtual_physics::algebra::log_so3(&pose.r);
            let h = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(v(pose.p.into()))
                    .rotation(v(rot.into()))
                    .can_sleep(sleeping),
            );
            let name = &body.name;
            let shapes: Vec<_> = a.shapes.iter().filter(|ls| &ls.link == name).collect();
            for ls in &shapes {
                let col = collider(&ls.shape)
                    .map_err(|e| anyhow::anyhow!("articulated[{t}] link {name}: {e}"))?
                    .translation(v(ls.position))
                    .rotation(v(ls.rotation))
                    .friction(0.5)
                    .mass((body.inertia.m / shapes.len() as f64) as Real);
                world
                    .colliders
                    .insert_with_parent(col, h, &mut world.bodies);
            }
            if let Some(p) = body.parent {
                let joint = &a.model.bodies[k].joint;
                if joint.kind != "revolute" {
                    bail!(
                        "articulated[{t}] link {name}: the rapier peer translates revolute \
                         joints below the root"
                    );
                }
                let axis = joint.axis.unwrap_or([0.0, 0.0, 1.0]);
                let joint = RevoluteJointBuilder::new(v(axis))
                    .local_anchor1(v(body.placement.p.into()))
                    .local_anchor2(Vector::ZERO);
                world.multibody_joints.insert(links[p], h, joint, true);
            }
            links.push(h);
        }
    }
    Ok(RapierScene {
        world,
        dynamic,
        ground,
    })
}
