//! Criterion benches of the forward dynamics (ABA) on the peer models (f64).
//! `vphys peers aba` times the same against Pinocchio.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use virtual_physics::dynamics::{aba, Workspace};
use virtual_physics::model::builders::{chain, humanoid, random_state};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("aba");
    for desc in [chain(7), chain(30), chain(100), humanoid()] {
        let tree = desc.build::<f64>().expect("model");
        let mut ws = Workspace::new(&tree);
        let states: Vec<_> = (0..64).map(|k| random_state(&tree, 1000 + k)).collect();
        let mut qdd = vec![0.0; tree.nv()];
        let mut k = 0;
        g.bench_function(desc.name.as_str(), |b| {
            b.iter(|| {
                let (q, qd, tau) = &states[k];
                k = (k + 1) % states.len();
                aba(
                    &tree,
                    &mut ws,
                    black_box(q),
                    black_box(qd),
                    black_box(tau),
                    None,
                    &mut qdd,
                )
                .expect("aba");
                black_box(qdd[0])
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
