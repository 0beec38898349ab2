//! Worlds and checks the hard cases and the integrator tests share: the fast-spinning box,
//! a world of one articulated tree, its energy run, and f32 against f64 ABA.
#![allow(dead_code)]

use crate::scene_order::{body_at, tree_at};
use virtual_physics::algebra::Vec3;
use virtual_physics::dynamics::{aba, Workspace};
use virtual_physics::geometry::Shape;
use virtual_physics::measure::accuracy::articulated::chain_model;
use virtual_physics::measure::accuracy::free_body;
use virtual_physics::model::description::ModelDescription;
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::{BodyBuilder, Effect, Effects, IntegratorKind, World};

pub fn finite(v: &Vec3) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Panics on a NaN or infinite pose or velocity of any body.
pub fn assert_finite(w: &World, case: &str) {
    for i in 0..w.body_count() {
        assert!(
            finite(&body_at(w, i).position())
                && finite(&body_at(w, i).linear_velocity())
                && finite(&body_at(w, i).angular_velocity()),
            "{case}: body {i} is not finite at t = {}",
            w.time()
        );
    }
}

/// The accuracy report's tumbling box spinning at 200 rad/s about its intermediate axis, in a
/// world at the defaults a user gets (the game's 1/60 s step, 12 substeps: `hω` = 0.28 rad
/// per substep), gyroscopic term on, no gravity; `kind` replaces the default integrator.
pub fn fast_spinning_box(kind: Option<IntegratorKind>) -> World {
    let mut b = World::builder(Effects::of(&[Effect::Gyroscopic]))
        .dt(1.0 / 60.0)
        .gravity(Vec3::zeros());
    if let Some(kind) = kind {
        b = b.integrator(kind);
    }
    let mut w = b.build();
    w.insert_body(
        BodyBuilder::dynamic(Shape::Cuboid {
            half: Vec3::from(free_body::HALF_EXTENTS),
        })
        .mass(free_body::MASS)
        .angular_velocity(Vec3::new(0.0, 200.0, 2.0)),
    );
    w
}

/// A world holding one articulated system (gravity on) with `substeps` per 1/60 s step.
pub fn articulated_world(model: &ModelDescription, q: Vec<f64>, kind: IntegratorKind) -> World {
    let tree = model.build::<f64>().unwrap();
    let nv = tree.nv();
    let mut w = World::builder(Effects::of(&[Effect::Gravity, Effect::Articulated]))
        .dt(1.0 / 60.0)
        .gravity(Vec3::new(0.0, 0.0, -9.81))
        .integrator(kind)
        .build();
    w.insert_tree(ArticulatedSystem::new(tree, q, vec![0.0; nv]));
    w
}

/// Relative energy change of an articulated run, scaled by `Σ m g ℓ`.
pub fn articulated_run(w: &mut World, steps: usize, scale: f64) -> f64 {
    let e0 = w.energy();
    for _ in 0..steps {
        w.step().unwrap();
    }
    let a = tree_at(w, 0);
    assert!(
        a.q().iter().chain(a.qd()).all(|x| x.is_finite()),
        "articulated state not finite"
    );
    (w.energy() - e0) / scale
}

/// f32 and f64 ABA agree on `model` at `q`, `qd` (relative 1e-3 of the f64 norm).
pub fn aba_f32_matches_f64(model: &ModelDescription, q: &[f64], qd: &[f64]) {
    let t64 = model.build::<f64>().unwrap();
    let t32 = model.build::<f32>().unwrap();
    let nv = t64.nv();
    let (mut a64, mut a32) = (vec![0.0f64; nv], vec![0.0f32; nv]);
    let tau = vec![0.0; nv];
    aba(&t64, &mut Workspace::new(&t64), q, qd, &tau, None, &mut a64).unwrap();
    let c = |v: &[f64]| v.iter().map(|x| *x as f32).collect::<Vec<f32>>();
    aba(
        &t32,
        &mut Workspace::new(&t32),
        &c(q),
        &c(qd),
        &c(&tau),
        None,
        &mut a32,
    )
    .unwrap();
    let norm = a64.iter().map(|x| x * x).sum::<f64>().sqrt().max(1.0);
    for (x, y) in a64.iter().zip(&a32) {
        assert!(x.is_finite() && y.is_finite());
        assert!(
            (x - *y as f64).abs() < 1e-3 * norm,
            "f32 {y} vs f64 {x} (norm {norm})"
        );
    }
}

/// A 10-link revolute chain (links 0.2 m) alternating 1 kg and 0.1 g, its first joint at
/// 0.8 rad, and its energy scale `Σ m g ℓ` (J).
pub fn one_to_ten_thousand_chain() -> (ModelDescription, Vec<f64>, f64) {
    let mut chain = chain_model(10, 0.2);
    for (k, b) in chain.bodies.iter_mut().enumerate() {
        if k % 2 == 1 {
            b.inertia.mass *= 1e-4;
            for x in b.inertia.inertia_com.iter_mut() {
                *x *= 1e-4;
            }
        }
    }
    let mut q = vec![0.0; 10];
    q[0] = 0.8;
    (chain, q, 5.0 * 9.81 * 0.2 * 10.0)
}
