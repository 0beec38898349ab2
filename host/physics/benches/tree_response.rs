//! What one contact row on a tree costs to prepare: the tree's response `M(q)⁻¹ Jᵀ` to a unit
//! impulse, by one articulated-body pass at zero velocity and gravity (what the engine does,
//! O(n) a row) against the joint-space mass matrix (composite rigid bodies, O(n²)) factorised
//! by Cholesky (O(n³)) and solved (O(n²) a row), on chains of 2 … 100 links.
//!
//!
//! `tree_step`: one step of a free-standing chain of 10, 100 and 200 links (gravity on, a
//! swinging state) with the default linearly implicit update (`symplectic-euler`) against one
//! with the explicit velocity products (`explicit-euler`: one ABA, the cost of the former
//! semi-implicit Euler step).
//!
//!     cargo bench -p virtual-physics --bench tree_response

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::Duration;
use virtual_physics::dynamics::{aba, cholesky_solve, mass_matrix, Workspace};
use virtual_physics::model::builders::{chain, random_state};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::IntegratorKind;

fn bench_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("tree_step");
    g.warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for n in [10, 100, 200] {
        let desc = chain(n);
        let (q, qd, _) = random_state(&desc.build::<f64>().expect("model"), 7);
        for kind in [
            IntegratorKind::ExplicitEuler,
            IntegratorKind::SymplecticEuler,
        ] {
            let tree = desc.build::<f64>().expect("model");
            let mut sys = ArticulatedSystem::new(tree, q.clone(), qd.clone());
            sys.set_integrator(kind);
            let start = (q.clone(), qd.clone());
            g.bench_function(format!("{}/{n}", kind.name()), |b| {
                b.iter(|| {
                    sys.q_mut().copy_from_slice(&start.0);
                    sys.qd_mut().copy_from_slice(&start.1);
                    sys.step(black_box(1e-3 / 12.0)).expect("step");
                    black_box(sys.qd()[0])
                })
            });
        }
    }
    g.finish();
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("tree_response");
    g.warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for n in [2, 10, 30, 100] {
        let mut desc = chain(n);
        desc.gravity = [0.0; 3];
        let tree = desc.build::<f64>().expect("model");
        let nv = tree.nv();
        let mut ws = Workspace::new(&tree);
        let (q, _, tau) = random_state(&tree, 7);
        let zero = vec![0.0; nv];
        let mut out = vec![0.0; nv];
        g.bench_function(format!("aba_row/{n}"), |b| {
            b.iter(|| {
                aba(
                    &tree,
                    &mut ws,
                    black_box(&q),
                    &zero,
                    black_box(&tau),
                    None,
                    &mut out,
                )
                .expect("aba");
                black_box(out[0])
            })
        });
        let mut m = vec![0.0; nv * nv];
        g.bench_function(format!("crba_cholesky_first_row/{n}"), |b| {
            b.iter(|| {
                mass_matrix(&tree, &mut ws, black_box(&q), &mut m).expect("crba");
                out.copy_from_slice(&tau);
                cholesky_solve(&mut m, nv, &mut out).expect("spd");
                black_box(out[0])
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench, bench_step);
criterion_main!(benches);
