//! Articulated problems: the heavy symmetric top in steady precession (analytic), a double
//! pendulum and a 10-link chain (against RKMK4 at [`REFERENCE_DT`]).

use super::{cpu_seconds, finite_or_inf, steps_in, Problem, Row, REFERENCE_DT};
use crate::algebra::{exp_so3, Vec3};
use crate::dynamics::{BodySet, DynamicsError};
use crate::geometry::V3;
use crate::model::description::{
    BodyDescription, InertiaDescription, JointDescription, ModelDescription, PlacementDescription,
};
use crate::pipeline::ArticulatedSystem;
use crate::pipeline::{Effect, Effects, IntegratorKind, SolverSettings, World};

/// Sample spacing of the comparisons (s); every swept step divides it.
pub(crate) const SAMPLE: f64 = 0.1;
/// Gravity (m/s², −z).
pub(crate) const G: f64 = 9.81;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// The heavy top: mass (kg), distance pivot → centre of mass (m), moments about the centre
/// (transverse, axial; kg·m²), tilt θ₀ (rad), spin ω₃ (rad/s), simulated time (s).
pub(crate) const TOP: (f64, f64, f64, f64, f64, f64, f64) =
    (1.0, 0.05, 0.002, 0.004, 0.5, 50.0, 5.0);

/// The top's steady precession rate `Ω` (rad/s, the slow root of
/// `I₁Ω² cos θ − I₃ω₃Ω + M g l = 0`, `I₁` about the pivot).
pub(crate) fn top_precession_rate() -> f64 {
    let (m, l, it, ia, theta, w3, _) = TOP;
    let i1 = it + m * l * l;
    let c = theta.cos();
    let disc = (ia * w3).powi(2) - 4.0 * i1 * c * m * G * l;
    (ia * w3 - disc.sqrt()) / (2.0 * i1 * c)
}

/// The analytic symmetry axis at time `t` (world): `(sin φ sin θ₀, −cos φ sin θ₀, cos θ₀)`,
/// `φ = Ω t` (z-x-z Euler angles, `R = Rz(φ) Rx(θ₀) Rz(ψ)`).
pub(crate) fn top_axis(t: f64) -> V3 {
    let theta = TOP.4;
    let (s, c) = (top_precession_rate() * t).sin_cos();
    V3::new(s * theta.sin(), -c * theta.sin(), theta.cos())
}

fn world_with(system: ArticulatedSystem, kind: IntegratorKind, dt: f64) -> World {
    let settings = SolverSettings {
        substeps: 1,
        ..SolverSettings::default()
    };
    let mut w = World::new(
        BodySet::default(),
        Effects::of(&[Effect::Gravity, Effect::Articulated]),
        dt,
        V3::new(0.0, 0.0, -G),
        settings,
    );
    w.set_integrator(kind);
    w.add_articulated(system);
    w
}

fn model(name: &str, bodies: Vec<BodyDescription>) -> ModelDescription {
    ModelDescription {
        name: name.into(),
        gravity: [0.0, 0.0, -G],
        bodies,
    }
}

/// The top: one body on a ball joint at the world origin, tilted by θ₀ about `x`, spinning.
pub(crate) fn top_world(kind: IntegratorKind, dt: f64) -> World {
    let (m, l, it, ia, theta, w3, _) = TOP;
    let d = model(
        "heavy-top",
        vec![BodyDescription {
            name: "top".into(),
            parent: None,
            joint: JointDescription::new("ball"),
            placement: PlacementDescription {
                rotation: IDENTITY,
                translation: [0.0; 3],
            },
            inertia: InertiaDescription {
                mass: m,
                com: [0.0, 0.0, l],
                inertia_com: [it, it, ia, 0.0, 0.0, 0.0],
            },
        }],
    );
    let tree = d.build::<f64>().expect("the top model is valid");
    let omega = top_precession_rate();
    let q = vec![theta, 0.0, 0.0];
    let qd = vec![0.0, omega * theta.sin(), w3];
    world_with(ArticulatedSystem::new(tree, q, qd), kind, dt)
}

/// A planar chain of `n` uniform rods (mass 1 kg, length `len` m) on revolute joints about `x`,
/// hanging along `−z`.
pub fn chain_model(n: usize, len: f64) -> ModelDescription {
    let rod = len * len / 12.0;
    let bodies = (0..n)
        .map(|k| BodyDescription {
            name: format!("rod{k}"),
            parent: k.checked_sub(1),
            joint: JointDescription::with_axis("revolute", [1.0, 0.0, 0.0]),
            placement: PlacementDescription {
                rotation: IDENTITY,
                translation: [0.0, 0.0, if k == 0 { 0.0 } else { -len }],
            },
            inertia: InertiaDescription {
                mass: 1.0,
                com: [0.0, 0.0, -len / 2.0],
                inertia_com: [rod, rod, 1e-4 * rod, 0.0, 0.0, 0.0],
            },
        })
        .collect();
    model(&format!("chain{n}"), bodies)
}

/// The double pendulum (2 rods of 0.5 m) or the 10-link chain (rods of 0.25 m), released
/// from rest at the problem's configuration.
pub fn chain_world(problem: Problem, kind: IntegratorKind, dt: f64) -> World {
    let (n, len, q) = match problem {
        Problem::DoublePendulum => (2, 0.5, vec![1.2, -0.6]),
        _ => {
            let mut q = vec![0.0; 10];
            q[0] = 1.0;
            q[4] = -0.5;
            (10, 0.25, q)
        }
    };
    let tree = chain_model(n, len)
        .build::<f64>()
        .expect("the chain model is valid");
    let qd = vec![0.0; n];
    world_with(ArticulatedSystem::new(tree, q, qd), kind, dt)
}

/// Simulated time of a problem (s).
pub(crate) fn duration(problem: Problem) -> f64 {
    match problem {
        Problem::HeavyTop => TOP.6,
        Problem::DoublePendulum => 5.0,
        _ => 3.0,
    }
}

/// Energy scale for relative drifts (J): `Σ m g ℓ` over the links, or the top's spin energy.
fn energy_scale(problem: Problem) -> f64 {
    match problem {
        Problem::HeavyTop => 0.5 * TOP.3 * TOP.5 * TOP.5,
        Problem::DoublePendulum => 2.0 * G * 0.5,
        _ => 10.0 * G * 0.25,
    }
}

/// A sampled run: per sample, the configuration (pendulum, chain) or the symmetry axis (top).
pub struct Samples {
    /// Samples.
    pub(crate) values: Vec<Vec<f64>>,
    /// CPU time of the stepping (s).
    pub(crate) cpu_s: f64,
    /// Energy change over the run relative to the problem's energy scale.
    pub(crate) energy_drift: f64,
}

/// Runs `problem` with `kind` at `dt`.
pub fn simulate(problem: Problem, kind: IntegratorKind, dt: f64) -> Result<Samples, DynamicsError> {
    let mut w = match problem {
        Problem::HeavyTop => top_world(kind, dt),
        _ => chain_world(problem, kind, dt),
    };
    let e0 = w.energy();
    let per = steps_in(SAMPLE, dt);
    let n = steps_in(duration(problem), SAMPLE);
    let mut values = Vec::with_capacity(n);
    let mut cpu = 0.0;
    let mut diverged = false;
    for _ in 0..n {
        let t0 = cpu_seconds();
        for _ in 0..per {
            if !diverged && w.step().is_err() {
                // A singular articulated inertia: the state has blown up (NaN or huge).
                diverged = true;
            }
        }
        cpu += cpu_seconds() - t0;
        if diverged {
            values.push(vec![f64::NAN; 3]);
            continue;
        }
        let a = &w.articulated[0];
        values.push(if problem == Problem::HeavyTop {
            let axis = exp_so3(&Vec3::new(a.q[0], a.q[1], a.q[2])) * V3::z();
            axis.as_slice().to_vec()
        } else {
            a.q.clone()
        });
    }
    Ok(Samples {
        values,
        cpu_s: cpu,
        energy_drift: if diverged {
            f64::NAN
        } else {
            (w.energy() - e0) / energy_scale(problem)
        },
    })
}

/// The converged reference of the pendulum and the chain (RKMK4 at [`REFERENCE_DT`]); the
/// top's reference is analytic and needs none.
pub fn reference(problem: Problem) -> Result<Option<Samples>, DynamicsError> {
    if problem == Problem::HeavyTop {
        return Ok(None);
    }
    simulate(problem, IntegratorKind::Rkmk4, REFERENCE_DT).map(Some)
}

/// One report row.
pub fn row(
    problem: Problem,
    kind: IntegratorKind,
    dt: f64,
    reference: Option<&Samples>,
) -> Result<Row, DynamicsError> {
    let s = simulate(problem, kind, dt)?;
    let mut err: f64 = 0.0;
    for (k, v) in s.values.iter().enumerate() {
        let e = match reference {
            None => {
                let a = top_axis(SAMPLE * (k + 1) as f64);
                let b = V3::new(v[0], v[1], v[2]);
                a.cross(&b).norm().atan2(a.dot(&b))
            }
            Some(_) if v.len() != reference.map_or(0, |r| r.values[k].len()) => f64::NAN,
            Some(r) => {
                v.iter()
                    .zip(&r.values[k])
                    .map(|(x, y)| (x - y).abs())
                    .fold(
                        0.0,
                        |m: f64, e| if e.is_nan() { f64::NAN } else { m.max(e) },
                    )
            }
        };
        err = if e.is_nan() {
            f64::INFINITY
        } else {
            err.max(e)
        };
    }
    let mut r = Row::new(problem, kind, dt);
    r.error = finite_or_inf(err);
    r.cpu_s_per_sim_s = s.cpu_s / duration(problem);
    r.energy_drift = Some(s.energy_drift);
    Ok(r)
}
