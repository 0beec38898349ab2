//! Criterion benches of the Table 3 operations, geometric form vs 6×6 matrix form (f64).
//! The same operations are timed in-process by `vphys table3`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use virtual_physics::measure::matrix_form as mf;
use virtual_physics::measure::table3::{eq6_step, Inputs};

fn bench(c: &mut Criterion) {
    let x: Inputs<f64> = Inputs::new();
    let v6 = mf::vec6_of_twist(&x.v);
    let w6 = mf::vec6_of_twist(&x.w);
    let j6 = mf::inertia_matrix(&x.j);
    let ja6 = x.ja.to_matrix6();

    let mut g = c.benchmark_group("Ad(SE3, se3)");
    g.bench_function("geometric", |b| {
        b.iter(|| black_box(&x.t).ad(black_box(&x.v)))
    });
    g.bench_function("matrix", |b| {
        b.iter(|| mf::ad(black_box(&x.t), black_box(&v6)))
    });
    g.finish();

    let mut g = c.benchmark_group("ad(se3, se3)");
    g.bench_function("geometric", |b| {
        b.iter(|| black_box(&x.v).ad(black_box(&x.w)))
    });
    g.bench_function("matrix", |b| {
        b.iter(|| mf::lie_ad(black_box(&x.v), black_box(&w6)))
    });
    g.finish();

    let mut g = c.benchmark_group("Inertia * se3");
    g.bench_function("geometric", |b| {
        b.iter(|| black_box(&x.j).mul_twist(black_box(&x.v)))
    });
    g.bench_function("matrix", |b| {
        b.iter(|| mf::inertia_mul(black_box(&j6), black_box(&v6)))
    });
    g.finish();

    let mut g = c.benchmark_group("Inertia.Xform(SE3)");
    g.bench_function("geometric", |b| {
        b.iter(|| black_box(&x.j).xform(black_box(&x.t)))
    });
    g.bench_function("matrix", |b| {
        b.iter(|| mf::xform(black_box(&j6), black_box(&x.t)))
    });
    g.finish();

    let mut g = c.benchmark_group("AInertia.Xform(SE3)");
    g.bench_function("geometric", |b| {
        b.iter(|| black_box(&x.ja).xform(black_box(&x.t)))
    });
    g.bench_function("matrix", |b| {
        b.iter(|| mf::xform(black_box(&ja6), black_box(&x.t)))
    });
    g.finish();

    let mut g = c.benchmark_group("Eq. (6) step");
    g.bench_function("geometric", |b| {
        b.iter(|| {
            eq6_step(
                black_box(&x.j),
                black_box(&x.ja),
                black_box(&x.v),
                black_box(&x.t),
            )
        })
    });
    g.bench_function("matrix", |b| {
        b.iter(|| {
            mf::eq7_step(
                black_box(&j6),
                black_box(&ja6),
                black_box(&v6),
                black_box(&x.t),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
