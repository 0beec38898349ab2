//! `vphys peers multibody`: an articulated tree in contact, in our engine and in rapier3d's
//! multibodies (feature `rapier-peer`), back to back in one process: ms per step and the
//! deepest penetration into the ground over the run.
//!
//! The scene (default `host/physics/scenes/chain-on-boxes.json`: a 10-link chain on a floating
//! base falling onto twelve boxes) is translated for Rapier as follows:
//! * each link becomes a dynamic rigid body at its neutral-configuration pose, and each
//!   revolute joint a multibody revolute joint with the same axis and anchors. The root link
//!   is free, as our floating base is;
//! * each link shape becomes a collider at its pose, with the link's mass. Rapier computes the
//!   inertia from the collider's shape, where ours is the model's stated inertia: a small
//!   difference in the chain's rotational inertia;
//! * the boxes and the ground translate as in `peers rapier`: friction 0.5, sleeping off.
//!
//! Rapier runs at its defaults (4 solver iterations, soft contacts at 30 Hz).

use anyhow::Result;

use crate::run::{load, stats};
use virtual_physics::pipeline::BodyHandle;

/// The comparison's result.
#[derive(serde::Serialize)]
pub struct Report {
    scene: String,
    steps: u64,
    ours_ms: f64,
    rapier_ms: f64,
    ratio: f64,
    ours_max_ground_penetration_m: f64,
    rapier_max_ground_penetration_m: f64,
}

/// Ours: ms per step (median) and the deepest ground penetration (m) over the run.
fn ours(s: &virtual_physics::scene::SceneFile, steps: u64) -> Result<(f64, f64)> {
    let mut w = s.build()?;
    let ground: Vec<BodyHandle> = w
        .bodies()
        .filter(|b| b.shape().is_half_space())
        .map(|b| b.handle())
        .collect();
    let mut t = Vec::with_capacity(steps as usize);
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        let t0 = std::time::Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        for c in w.contacts() {
            if ground.contains(&c.a) || ground.contains(&c.b) {
                deepest = deepest.max(-c.min_separation());
            }
        }
    }
    Ok((stats(&t).0, deepest))
}

#[cfg(feature = "rapier-peer")]
fn rapier(s: &virtual_physics::scene::SceneFile, steps: u64) -> Result<(f64, f64)> {
    use anyhow::bail;
    use rapier3d::prelude::*;
    use virtual_physics::scene::{BodyKindDesc, ShapeDesc};

    let v = |a: [f64; 3]| Vector::new(a[0] as Real, a[1] as Real, a[2] as Real);
    let mut w = PhysicsWorld {
        gravity: v(s.gravity),
        ..PhysicsWorld::default()
    };
    w.integration_parameters.dt = s.dt as Real;
    let collider = |shape: &ShapeDesc| -> Result<ColliderBuilder> {
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
            _ => bail!("the multibody peer supports boxes, spheres, capsules and half-spaces"),
        })
    };
    let mut ground = Vec::new();
    for b in &s.bodies {
        let rb = match b.kind {
            BodyKindDesc::Dynamic => RigidBodyBuilder::dynamic(),
            BodyKindDesc::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
            BodyKindDesc::Fixed => RigidBodyBuilder::fixed(),
        }
        .translation(v(b.position))
        .rotation(v(b.rotation))
        .can_sleep(false);
        let mut col = collider(&b.shape)?.friction(0.5);
        if b.kind == BodyKindDesc::Dynamic {
            let m = b
                .mass
                .unwrap_or_else(|| b.density.unwrap_or(1.0) * b.shape.shape().volume());
            col = col.mass(m as Real);
        }
        let (_, c) = w.insert(rb, col);
        if matches!(b.shape, ShapeDesc::HalfSpace { .. }) {
            ground.push(c);
        }
    }
    for a in &s.articulated {
        let tree = a.model.build::<f64>()?;
        let q = a.q.clone().unwrap_or_else(|| tree.neutral_configuration());
        let poses = tree.body_poses(&q);
        let mut handles = Vec::new();
        for (k, body) in tree.bodies().iter().enumerate() {
            let pose = &poses[k];
            let rot = virtual_physics::algebra::log_so3(&pose.r);
            let h = w.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(v(pose.p.into()))
                    .rotation(v(rot.into()))
                    .can_sleep(false),
            );
            let shapes: Vec<_> = a.shapes.iter().filter(|ls| ls.link == body.name).collect();
            for ls in &shapes {
                let col = collider(&ls.shape)?
                    .translation(v(ls.position))
                    .rotation(v(ls.rotation))
                    .friction(0.5)
                    .mass((body.inertia.m / shapes.len() as f64) as Real);
                w.colliders.insert_with_parent(col, h, &mut w.bodies);
            }
            if let Some(p) = body.parent {
                let d = a.model.bodies[k].joint.clone();
                if d.kind != "revolute" {
                    bail!(
                        "link {}: the multibody peer supports revolute joints below the root",
                        body.name
                    );
                }
                let axis = d.axis.unwrap_or([0.0, 0.0, 1.0]);
                let joint = RevoluteJointBuilder::new(v(axis))
                    .local_anchor1(v(body.placement.p.into()))
                    .local_anchor2(Vector::ZERO);
                w.multibody_joints.insert(handles[p], h, joint, true);
            }
            handles.push(h);
        }
    }
    let mut t = Vec::with_capacity(steps as usize);
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        let t0 = std::time::Instant::now();
        w.step();
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        for &g in &ground {
            for pair in w.contact_pairs_with(g) {
                for m in pair.manifolds() {
                    for p in &m.points {
                        deepest = deepest.max(-(p.dist as f64));
                    }
                }
            }
        }
    }
    Ok((stats(&t).0, deepest))
}

#[cfg(not(feature = "rapier-peer"))]
fn rapier(_: &virtual_physics::scene::SceneFile, _: u64) -> Result<(f64, f64)> {
    Err(crate::exit::PeerMissing(
        "vphys was built without the rapier peer; rebuild with `cargo run -p \
         virtual-physics-cli --release --features rapier-peer -- peers multibody`"
            .to_string(),
    )
    .into())
}

/// Runs the comparison and prints a table, or the report as JSON.
pub fn run(scene: &str, steps: Option<u64>, json: bool) -> Result<()> {
    let s = load(scene, Some(false))?;
    let n = steps.or(s.steps).unwrap_or(600);
    let (ours_ms, ours_pen) = ours(&s, n)?;
    let (rapier_ms, rapier_pen) = rapier(&s, n)?;
    let r = Report {
        scene: scene.to_string(),
        steps: n,
        ours_ms,
        rapier_ms,
        ratio: ours_ms / rapier_ms,
        ours_max_ground_penetration_m: ours_pen,
        rapier_max_ground_penetration_m: rapier_pen,
    };
    if json {
        outln!("{}", serde_json::to_string(&r)?);
    } else {
        outln!("{scene}, {n} steps, sleeping off");
        outln!("| engine | ms per step (median) | deepest ground penetration (mm) |");
        outln!("|---|---|---|");
        outln!(
            "| ours | {:.3} | {:.2} |",
            r.ours_ms,
            1e3 * r.ours_max_ground_penetration_m
        );
        outln!(
            "| rapier3d multibodies | {:.3} | {:.2} |",
            r.rapier_ms,
            1e3 * r.rapier_max_ground_penetration_m
        );
        outln!("ratio ours / rapier: {:.2}", r.ratio);
    }
    Ok(())
}
