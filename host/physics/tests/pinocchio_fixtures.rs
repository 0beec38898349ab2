//! Forward dynamics against Pinocchio's `aba` (fixtures written by
//! `vphys peers fixtures`, i.e. `peers/pinocchio_fixtures.py`), and forward ∘ inverse
//! dynamics round trips on the same states.

mod common;

use common::rel_err;
use serde::Deserialize;
use virtual_physics::dynamics::{aba, rnea, Workspace};
use virtual_physics::model::builders::peer_models;
use virtual_physics::model::description::ModelDescription;

#[derive(Deserialize)]
struct State {
    q: Vec<f64>,
    qd: Vec<f64>,
    tau: Vec<f64>,
    qdd: Vec<f64>,
}

#[derive(Deserialize)]
struct Fixture {
    model: ModelDescription,
    states: Vec<State>,
}

fn load(name: &str) -> Fixture {
    let path = format!("{}/tests/fixtures/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn check(name: &str) {
    let fx = load(name);
    // The fixture was made from the model the builders make today.
    let current = peer_models()
        .into_iter()
        .find(|m| m.name == name)
        .expect("peer model");
    assert_eq!(
        fx.model, current,
        "{name}: fixture model differs from builders; regenerate with `vphys peers fixtures`"
    );
    let tree = fx.model.build::<f64>().expect("model builds");
    let mut ws = Workspace::new(&tree);
    assert!(!fx.states.is_empty());
    for (k, s) in fx.states.iter().enumerate() {
        let mut qdd = vec![0.0; tree.nv()];
        aba(&tree, &mut ws, &s.q, &s.qd, &s.tau, None, &mut qdd).unwrap();
        let e = rel_err(&qdd, &s.qdd);
        println!("{name} state {k}: relative error vs Pinocchio {e:e}");
        assert!(
            e <= 1e-9,
            "{name} state {k}: relative error vs Pinocchio {e:e}"
        );
        // forward ∘ inverse: τ → q̈ → τ
        let mut tau = vec![0.0; tree.nv()];
        rnea(&tree, &mut ws, &s.q, &s.qd, &qdd, None, &mut tau).unwrap();
        let e = rel_err(&tau, &s.tau);
        assert!(
            e <= 1e-10,
            "{name} state {k}: τ round trip relative error {e:e}"
        );
    }
}

#[test]
fn chain7_matches_pinocchio() {
    check("chain7");
}

#[test]
fn chain30_matches_pinocchio() {
    check("chain30");
}

#[test]
fn chain100_matches_pinocchio() {
    check("chain100");
}

#[test]
fn humanoid_matches_pinocchio() {
    check("humanoid");
}

#[test]
fn mass_ratio_matches_pinocchio() {
    check("mass_ratio");
}

#[test]
fn peer_models_round_trip_through_json() {
    for m in peer_models() {
        let back = ModelDescription::from_json(&m.to_json()).unwrap();
        assert_eq!(back, m);
        let tree = m.build::<f64>().unwrap();
        let again = ModelDescription::of(&m.name, &tree);
        assert_eq!(again.bodies.len(), m.bodies.len());
        for (a, b) in again.bodies.iter().zip(&m.bodies) {
            assert_eq!(a.joint, b.joint);
            assert_eq!(a.parent, b.parent);
            assert!((a.inertia.mass - b.inertia.mass).abs() < 1e-12);
            for k in 0..3 {
                assert!((a.inertia.com[k] - b.inertia.com[k]).abs() < 1e-12);
            }
            for k in 0..6 {
                assert!((a.inertia.inertia_com[k] - b.inertia.inertia_com[k]).abs() < 1e-12);
            }
        }
    }
    let h = virtual_physics::model::builders::humanoid();
    assert!(h.bodies.len() >= 20);
}
