//! `vphys peers parry`: box–box manifold cost, our SAT + clipping (f64) against parry3d's
//! `contact_manifold_cuboid_cuboid` (f32, the routine Rapier uses), on the three contact
//! configurations of the stacking scenes. Feature `rapier-peer` (parry comes with rapier).

use anyhow::Result;

/// Runs the measurement and prints a table or JSON.
#[cfg(feature = "rapier-peer")]
pub fn run(json: bool) -> Result<()> {
    use rapier3d::parry::math::{Pose, Vector};
    use rapier3d::parry::query::details::contact_manifold_cuboid_cuboid;
    use rapier3d::parry::query::ContactManifold;
    use rapier3d::parry::shape::Cuboid;
    use std::hint::black_box;
    use std::time::Instant;
    use virtual_physics::algebra::exp_so3;
    use virtual_physics::algebra::Vec3;
    use virtual_physics::geometry::Manifold;
    use virtual_physics::geometry::{box_box, BoxPose};

    // (name, rotation vector of A, B's centre, rotation vector of B); A at the origin.
    let q = std::f64::consts::FRAC_PI_4;
    let d = std::f64::consts::SQRT_2 - 0.001;
    type Case<'a> = (&'a str, [f64; 3], [f64; 3], [f64; 3]);
    let cases: [Case; 3] = [
        (
            "face (stacked, 1 mm overlap)",
            [0.0; 3],
            [0.0, 0.0, 0.999],
            [0.0; 3],
        ),
        (
            "face, rotated 45° (octagon)",
            [0.0; 3],
            [0.0, 0.0, 0.999],
            [0.0, 0.0, q],
        ),
        (
            "edge–edge (1 mm)",
            [q, 0.0, 0.0],
            [0.0, 0.0, d],
            [0.0, q, 0.0],
        ),
    ];
    let n = 200_000u32;
    let half = Vec3::repeat(0.5);
    let mut rows = Vec::new();
    for (name, a_aa, t, aa) in cases {
        // Ours.
        let ra = exp_so3(&Vec3::new(a_aa[0], a_aa[1], a_aa[2]));
        let rb = exp_so3(&Vec3::new(aa[0], aa[1], aa[2]));
        let pa = Vec3::zeros();
        let pb = Vec3::new(t[0], t[1], t[2]);
        let mut m = Manifold::new(0, 1);
        let mut best_ours = f64::INFINITY;
        let mut ours_points = 0;
        for _ in 0..5 {
            let t0 = Instant::now();
            for _ in 0..n {
                box_box(
                    black_box(BoxPose {
                        r: &ra,
                        p: &pa,
                        half: &half,
                    }),
                    black_box(BoxPose {
                        r: &rb,
                        p: &pb,
                        half: &half,
                    }),
                    0.02,
                    &mut m,
                );
                black_box(&m);
            }
            best_ours = best_ours.min(t0.elapsed().as_secs_f64() * 1e9 / n as f64);
            ours_points = m.points().len();
        }
        // Parry, from scratch each call (manifold cleared, as on a new pair).
        let c = Cuboid::new(Vector::new(0.5, 0.5, 0.5));
        // pos12 = pos1⁻¹ pos2.
        let r12 = virtual_physics::algebra::log_so3(&ra.tr_mul(&rb));
        let p12 = ra.tr_mul(&(pb - pa));
        let pos12 = Pose::new(
            Vector::new(p12.x as f32, p12.y as f32, p12.z as f32),
            Vector::new(r12.x as f32, r12.y as f32, r12.z as f32),
        );
        let mut pm: ContactManifold<(), ()> = ContactManifold::new();
        let mut best_parry = f64::INFINITY;
        let mut parry_points = 0;
        for _ in 0..5 {
            let t0 = Instant::now();
            for _ in 0..n {
                pm.clear();
                contact_manifold_cuboid_cuboid(black_box(&pos12), &c, &c, 0.02, &mut pm);
                black_box(&pm);
            }
            best_parry = best_parry.min(t0.elapsed().as_secs_f64() * 1e9 / n as f64);
            parry_points = pm.points.len();
        }
        rows.push((name, best_ours, ours_points, best_parry, parry_points));
    }
    if json {
        let r: Vec<_> = rows
            .iter()
            .map(|(name, o, op, p, pp)| {
                serde_json::json!({"case": name, "ours_ns": o, "ours_points": op,
                                   "parry_ns": p, "parry_points": pp})
            })
            .collect();
        outln!("{}", serde_json::json!({ "rows": r }));
    } else {
        outln!("box–box manifold, ns per call (best of 5 × {n}); ours f64, parry3d 0.31 f32");
        outln!(
            "{:<30} {:>9} {:>7} {:>9} {:>7}",
            "case",
            "ours ns",
            "points",
            "parry ns",
            "points"
        );
        for (name, o, op, p, pp) in rows {
            outln!("{name:<30} {o:>9.1} {op:>7} {p:>9.1} {pp:>7}");
        }
    }
    Ok(())
}

/// Without the feature: says how to rebuild.
#[cfg(not(feature = "rapier-peer"))]
pub fn run(_json: bool) -> Result<()> {
    Err(crate::exit::PeerMissing(
        "vphys was built without the rapier peer; rebuild with `cargo run -p \
         virtual-physics-cli --release --features rapier-peer -- peers parry`"
            .to_string(),
    )
    .into())
}
