//! The cost of the ball's time of impact: one swept-sphere cast per shape, and one world
//! step of the goal-mouth scene (`tests/goal_mouth_scene`) with a 15 m/s ball passing 1 mm
//! beside the post, with and without the continuous-collision effect.
//!
//!     cargo bench -p virtual-physics --bench ccd

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use virtual_physics::algebra::{Mat3, Vec3};
use virtual_physics::geometry::{sphere_cast, Shape};

#[path = "../tests/goal_mouth_scene/mod.rs"]
mod goal_mouth_scene;
use goal_mouth_scene::*;

fn casts(c: &mut Criterion) {
    let r = 0.0175;
    let (rot, pos, still) = (Mat3::identity(), Vec3::zeros(), Vec3::zeros());
    let cuboid = Shape::Cuboid {
        half: Vec3::new(0.025, 0.15, 0.08),
    };
    let cylinder = Shape::Cylinder {
        radius: 0.008,
        half_height: 0.6,
    };
    let mut g = c.benchmark_group("sphere_cast");
    // Onto a box's edge (the post), and past it 1 mm clear.
    let (c_edge, c_miss) = (
        Vec3::new(-0.05, -0.15 - 0.5 * r, 0.0),
        Vec3::new(-0.05, -0.15 - r - 1e-3, 0.0),
    );
    let d = Vec3::new(0.015, 0.0, 0.0) * 3.0;
    g.bench_function("box edge hit", |b| {
        b.iter(|| sphere_cast(black_box(&c_edge), &d, r, &cuboid, &rot, &pos, &still))
    });
    g.bench_function("box miss by 1 mm", |b| {
        b.iter(|| sphere_cast(black_box(&c_miss), &d, r, &cuboid, &rot, &pos, &still))
    });
    // Across a rod (the cylinder's side), and past it.
    let c_rod = Vec3::new(-0.04, 0.0, 0.0);
    let c_past = Vec3::new(-0.04, 0.0, 0.0) + Vec3::new(0.0, 0.03, 0.0);
    let dz = Vec3::new(0.06, 0.0, 0.0);
    let lying =
        virtual_physics::algebra::exp_so3(&Vec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0));
    g.bench_function("cylinder side hit", |b| {
        b.iter(|| sphere_cast(black_box(&c_rod), &dz, r, &cylinder, &lying, &pos, &still))
    });
    g.bench_function("cylinder miss", |b| {
        b.iter(|| sphere_cast(black_box(&c_past), &dz, r, &cylinder, &lying, &pos, &still))
    });
    g.finish();
}

fn steps(c: &mut Criterion) {
    let p0 = Vec3::new(HL - 0.03, GW - R - 1e-3, 0.5 * GH);
    let v0 = Vec3::new(15.0, 0.0, 0.0);
    let mut g = c.benchmark_group("goal_mouth_step");
    for (name, effects) in [
        (
            "ccd on",
            r#"["contacts", "friction", "restitution", "continuous_collision"]"#,
        ),
        ("ccd off", r#"["contacts", "friction", "restitution"]"#),
    ] {
        let mut w = scene_with(p0, v0, effects);
        let h = w.body_named("ball").unwrap();
        g.bench_function(name, |b| {
            b.iter(|| {
                // The same step each time: the ball 30 mm before the goal line.
                w.body_mut(h)
                    .unwrap()
                    .set_position(p0)
                    .set_linear_velocity(v0);
                w.step().unwrap();
            })
        });
    }
    g.finish();
}

criterion_group!(benches, casts, steps);
criterion_main!(benches);
