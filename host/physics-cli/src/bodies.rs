//! What `vphys run` reports about individual bodies: each body's pose and velocity in the
//! world frame (`--bodies`), and how far the bodies moved from their start.
//!
//! Every read of the world's bodies goes through this module, so that it is the one place
//! that follows the library's body API.

use anyhow::{bail, Result};
use nalgebra::{Rotation3, UnitQuaternion};
use serde::Serialize;
use virtual_physics::algebra::Vec3;
use virtual_physics::dynamics::BodyKind;
use virtual_physics::pipeline::World;

/// One body at one step: a line of `vphys run --bodies`. All vectors in the world frame.
#[derive(Debug, Clone, Serialize)]
pub struct BodyLine<'a> {
    /// Step count since the start (the first printed step is 1).
    pub step: u64,
    /// Simulated time (s).
    pub t: f64,
    /// Index of the body in the scene's `bodies` list.
    pub body: usize,
    /// The body's name in the scene (may be empty).
    pub name: &'a str,
    /// `dynamic`, `kinematic` or `fixed`.
    pub kind: &'static str,
    /// Centre of mass (m, world).
    pub position_m: [f64; 3],
    /// Rotation world ← body as a unit quaternion `[w, x, y, z]`, sign chosen with `w ≥ 0`.
    pub quaternion_wxyz: [f64; 4],
    /// Velocity of the centre of mass (m/s, world).
    pub linear_velocity_mps: [f64; 3],
    /// Angular velocity (rad/s, world).
    pub angular_velocity_radps: [f64; 3],
    /// Distance of the centre of mass from where it started (m, 3D).
    pub displacement_m: f64,
}

fn kind_name(k: BodyKind) -> &'static str {
    match k {
        BodyKind::Dynamic => "dynamic",
        BodyKind::Kinematic => "kinematic",
        BodyKind::Fixed => "fixed",
    }
}

/// The bodies to print: all of them, or those with the given names (every name must exist).
pub fn select(world: &World, names: &[String]) -> Result<Vec<usize>> {
    let n = world.body_count();
    let name_of: Vec<&str> = world.bodies().map(|b| b.name()).collect();
    if names.is_empty() {
        return Ok((0..n).collect());
    }
    let mut out = Vec::new();
    for want in names {
        let found: Vec<usize> = (0..n).filter(|&i| name_of[i] == want.as_str()).collect();
        if found.is_empty() {
            let named: Vec<&str> = name_of
                .iter()
                .copied()
                .filter(|s| !s.is_empty())
                .take(12)
                .collect();
            if named.is_empty() {
                bail!("no body named '{want}': the scene's bodies have no names");
            }
            bail!(
                "no body named '{want}' in the scene (named bodies include: {})",
                named.join(", ")
            );
        }
        for i in found {
            if !out.contains(&i) {
                out.push(i);
            }
        }
    }
    Ok(out)
}

/// Every body's centre of mass now (m, world): the start that displacements refer to.
pub fn positions(world: &World) -> Vec<Vec3> {
    world.bodies().map(|b| b.position()).collect()
}

/// The line of body `i` at `step`, `start` being [`positions`] at step 0.
pub fn line<'w>(world: &'w World, step: u64, i: usize, start: &[Vec3]) -> BodyLine<'w> {
    let b = world.bodies().nth(i).expect("a selected body");
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(b.rotation()));
    let q = if q.w < 0.0 {
        -q.into_inner()
    } else {
        q.into_inner()
    };
    BodyLine {
        step,
        t: world.time(),
        body: i,
        name: b.name(),
        kind: kind_name(b.kind()),
        position_m: b.position().into(),
        quaternion_wxyz: [q.w, q.i, q.j, q.k],
        linear_velocity_mps: b.linear_velocity().into(),
        angular_velocity_radps: b.angular_velocity().into(),
        displacement_m: start.get(i).map_or(0.0, |p0| (b.position() - p0).norm()),
    }
}

/// How far the dynamic bodies moved from `start` (m): the largest 3D distance, the largest
/// horizontal (x, y) distance and the largest vertical (z) distance, each over all bodies.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Displacement {
    /// Largest `|p − p₀|` (m).
    pub max_3d: f64,
    /// Largest `√(Δx² + Δy²)` (m).
    pub max_horizontal: f64,
    /// Largest `|Δz|` (m).
    pub max_vertical: f64,
}

/// [`Displacement`] of the dynamic bodies since `start`.
pub fn displacement(world: &World, start: &[Vec3]) -> Displacement {
    let mut d = Displacement::default();
    for (b, p0) in world.bodies().zip(start) {
        if b.kind() == BodyKind::Dynamic {
            let v = b.position() - p0;
            d.max_3d = d.max_3d.max(v.norm());
            d.max_horizontal = d.max_horizontal.max((v.x * v.x + v.y * v.y).sqrt());
            d.max_vertical = d.max_vertical.max(v.z.abs());
        }
    }
    d
}
