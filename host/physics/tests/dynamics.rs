//! Articulated-body dynamics: ABA against the mass matrix and RNEA on trees with every joint
//! type, the single-body Eq. (3), kinematics against finite differences, f32.

mod common;

use common::rel_err;
use virtual_physics::algebra::{dse3, se3, Inertia, Sym3, Vec3, SE3};
use virtual_physics::dynamics::{aba, cholesky_solve, mass_matrix, rigid_body, rnea, Workspace};
use virtual_physics::model::builders::random_state;
use virtual_physics::model::{
    ArticulatedTree, Ball, Cylindrical, Fixed, Free, Prismatic, Revolute, Universal,
};

fn body_inertia(k: usize) -> Inertia<f64> {
    let s = 1.0 + 0.1 * k as f64;
    Inertia::from_com(
        s,
        Vec3::new(0.03 * s, -0.02, 0.1),
        Sym3::new(0.02 * s, 0.025 * s, 0.03 * s, 0.001, -0.002, 0.0015),
    )
}

fn placement(k: usize) -> SE3<f64> {
    let a = 0.3 + 0.2 * k as f64;
    SE3::exp(&se3::new(
        Vec3::new(0.1 * a, -0.2, 0.3 * a.sin()),
        Vec3::new(0.05, 0.1 * a.cos(), 0.2),
    ))
}

/// A tree with every joint type, branching twice.
fn all_joints_tree(floating: bool) -> ArticulatedTree<f64> {
    let mut t = ArticulatedTree::new(Vec3::new(0.0, 0.0, -9.81));
    let root = if floating {
        t.add_body("root", None, SE3::identity(), Free, body_inertia(0))
            .unwrap()
    } else {
        t.add_body(
            "root",
            None,
            placement(0),
            Revolute::new(Vec3::new(0.0, 0.0, 1.0)),
            body_inertia(0),
        )
        .unwrap()
    };
    let a = t
        .add_body(
            "rod",
            Some(root),
            placement(1),
            Cylindrical::new(Vec3::new(1.0, 0.2, 0.0)),
            body_inertia(1),
        )
        .unwrap();
    let b = t
        .add_body(
            "hooke",
            Some(a),
            placement(2),
            Universal::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.6, 0.8)),
            body_inertia(2),
        )
        .unwrap();
    t.add_body("ball", Some(b), placement(3), Ball, body_inertia(3))
        .unwrap();
    let c = t
        .add_body(
            "slide",
            Some(root),
            placement(4),
            Prismatic::new(Vec3::new(0.3, 1.0, -0.2)),
            body_inertia(4),
        )
        .unwrap();
    let d = t
        .add_body("weld", Some(c), placement(5), Fixed, body_inertia(5))
        .unwrap();
    t.add_body(
        "tip",
        Some(d),
        placement(6),
        Revolute::new(Vec3::new(0.5, -0.5, 0.7)),
        body_inertia(6),
    )
    .unwrap();
    t.add_body("free_child", Some(b), placement(7), Free, body_inertia(7))
        .unwrap();
    t
}

fn random_vec(n: usize, seed: u64, scale: f64) -> Vec<f64> {
    (0..n)
        .map(|k| scale * ((k as f64 + 1.0) * 12.9898 + seed as f64 * 78.233).sin())
        .collect()
}

fn check_consistency(tree: &ArticulatedTree<f64>, seed: u64) {
    let (mut q, qd, tau) = random_state(tree, seed);
    // random_state knows the joint types by name; cover the rest with generic values.
    if q.len() != tree.nq() {
        q = random_vec(tree.nq(), seed, 1.0);
    }
    let nv = tree.nv();
    let mut ws = Workspace::new(tree);
    let mut qdd = vec![0.0; nv];
    aba(tree, &mut ws, &q, &qd, &tau, None, &mut qdd).unwrap();
    // forward ∘ inverse
    let mut back = vec![0.0; nv];
    rnea(tree, &mut ws, &q, &qd, &qdd, None, &mut back).unwrap();
    assert!(
        rel_err(&back, &tau) < 1e-12,
        "round trip {}",
        rel_err(&back, &tau)
    );
    // ABA = M⁻¹ (τ − h)
    let mut m = vec![0.0; nv * nv];
    mass_matrix(tree, &mut ws, &q, &mut m).unwrap();
    let mut h = vec![0.0; nv];
    rnea(tree, &mut ws, &q, &qd, &vec![0.0; nv], None, &mut h).unwrap();
    // M from RNEA columns equals the composite-body M.
    for j in 0..nv {
        let mut e = vec![0.0; nv];
        e[j] = 1.0;
        let mut col = vec![0.0; nv];
        let zero = vec![0.0; nv];
        rnea(tree, &mut ws, &q, &zero, &e, None, &mut col).unwrap();
        let mut g = vec![0.0; nv];
        rnea(tree, &mut ws, &q, &zero, &zero, None, &mut g).unwrap();
        for i in 0..nv {
            let mij = col[i] - g[i];
            let scale = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            assert!(
                (mij - m[i * nv + j]).abs() < 1e-12 * scale,
                "M[{i},{j}] {mij} vs {} (max {scale})",
                m[i * nv + j]
            );
        }
    }
    let mut rhs: Vec<f64> = tau.iter().zip(&h).map(|(t, h)| t - h).collect();
    cholesky_solve(&mut m, nv, &mut rhs).unwrap();
    assert!(
        rel_err(&qdd, &rhs) < 1e-11,
        "ABA vs M⁻¹(τ−h): {}",
        rel_err(&qdd, &rhs)
    );
}

#[test]
fn aba_consistent_with_mass_matrix_and_rnea_all_joint_types() {
    for floating in [false, true] {
        let tree = all_joints_tree(floating);
        for seed in 0..5 {
            check_consistency(&tree, seed);
        }
    }
}

#[test]
fn aba_consistent_on_peer_models() {
    for m in virtual_physics::model::builders::peer_models() {
        let tree = m.build::<f64>().unwrap();
        check_consistency(&tree, 3);
    }
}

#[test]
fn single_free_body_follows_eq3() {
    // A free body under gravity and an external wrench: ABA's V̇ equals Eq. (3) solved for V̇,
    // and the Euler equations at the centre of mass hold.
    let j = body_inertia(2);
    let mut t = ArticulatedTree::new(Vec3::new(0.0, 0.0, -9.81));
    t.add_body("b", None, SE3::identity(), Free, j).unwrap();
    let q = [0.3, -0.2, 0.5, 0.1, 0.2, 0.3];
    let qd = [0.7, -1.1, 0.4, 0.2, -0.3, 0.5];
    let tau = [0.1, 0.2, -0.3, 1.0, -2.0, 0.5];
    let fext = [dse3::new(
        Vec3::new(0.05, 0.0, -0.1),
        Vec3::new(0.3, 0.1, 0.0),
    )];
    let mut ws = Workspace::new(&t);
    let mut qdd = [0.0; 6];
    aba(&t, &mut ws, &q, &qd, &tau, Some(&fext), &mut qdd).unwrap();
    let pose = t.body_poses(&q)[0];
    let v = se3::from_array(qd);
    // Total wrench in the body frame: joint wrench + external + gravity (m g at the COM).
    let g_body = pose.r.transpose() * Vec3::new(0.0, 0.0, -9.81);
    let fg = dse3::new(j.h.cross(&(g_body * 1.0)), g_body * j.m);
    let total = dse3::from_array(tau) + fext[0] + fg;
    let expect = rigid_body::acceleration(&j, &v, &total);
    assert!(
        common::close6(qdd, expect.to_array(), 1e-12),
        "{qdd:?} vs {expect:?}"
    );
    // Eq. (3) forwards gives the wrench back.
    let back = rigid_body::wrench(&j, &v, &expect);
    assert!(common::close6(back.to_array(), total.to_array(), 1e-12));
    // Euler at the centre of mass: τ_c = I_c ω̇ + ω × I_c ω (a classical check of the sign).
    let jc = Inertia::from_com(
        2.0,
        Vec3::zeros(),
        Sym3::new(0.3, 0.4, 0.5, 0.01, 0.02, 0.03),
    );
    let w = se3::new(Vec3::new(0.3, -0.8, 1.2), Vec3::zeros());
    let wd = se3::new(Vec3::new(0.1, 0.2, -0.4), Vec3::zeros());
    let f = rigid_body::wrench(&jc, &w, &wd);
    let ic = jc.i.to_matrix();
    let euler = ic * wd.w + w.w.cross(&(ic * w.w));
    assert!((f.m - euler).norm() < 1e-14);
}

#[test]
fn velocities_and_accelerations_match_finite_differences() {
    // Joints whose q̇ is dq/dt (revolute, prismatic, cylindrical, universal): body velocities
    // are the finite differences of the poses, body accelerations those of the velocities —
    // this checks the universal joint's Ṡ q̇ term.
    let mut t = ArticulatedTree::new(Vec3::zeros());
    let a = t
        .add_body(
            "a",
            None,
            placement(0),
            Universal::new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.6, 0.8)),
            body_inertia(0),
        )
        .unwrap();
    let b = t
        .add_body(
            "b",
            Some(a),
            placement(1),
            Cylindrical::new(Vec3::new(0.0, 1.0, 0.3)),
            body_inertia(1),
        )
        .unwrap();
    let c = t
        .add_body(
            "c",
            Some(b),
            placement(2),
            Universal::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0)),
            body_inertia(2),
        )
        .unwrap();
    t.add_body(
        "d",
        Some(c),
        placement(3),
        Prismatic::new(Vec3::new(1.0, 1.0, 0.0)),
        body_inertia(3),
    )
    .unwrap();
    t.add_body(
        "e",
        Some(a),
        placement(4),
        Revolute::new(Vec3::new(0.2, 0.3, 1.0)),
        body_inertia(4),
    )
    .unwrap();
    let nv = t.nv();
    let q0 = random_vec(nv, 1, 1.0);
    let qd0 = random_vec(nv, 2, 1.0);
    let qdd0 = random_vec(nv, 3, 1.0);
    let path = |s: f64| -> (Vec<f64>, Vec<f64>) {
        let q = (0..nv)
            .map(|k| q0[k] + qd0[k] * s + 0.5 * qdd0[k] * s * s)
            .collect();
        let qd = (0..nv).map(|k| qd0[k] + qdd0[k] * s).collect();
        (q, qd)
    };
    let mut ws = Workspace::new(&t);
    let mut tau = vec![0.0; nv];
    rnea(&t, &mut ws, &q0, &qd0, &qdd0, None, &mut tau).unwrap();
    let (v, acc) = (ws.velocities().to_vec(), ws.accelerations().to_vec());
    let h = 1e-5;
    let velocities_at = |s: f64, ws: &mut Workspace<f64>| {
        let (q, qd) = path(s);
        let mut tau = vec![0.0; nv];
        rnea(&t, ws, &q, &qd, &vec![0.0; nv], None, &mut tau).unwrap();
        ws.velocities().to_vec()
    };
    let vp = velocities_at(h, &mut ws);
    let vm = velocities_at(-h, &mut ws);
    let (qp, _) = path(h);
    let (qm, _) = path(-h);
    let (pp, pm) = (t.body_poses(&qp), t.body_poses(&qm));
    for i in 0..t.len() {
        // V = (T⁻¹ Ṫ)^∨ ≈ Log(T(−h)⁻¹ T(h)) / 2h
        let fd = (pm[i].inverse() * pp[i]).log() * (0.5 / h);
        assert!(
            common::close6(fd.to_array(), v[i].to_array(), 1e-7),
            "V {i}: {fd:?} vs {:?}",
            v[i]
        );
        let fda = (vp[i] - vm[i]) * (0.5 / h);
        assert!(
            common::close6(fda.to_array(), acc[i].to_array(), 1e-7),
            "V̇ {i}: {fda:?} vs {:?}",
            acc[i]
        );
    }
}

#[test]
fn works_in_f32() {
    let desc = virtual_physics::model::builders::chain(7);
    let t64 = desc.build::<f64>().unwrap();
    let t32 = desc.build::<f32>().unwrap();
    let (q, qd, tau) = random_state(&t64, 9);
    let mut a64 = vec![0.0; 7];
    aba(
        &t64,
        &mut Workspace::new(&t64),
        &q,
        &qd,
        &tau,
        None,
        &mut a64,
    )
    .unwrap();
    let f = |x: &Vec<f64>| x.iter().map(|&v| v as f32).collect::<Vec<f32>>();
    let mut a32 = vec![0.0f32; 7];
    aba(
        &t32,
        &mut Workspace::new(&t32),
        &f(&q),
        &f(&qd),
        &f(&tau),
        None,
        &mut a32,
    )
    .unwrap();
    let a32: Vec<f64> = a32.iter().map(|&x| x as f64).collect();
    assert!(rel_err(&a32, &a64) < 1e-3, "{}", rel_err(&a32, &a64));
}

#[test]
fn wrong_sizes_are_errors() {
    let t = all_joints_tree(true);
    let mut ws = Workspace::new(&t);
    let mut qdd = vec![0.0; t.nv()];
    let q = t.neutral_configuration();
    let e = aba(
        &t,
        &mut ws,
        &q,
        &vec![0.0; t.nv() - 1],
        &vec![0.0; t.nv()],
        None,
        &mut qdd,
    );
    assert!(matches!(
        e,
        Err(virtual_physics::dynamics::DynamicsError::Dimension { what: "qd", .. })
    ));
    let other = all_joints_tree(false);
    let e = aba(
        &other,
        &mut ws,
        &other.neutral_configuration(),
        &vec![0.0; other.nv()],
        &vec![0.0; other.nv()],
        None,
        &mut vec![0.0; other.nv()],
    );
    assert!(e.is_err());
    // A massless leaf is singular.
    let mut m = ArticulatedTree::new(Vec3::zeros());
    m.add_body(
        "ghost",
        None,
        SE3::identity(),
        Revolute::new(Vec3::new(0.0, 0.0, 1.0)),
        Inertia::zeros(),
    )
    .unwrap();
    let mut ws = Workspace::new(&m);
    let e = aba(&m, &mut ws, &[0.0], &[0.0], &[1.0], None, &mut [0.0]);
    assert_eq!(
        e,
        Err(virtual_physics::dynamics::DynamicsError::Singular { body: 0 })
    );
    // Parents must come first.
    let mut bad = ArticulatedTree::new(Vec3::zeros());
    assert!(bad
        .add_body("x", Some(0), SE3::identity(), Ball, body_inertia(0))
        .is_err());
}
