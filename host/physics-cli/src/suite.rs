//! `vphys peers rapier --suite`: the committed benchmark suite, ours against rapier3d 0.36 at
//! both engines' defaults, sleeping off.
//!
//! The suite holds the two resting stacks (built in) and the scenes in motion of
//! `host/physics/scenes/suite/` (written by its `generate.py`): rain, heaps in a bin, a heavy
//! ball wrecking a pyramid, many small pyramids, a pile of bodies thrown spinning into a bin,
//! and a pile of articulated chains (against Rapier's multibodies). Each scene runs `repeats` times, ours and
//! rapier interleaved, and each engine keeps its best median, so that a load on the shared
//! machine that slows one run does not decide the ratio.

use anyhow::Result;

use crate::rapier_peer::{max_drift, missing, rapier_measure, DynamicBodies, RapierSettings};
use crate::run::{load, stats};
use virtual_physics::pipeline::World;

/// The suite's scenes: built-in names, and files under `host/physics/scenes/suite/`.
pub const SUITE: [&str; 11] = [
    "towers-1120",
    "pyramid-1240",
    "rain-1000",
    "rain-400",
    "heap-1000",
    "heap-300",
    "wreck-210",
    "wreck-120",
    "pyramids-20x10",
    "tumble-500",
    "chains-24",
];

/// The scene argument `load` takes for a suite name: a built-in stays a name, the others
/// become the committed file's path.
fn scene_path(name: &str) -> String {
    if virtual_physics::scene::builtin::NAMES.contains(&name) {
        name.to_string()
    } else {
        format!(
            "{}/../physics/scenes/suite/{name}.json",
            env!("CARGO_MANIFEST_DIR")
        )
    }
}

/// One scene's row.
#[derive(serde::Serialize)]
struct SuiteRow {
    scene: String,
    steps: u64,
    ours_ms: f64,
    rapier_ms: f64,
    ratio: f64,
    /// Our median step over every contact point of every substep taken (ns).
    ours_ns_per_point_substep: f64,
    mean_contact_points: f64,
    mean_substeps: f64,
    ours_deepest_m: f64,
    rapier_deepest_m: f64,
    ours_max_drift_m: f64,
    rapier_max_drift_m: f64,
}

/// What one of our runs measured.
struct OurRun {
    ms: f64,
    points: f64,
    substeps: f64,
    deepest: f64,
    drift: f64,
}

/// Steps `w` for `n` steps: the median step, the mean contact points and substeps per step,
/// the deepest overlap after any step (read outside the timing) and the largest drift.
fn our_run(mut w: World, n: u64) -> Result<OurRun> {
    let dynamic = DynamicBodies::of(&w);
    let snap = |w: &World| dynamic.positions(w);
    let start = snap(&w);
    let mut t = Vec::with_capacity(n as usize);
    let (mut points, mut substeps, mut deepest) = (0.0, 0.0, 0.0f64);
    for _ in 0..n {
        let t0 = std::time::Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        points += w.counters().contacts as f64;
        substeps += w.counters().substeps as f64;
        deepest = deepest.max(w.max_penetration());
    }
    let steps = n.max(1) as f64;
    Ok(OurRun {
        ms: stats(&t).0,
        points: points / steps,
        substeps: substeps / steps,
        deepest,
        drift: max_drift(&start, &snap(&w)),
    })
}

/// Runs the suite and prints its table, or `{"rows": [...]}`.
pub fn run(steps: Option<u64>, repeats: usize, json: bool) -> Result<()> {
    if cfg!(not(feature = "rapier-peer")) {
        return Err(missing());
    }
    let repeats = repeats.max(1);
    let mut rows = Vec::new();
    for name in SUITE {
        let s = load(&scene_path(name), Some(false))?;
        let n = steps.or(s.steps).unwrap_or(600);
        let mut best: Option<OurRun> = None;
        let mut rapier_best = None;
        for _ in 0..repeats {
            let ours = our_run(s.build()?, n)?;
            if best.as_ref().is_none_or(|b| ours.ms < b.ms) {
                best = Some(ours);
            }
            let r = rapier_measure(&s, false, n, RapierSettings::Defaults)?;
            if rapier_best.is_none_or(|b: crate::rapier_peer::RapierRun| r.ms < b.ms) {
                rapier_best = Some(r);
            }
        }
        let (ours, rapier) = (best.expect("one run"), rapier_best.expect("one run"));
        let per_point = if ours.points > 0.0 && ours.substeps > 0.0 {
            ours.ms * 1e6 / (ours.points * ours.substeps)
        } else {
            0.0
        };
        rows.push(SuiteRow {
            scene: name.to_string(),
            steps: n,
            ours_ms: ours.ms,
            rapier_ms: rapier.ms,
            ratio: ours.ms / rapier.ms,
            ours_ns_per_point_substep: per_point,
            mean_contact_points: ours.points,
            mean_substeps: ours.substeps,
            ours_deepest_m: ours.deepest,
            rapier_deepest_m: rapier.deepest,
            ours_max_drift_m: ours.drift,
            rapier_max_drift_m: rapier.drift,
        });
    }
    if json {
        outln!(
            "{}",
            serde_json::json!({ "repeats": repeats, "rows": rows })
        );
        return Ok(());
    }
    outln!(
        "best median ms per step of {repeats} interleaved runs, one thread, sleeping off; ours f64 at its \
         defaults, rapier3d 0.36 f32 at its defaults; deepest = deepest overlap after any step (m)"
    );
    outln!(
        "{:<15} {:>6} {:>9} {:>10} {:>6} {:>9} {:>8} {:>6} {:>10} {:>11}",
        "scene",
        "steps",
        "ours ms",
        "rapier ms",
        "ratio",
        "ns/pt/ss",
        "points",
        "subst",
        "ours deep",
        "rapier deep"
    );
    for r in &rows {
        outln!(
            "{:<15} {:>6} {:>9.3} {:>10.3} {:>6.2} {:>9.1} {:>8.0} {:>6.1} {:>10.4} {:>11.4}",
            r.scene,
            r.steps,
            r.ours_ms,
            r.rapier_ms,
            r.ratio,
            r.ours_ns_per_point_substep,
            r.mean_contact_points,
            r.mean_substeps,
            r.ours_deepest_m,
            r.rapier_deepest_m
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_suite_scene_is_built_in_or_committed() {
        for name in SUITE {
            let path = scene_path(name);
            assert!(
                virtual_physics::scene::builtin::NAMES.contains(&path.as_str())
                    || std::path::Path::new(&path).is_file(),
                "{name}: no built-in scene and no file {path}"
            );
        }
    }
}
