//! The torque-free tumbling box (paper's Dzhanibekov example) and the cost of one free-body
//! step of each integrator.

use super::{cpu_seconds, finite_or_inf, steps_in, Problem, Row, REFERENCE_DT};
use crate::dynamics::{BodyKind, BodySet, DynamicsError, Material};
use crate::geometry::{Shape, M3, V3};
use crate::pipeline::{
    Effect, Effects, FreeForces, FreeIntegrator, IntegratorKind, SolverSettings, World,
};

/// Half extents of the box (m): 0.1 × 0.2 × 0.4 m.
pub const HALF_EXTENTS: [f64; 3] = [0.05, 0.1, 0.2];
/// Mass (kg).
pub const MASS: f64 = 1.0;
/// Initial angular velocity, body frame (rad/s): near the intermediate (`y`) axis.
pub const OMEGA0: [f64; 3] = [0.0, 5.0, 0.05];
/// Simulated time (s).
pub const DURATION: f64 = 10.0;
/// Sample spacing of the comparison (s); every swept step divides it.
pub const SAMPLE: f64 = 0.1;

/// A world with the box alone, the `gyroscopic` effect, one substep, the integrator `kind`.
pub fn world(kind: IntegratorKind, dt: f64) -> World {
    let mut bodies = BodySet::default();
    let h = HALF_EXTENTS;
    bodies.push(
        "box".into(),
        BodyKind::Dynamic,
        Shape::Cuboid {
            half: V3::new(h[0], h[1], h[2]),
        },
        Material::default(),
        MASS,
        V3::zeros(),
        M3::identity(),
        V3::zeros(),
        V3::from(OMEGA0),
    );
    let settings = SolverSettings {
        substeps: 1,
        ..SolverSettings::default()
    };
    let mut w = World::new(
        bodies,
        Effects::of(&[Effect::Gyroscopic]),
        dt,
        V3::zeros(),
        settings,
    );
    w.set_integrator(kind);
    w
}

/// Body-frame angular velocity of the box (rad/s).
pub fn body_omega(w: &World) -> V3 {
    w.bodies.rot[0].tr_mul(&w.bodies.omega[0])
}

/// The body angular velocity at every sample time (`SAMPLE`, `2 SAMPLE`, … `DURATION`) of a run.
pub struct Trajectory {
    /// Samples (rad/s, body frame).
    pub omega: Vec<V3>,
    /// CPU time of the stepping (s).
    pub cpu_s: f64,
    /// Relative energy change.
    pub energy_drift: f64,
    /// `|L₁ − L₀| / |L₀|` (world angular momentum).
    pub momentum_drift: f64,
    /// Sign changes of `ω_y` (body) over the samples.
    pub flips: u32,
}

/// Runs the box for [`DURATION`] with `kind` at `dt`.
pub fn simulate(kind: IntegratorKind, dt: f64) -> Result<Trajectory, DynamicsError> {
    let mut w = world(kind, dt);
    let per_sample = steps_in(SAMPLE, dt);
    let samples = steps_in(DURATION, SAMPLE);
    let (e0, l0) = (w.energy(), w.bodies.angular_momentum());
    let mut omega = Vec::with_capacity(samples);
    let mut cpu = 0.0;
    let mut flips = 0;
    let mut sign = body_omega(&w).y > 0.0;
    for _ in 0..samples {
        let t0 = cpu_seconds();
        for _ in 0..per_sample {
            w.step()?;
        }
        cpu += cpu_seconds() - t0;
        let wb = body_omega(&w);
        if (wb.y > 0.0) != sign && wb.y != 0.0 {
            flips += 1;
            sign = wb.y > 0.0;
        }
        omega.push(wb);
    }
    Ok(Trajectory {
        omega,
        cpu_s: cpu,
        energy_drift: (w.energy() - e0) / e0,
        momentum_drift: (w.bodies.angular_momentum() - l0).norm() / l0.norm(),
        flips,
    })
}

/// The converged reference (RKMK4 at [`REFERENCE_DT`]).
pub fn reference() -> Result<Trajectory, DynamicsError> {
    simulate(IntegratorKind::Rkmk4, REFERENCE_DT)
}

/// One report row.
pub fn row(kind: IntegratorKind, dt: f64, reference: &Trajectory) -> Result<Row, DynamicsError> {
    let t = simulate(kind, dt)?;
    let w0 = V3::from(OMEGA0).norm();
    let err = t
        .omega
        .iter()
        .zip(&reference.omega)
        .map(|(a, b)| (a - b).norm() / w0)
        .fold(
            0.0,
            |m: f64, e| if e.is_nan() { f64::INFINITY } else { m.max(e) },
        );
    let mut r = Row::new(Problem::TumblingBox, kind, dt);
    r.error = finite_or_inf(err);
    r.cpu_s_per_sim_s = t.cpu_s / DURATION;
    r.energy_drift = Some(t.energy_drift);
    r.momentum_drift = Some(t.momentum_drift);
    r.flips = Some(t.flips);
    Ok(r)
}

/// Cost of one free-body step (velocity and pose stage, gyroscopic term on) per integrator.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StepCost {
    /// Integrator name.
    pub integrator: &'static str,
    /// Nanoseconds per body per step (best of the rounds).
    pub ns_per_body_step: f64,
    /// Ratio to the semi-implicit (symplectic) Euler step of the same run.
    pub ratio_to_symplectic_euler: f64,
}

/// Times the integrators' free-body step on `bodies` tumbling boxes (different spins) at
/// 1 ms: `rounds` rounds, each timing every integrator for `steps` steps (round robin, so
/// all see the same machine load); the best round per integrator counts.
pub fn step_cost(bodies: usize, steps: usize, rounds: usize) -> Vec<StepCost> {
    let h = 1e-3;
    let forces = FreeForces {
        gravity: V3::zeros(),
        gyroscopic: true,
        damping: None,
    };
    let make = || {
        let mut set = BodySet::default();
        let he = HALF_EXTENTS;
        for k in 0..bodies {
            let f = k as f64 / bodies.max(1) as f64;
            set.push(
                String::new(),
                BodyKind::Dynamic,
                Shape::Cuboid {
                    half: V3::new(he[0], he[1], he[2]),
                },
                Material::default(),
                MASS,
                V3::zeros(),
                M3::identity(),
                V3::new(0.1, 0.0, 0.0),
                V3::new(OMEGA0[0] + f, OMEGA0[1], OMEGA0[2] + f),
            );
        }
        set
    };
    let kinds = IntegratorKind::ALL;
    let mut best = vec![f64::INFINITY; kinds.len()];
    let mut sets: Vec<BodySet> = kinds.iter().map(|_| make()).collect();
    let mut integrators: Vec<FreeIntegrator> =
        kinds.iter().map(|k| FreeIntegrator::new(*k)).collect();
    for _ in 0..rounds {
        for (k, (set, integ)) in sets.iter_mut().zip(&mut integrators).enumerate() {
            let t0 = cpu_seconds();
            for _ in 0..steps {
                integ.integrate_velocities(set, h, &forces);
                integ.integrate_positions(set, h);
            }
            let ns = (cpu_seconds() - t0) * 1e9 / (steps * bodies) as f64;
            std::hint::black_box(&set.rot);
            best[k] = best[k].min(ns);
        }
    }
    let base = best[1];
    kinds
        .iter()
        .zip(best)
        .map(|(k, ns)| StepCost {
            integrator: k.name(),
            ns_per_body_step: ns,
            ratio_to_symplectic_euler: ns / base,
        })
        .collect()
}
