//! The five integrators: selection (scene JSON and `World`), the default (semi-implicit Euler
//! with the implicit gyroscopic term), the
//! tumbling-box target (energy-momentum: |energy drift| ≤ 1e-6 and 3 flips at 1 ms), and
//! the measured order of each on the tumbling box and the double pendulum.

use virtual_physics::measure::accuracy::{articulated, free_body, Problem};
use virtual_physics::pipeline::{IntegratorKind, World};
use virtual_physics::scene::{builtin, SceneFile};

mod scene_order;
use scene_order::*;

#[test]
fn scenes_select_the_integrator_by_name_and_default_to_the_implicit_gyroscopic_step() {
    let s = builtin::ball_roll();
    assert_eq!(s.integrator, IntegratorKind::ImplicitGyroscopic);
    assert!(
        !s.to_json().contains("integrator"),
        "the default is not written"
    );
    for kind in IntegratorKind::ALL {
        let mut s = builtin::ball_roll();
        s.integrator = kind;
        let text = s.to_json();
        let written = text.contains(&format!("\"integrator\": \"{}\"", kind.name()));
        assert_eq!(written, kind != IntegratorKind::default(), "{text}");
        let back = SceneFile::from_json(&text).unwrap();
        assert_eq!(back.integrator, kind);
        let w = back.build().unwrap();
        assert_eq!(w.integrator(), kind);
        assert_eq!(IntegratorKind::from_name(kind.name()), Some(kind));
    }
    let mut text = builtin::ball_roll().to_json();
    text = text.replacen('{', "{\"integrator\": \"leapfrog\",", 1);
    let err = SceneFile::from_json(&text).unwrap_err().to_string();
    assert!(err.contains("leapfrog") && err.contains("rkmk4"), "{err}");
}

#[test]
fn set_integrator_reaches_articulated_trees() {
    let mut w: World =
        articulated::chain_world(Problem::DoublePendulum, IntegratorKind::Rkmk4, 0.01);
    assert_eq!(tree_at(&w, 0).integrator(), IntegratorKind::Rkmk4);
    w.set_integrator(IntegratorKind::ExplicitEuler);
    assert_eq!(tree_at(&w, 0).integrator(), IntegratorKind::ExplicitEuler);
}

/// The tumbling-box target: |energy drift| ≤ 1e-6 and the reference's 3 flips at 1 ms over 10 s.
#[test]
fn energy_momentum_meets_the_tumbling_box_target() {
    let t = free_body::simulate(IntegratorKind::EnergyMomentum, 1e-3).unwrap();
    assert!(
        t.energy_drift.abs() <= 1e-6,
        "energy drift {:e}",
        t.energy_drift
    );
    assert!(
        t.momentum_drift <= 1e-6,
        "momentum drift {:e}",
        t.momentum_drift
    );
    assert_eq!(t.flips, 3);
    // Semi-implicit Euler drifts by ~1.75 % here, as MuJoCo's Euler does.
    let s = free_body::simulate(IntegratorKind::SymplecticEuler, 1e-3).unwrap();
    assert!(
        s.energy_drift > 1e-2,
        "semi-implicit drift {:e}",
        s.energy_drift
    );
    // Catto's implicit step (the default) loses about as much.
    let c = free_body::simulate(IntegratorKind::ImplicitGyroscopic, 1e-3).unwrap();
    assert!(
        c.energy_drift < -1e-2,
        "implicit gyroscopic drift {:e}",
        c.energy_drift
    );
}

/// The observed order from the errors at `dt` and `dt/4`: `log2(e(dt)/e(dt/4)) / 2`.
fn order(e_coarse: f64, e_fine: f64) -> f64 {
    (e_coarse / e_fine).log2() / 2.0
}

#[test]
fn measured_orders_on_the_tumbling_box() {
    let reference = free_body::simulate(IntegratorKind::Rkmk4, 1.0 / 16000.0).unwrap();
    let err = |kind, dt| free_body::row(kind, dt, &reference).unwrap().error;
    for (kind, dt, expected) in [
        (IntegratorKind::ExplicitEuler, 1.0 / 2000.0, 1.0),
        (IntegratorKind::SymplecticEuler, 1.0 / 2000.0, 1.0),
        (IntegratorKind::ImplicitGyroscopic, 1.0 / 2000.0, 1.0),
        (IntegratorKind::EnergyMomentum, 1.0 / 1000.0, 2.0),
        (IntegratorKind::Rkmk4, 1.0 / 100.0, 4.0),
    ] {
        let p = order(err(kind, dt), err(kind, dt / 4.0));
        eprintln!("tumbling {kind}: {p:.2}");
        assert!(
            (p - expected).abs() < 0.3,
            "{kind}: order {p:.2}, expected {expected}"
        );
    }
}

#[test]
fn measured_orders_on_the_double_pendulum() {
    let p = Problem::DoublePendulum;
    let reference = articulated::simulate(p, IntegratorKind::Rkmk4, 1.0 / 8000.0).unwrap();
    let err = |kind, dt| {
        articulated::row(p, kind, dt, Some(&reference))
            .unwrap()
            .error
    };
    for (kind, dt, expected) in [
        (IntegratorKind::ExplicitEuler, 1.0 / 4000.0, 1.0),
        (IntegratorKind::SymplecticEuler, 1.0 / 1000.0, 1.0),
        (IntegratorKind::EnergyMomentum, 1.0 / 250.0, 2.0),
        (IntegratorKind::Rkmk4, 1.0 / 250.0, 4.0),
    ] {
        let q = order(err(kind, dt), err(kind, dt / 4.0));
        eprintln!("pendulum {kind}: {q:.2}");
        assert!(
            (q - expected).abs() < 0.35,
            "{kind}: order {q:.2}, expected {expected}"
        );
    }
}
