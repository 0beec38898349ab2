//! Contact problems: the ball bouncing and rolling on cloth (analytic rebound height and
//! stopping distance) and towers of boxes (sink and drift against the solver's substeps).

use std::collections::BTreeMap;

use super::{cpu_seconds, finite_or_inf, steps_in, Problem, Row};
use crate::dynamics::DynamicsError;
use crate::pipeline::{Effect, IntegratorKind, World};
use crate::scene::{builtin, SceneError, SceneFile};

/// Errors of the contact problems.
#[derive(Debug, thiserror::Error)]
pub enum ContactProblemError {
    /// The scene did not build.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A step failed.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
}

/// Ball restitution against the cloth (–).
pub(crate) const RESTITUTION: f64 = 0.5;
/// Drop height of the ball's centre above its resting height (m).
pub(crate) const DROP: f64 = 0.2;
/// Rolling resistance of the cloth (–) and the ball's initial speed (m/s).
pub(crate) const ROLLING: (f64, f64) = (0.05, 1.0);
/// Gravity (m/s²).
const G: f64 = 9.81;

/// The ball scene (built-in `ball-roll`) with restitution on, one substep, the integrator.
fn ball_scene(kind: IntegratorKind, dt: f64) -> SceneFile {
    let mut s = builtin::ball_roll();
    s.effects.push(Effect::Restitution);
    s.effects.push(Effect::ContinuousCollision);
    s.materials[1].restitution = RESTITUTION;
    s.materials[0].rolling_resistance = ROLLING.0;
    s.solver.substeps = 1;
    s.dt = dt;
    s.integrator = kind;
    s
}

fn build(s: &SceneFile) -> Result<(World, usize), ContactProblemError> {
    let w = s.build()?;
    let b = w.body_index("ball").unwrap_or(1);
    Ok((w, b))
}

/// First rebound apex above the resting height (m) and CPU seconds, from a drop of [`DROP`].
pub(crate) fn bounce(
    kind: IntegratorKind,
    dt: f64,
) -> Result<(f64, f64, f64), ContactProblemError> {
    let mut s = ball_scene(kind, dt);
    s.bodies[1].velocity = [0.0; 3];
    s.bodies[1].angular_velocity = [0.0; 3];
    let r = 0.0175;
    s.bodies[1].position[2] = r + DROP;
    let (mut w, b) = build(&s)?;
    let n = steps_in(1.0, dt);
    let mut bounced = false;
    let mut apex: f64 = 0.0;
    let mut cpu = 0.0;
    for _ in 0..n {
        let t0 = cpu_seconds();
        w.step()?;
        cpu += cpu_seconds() - t0;
        let vz = w.bodies.vel[b].z;
        if !bounced && vz > 0.0 {
            bounced = true;
        }
        if bounced {
            apex = apex.max(w.bodies.pos[b].z - r);
            if vz < 0.0 {
                break;
            }
        }
    }
    Ok((apex, cpu, w.max_penetration()))
}

/// Distance (m) the ball rolls before it stops (speed < 1 mm/s), and CPU seconds.
pub(crate) fn roll(kind: IntegratorKind, dt: f64) -> Result<(f64, f64, f64), ContactProblemError> {
    let s = ball_scene(kind, dt);
    let (mut w, b) = build(&s)?;
    let n = steps_in(6.0, dt);
    let mut cpu = 0.0;
    let x0 = w.bodies.pos[b].x;
    for _ in 0..n {
        let t0 = cpu_seconds();
        w.step()?;
        cpu += cpu_seconds() - t0;
        if w.bodies.vel[b].norm() < 1e-3 {
            break;
        }
    }
    Ok((w.bodies.pos[b].x - x0, cpu, w.time))
}

/// Analytic rebound height `e² h₀` (m) and stopping distance `v₀² / (2 · 5/7 μ_r g)` (m) of a
/// solid sphere rolling without slipping.
pub(crate) fn analytic() -> (f64, f64) {
    let (mu, v0) = ROLLING;
    (
        RESTITUTION * RESTITUTION * DROP,
        v0 * v0 / (2.0 * 5.0 / 7.0 * mu * G),
    )
}

/// One report row of the ball problem.
pub fn ball_row(kind: IntegratorKind, dt: f64) -> Result<Row, ContactProblemError> {
    let (apex, cpu_b, pen) = bounce(kind, dt)?;
    let (dist, cpu_r, t_roll) = roll(kind, dt)?;
    let (apex_ref, dist_ref) = analytic();
    let e_b = (apex - apex_ref).abs() / apex_ref;
    let e_r = (dist - dist_ref).abs() / dist_ref;
    let mut r = Row::new(Problem::BallOnCloth, kind, dt);
    r.error = finite_or_inf(e_b.max(e_r));
    // Simulated seconds: the bounce up to its apex plus the roll.
    let sim = (2.0 * DROP / G).sqrt() + RESTITUTION * (2.0 * G * DROP).sqrt() / G + t_roll;
    r.cpu_s_per_sim_s = (cpu_b + cpu_r) / sim;
    r.penetration = Some(pen);
    r.detail = BTreeMap::from([
        ("rebound_m", apex),
        ("rebound_analytic_m", apex_ref),
        ("rolling_distance_m", dist),
        ("rolling_distance_analytic_m", dist_ref),
    ]);
    Ok(r)
}

/// The towers scene of the report: `towers-1120` (8 × 7 towers of 20) or, quick, 2 × 2 towers
/// of 10 (`towers-40`).
pub fn towers_scene(quick: bool) -> SceneFile {
    if quick {
        builtin::towers(2, 2, 10)
    } else {
        builtin::towers(8, 7, 20)
    }
}

/// Towers with `substeps` solver substeps for `steps` steps of 1/60 s: error = the largest
/// sink or horizontal drift of any box (m).
pub fn towers_row(
    kind: IntegratorKind,
    substeps: usize,
    steps: usize,
    quick: bool,
) -> Result<Row, ContactProblemError> {
    let mut s = towers_scene(quick);
    s.solver.substeps = substeps as i64;
    s.integrator = kind;
    let mut w = s.build()?;
    let start = w.bodies.pos.clone();
    let t0 = cpu_seconds();
    for _ in 0..steps {
        w.step()?;
    }
    let cpu = cpu_seconds() - t0;
    let (mut horizontal, mut sink): (f64, f64) = (0.0, 0.0);
    for (i, p0) in start.iter().enumerate() {
        if w.bodies.inv_mass[i] > 0.0 {
            let d = w.bodies.pos[i] - p0;
            horizontal = horizontal.max((d.x * d.x + d.y * d.y).sqrt());
            sink = sink.max(-d.z);
        }
    }
    let mut r = Row::new(Problem::Towers, kind, s.dt / substeps as f64);
    r.error = finite_or_inf(horizontal.max(sink));
    r.cpu_s_per_sim_s = cpu / (steps as f64 * s.dt);
    r.substeps = Some(substeps);
    r.penetration = Some(w.max_penetration());
    r.detail = BTreeMap::from([("max_sink_m", sink), ("max_horizontal_drift_m", horizontal)]);
    Ok(r)
}
