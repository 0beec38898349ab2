//! What one contact row on a tree costs to prepare: the tree's response `M(q)⁻¹ Jᵀ` to a unit
//! impulse, by one articulated-body pass at zero velocity and gravity (what the engine does,
//! O(n) a row) against the joint-space mass matrix (composite rigid bodies, O(n²)) factorised
//! by Cholesky (O(n³)) and solved (O(n²) a row), on chains of 2 … 100 links.
//!
//!     cargo bench -p virtual-physics --bench tree_response

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::Duration;
use virtual_physics::dynamics::{aba, cholesky_solve, mass_matrix, Workspace};
use virtual_physics::model::builders::{chain, random_state};

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

criterion_group!(benches, bench);
criterion_main!(benches);
