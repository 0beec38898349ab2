//! `vphys peers multibody`: an articulated tree in contact, in our engine and in rapier3d's
//! multibodies (feature `rapier-peer`), back to back in one process: ms per step and the
//! deepest penetration into the ground over the run.
//!
//! The scene (default `host/physics/scenes/chain-on-boxes.json`: a 10-link chain on a floating
//! base falling onto twelve boxes) is translated for Rapier by `rapier_scene`: each link a
//! rigid body joined to its parent by a multibody revolute joint, the root free as our
//! floating base is.
//!
//! Rapier runs at its defaults (4 solver iterations, soft contacts at 30 Hz).

use anyhow::Result;

use crate::run::{load, stats};
use virtual_physics::pipeline::BodyHandle;

/// The comparison's result.
#[derive(serde::Serialize)]
pub struct Report {
    scene: String,
    steps: u64,
    ours_ms: f64,
    rapier_ms: f64,
    ratio: f64,
    ours_max_ground_penetration_m: f64,
    rapier_max_ground_penetration_m: f64,
}

/// Ours: ms per step (median) and the deepest ground penetration (m) over the run.
fn ours(s: &virtual_physics::scene::SceneFile, steps: u64) -> Result<(f64, f64)> {
    let mut w = s.build()?;
    let ground: Vec<BodyHandle> = w
        .bodies()
        .filter(|b| b.shape().is_half_space())
        .map(|b| b.handle())
        .collect();
    let mut t = Vec::with_capacity(steps as usize);
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        let t0 = std::time::Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        for c in w.contacts() {
            if ground.contains(&c.a) || ground.contains(&c.b) {
                deepest = deepest.max(-c.min_separation());
            }
        }
    }
    Ok((stats(&t).0, deepest))
}

#[cfg(feature = "rapier-peer")]
fn rapier(s: &virtual_physics::scene::SceneFile, steps: u64) -> Result<(f64, f64)> {
    let crate::rapier_scene::RapierScene {
        world: mut w,
        ground,
        ..
    } = crate::rapier_scene::rapier_scene(s, false)?;
    let mut t = Vec::with_capacity(steps as usize);
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        let t0 = std::time::Instant::now();
        w.step();
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        for &g in &ground {
            for pair in w.contact_pairs_with(g) {
                for m in pair.manifolds() {
                    for p in &m.points {
                        deepest = deepest.max(-(p.dist as f64));
                    }
                }
            }
        }
    }
    Ok((stats(&t).0, deepest))
}

#[cfg(not(feature = "rapier-peer"))]
fn rapier(_: &virtual_physics::scene::SceneFile, _: u64) -> Result<(f64, f64)> {
    Err(crate::exit::PeerMissing(
        "vphys was built without the rapier peer; rebuild with `cargo run -p \
         virtual-physics-cli --release --features rapier-peer -- peers multibody`"
            .to_string(),
    )
    .into())
}

/// Runs the comparison and prints a table, or the report as JSON.
pub fn run(scene: &str, steps: Option<u64>, json: bool) -> Result<()> {
    let s = load(scene, Some(false))?;
    let n = steps.or(s.steps).unwrap_or(600);
    let (ours_ms, ours_pen) = ours(&s, n)?;
    let (rapier_ms, rapier_pen) = rapier(&s, n)?;
    let r = Report {
        scene: scene.to_string(),
        steps: n,
        ours_ms,
        rapier_ms,
        ratio: ours_ms / rapier_ms,
        ours_max_ground_penetration_m: ours_pen,
        rapier_max_ground_penetration_m: rapier_pen,
    };
    if json {
        outln!("{}", serde_json::to_string(&r)?);
    } else {
        outln!("{scene}, {n} steps, sleeping off");
        outln!("| engine | ms per step (median) | deepest ground penetration (mm) |");
        outln!("|---|---|---|");
        outln!(
            "| ours | {:.3} | {:.2} |",
            r.ours_ms,
            1e3 * r.ours_max_ground_penetration_m
        );
        outln!(
            "| rapier3d multibodies | {:.3} | {:.2} |",
            r.rapier_ms,
            1e3 * r.rapier_max_ground_penetration_m
        );
        outln!("ratio ours / rapier: {:.2}", r.ratio);
    }
    Ok(())
}
