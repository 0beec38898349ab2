//! `vphys peers rapier`: the same scenes in our engine and in rapier3d 0.36 (f32, one
//! thread), back to back in one process, sleeping off and on.
//!
//! The scenes are translated body by body from the same [`SceneFile`] (`rapier_scene`): the
//! same shapes, poses, velocities, masses and friction (0.5 without a material; rapier
//! averages, we take the geometric mean: equal for equal materials), gravity and step.
//! Sleeping off is `can_sleep(false)` on every rapier body and no `sleeping` effect on ours.
//!
//! Rapier runs at its defaults (4 solver iterations, contacts at 30 Hz, 60 Hz against fixed
//! bodies) for the main rows. A second table runs it, sleeping off, with the scene's own solver
//! settings — as many solver iterations as we take substeps, our contact stiffness — so that
//! the two engines are also compared at the same accuracy.

use anyhow::Result;

use crate::run::{load, stats, time_steps_counting_points};
use virtual_physics::dynamics::BodyKind;
use virtual_physics::pipeline::{BodyHandle, World};

/// One row of the comparison.
#[derive(serde::Serialize)]
pub struct Row {
    scene: String,
    sleeping: bool,
    ours_ms: f64,
    rapier_ms: f64,
    ratio: f64,
    ours_max_drift_m: f64,
    rapier_max_drift_m: f64,
}

/// One row of the comparison at the same solver settings (sleeping off).
#[derive(serde::Serialize)]
pub struct MatchedRow {
    scene: String,
    rapier_iterations: usize,
    rapier_contact_hertz: f64,
    ours_ms: f64,
    rapier_ms: f64,
    ratio: f64,
    ours_max_drift_m: f64,
    rapier_max_drift_m: f64,
}

/// Rapier's solver settings for one run.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(feature = "rapier-peer"), allow(dead_code))]
pub(crate) enum RapierSettings {
    /// `IntegrationParameters::default()`.
    Defaults,
    /// `num_solver_iterations = substeps`; contact natural frequency `hertz` (Hz), twice that
    /// against fixed bodies, as ours.
    Matched { substeps: usize, hertz: f64 },
    /// The defaults with `num_solver_iterations` set (Rapier's accuracy knob).
    Iterations(usize),
}

/// The dynamic bodies of a world, whose positions the drift is measured on.
pub(crate) struct DynamicBodies(Vec<BodyHandle>);

impl DynamicBodies {
    /// The dynamic bodies of `w` as it stands.
    pub(crate) fn of(w: &World) -> Self {
        Self(
            w.bodies()
                .filter(|b| b.kind() == BodyKind::Dynamic)
                .map(|b| b.handle())
                .collect(),
        )
    }

    /// Their positions in `w` (m, world).
    pub(crate) fn positions(&self, w: &World) -> Vec<[f64; 3]> {
        self.0
            .iter()
            .filter_map(|&h| w.body(h).map(|b| b.position().into()))
            .collect()
    }
}

/// Largest displacement of a dynamic body from its start (m).
pub(crate) fn max_drift(start: &[[f64; 3]], now: &[[f64; 3]]) -> f64 {
    start
        .iter()
        .zip(now)
        .map(|(a, b)| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// What one run of a scene in rapier3d measured.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RapierRun {
    /// Median ms per step.
    pub ms: f64,
    /// Largest drift of a dynamic body from its start (m).
    pub drift: f64,
    /// Deepest overlap of any contact after any step (m, ≥ 0), read outside the timing.
    pub deepest: f64,
}

/// Steps scene `s` in rapier3d for `steps` steps: median ms per step and the largest drift of
/// a dynamic body (m).
pub(crate) fn rapier_run(
    s: &virtual_physics::scene::SceneFile,
    sleeping: bool,
    steps: u64,
    settings: RapierSettings,
) -> Result<(f64, f64)> {
    rapier_measure(s, sleeping, steps, settings).map(|r| (r.ms, r.drift))
}

/// Steps scene `s` in rapier3d for `steps` steps ([`RapierRun`]).
#[cfg(feature = "rapier-peer")]
pub(crate) fn rapier_measure(
    s: &virtual_physics::scene::SceneFile,
    sleeping: bool,
    steps: u64,
    settings: RapierSettings,
) -> Result<RapierRun> {
    let crate::rapier_scene::RapierScene {
        world: mut w,
        dynamic: handles,
        ..
    } = crate::rapier_scene::rapier_scene(s, sleeping)?;
    match settings {
        RapierSettings::Defaults => {}
        RapierSettings::Matched { substeps, hertz } => {
            let p = &mut w.integration_parameters;
            p.num_solver_iterations = substeps;
            p.contact_softness.natural_frequency = hertz as f32;
            p.static_contact_softness.natural_frequency = 2.0 * hertz as f32;
        }
        RapierSettings::Iterations(n) => w.integration_parameters.num_solver_iterations = n,
    }
    let pos = |w: &rapier3d::prelude::PhysicsWorld| -> Vec<[f64; 3]> {
        handles
            .iter()
            .map(|h| {
                let t = w.bodies[*h].translation();
                [t.x as f64, t.y as f64, t.z as f64]
            })
            .collect()
    };
    let start = pos(&w);
    let mut t = Vec::with_capacity(steps as usize);
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        let t0 = std::time::Instant::now();
        w.step();
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        for pair in w.contact_pairs() {
            if let Some((_, c)) = pair.find_deepest_contact() {
                deepest = deepest.max(-c.dist as f64);
            }
        }
    }
    Ok(RapierRun {
        ms: stats(&t).0,
        drift: max_drift(&start, &pos(&w)),
        deepest,
    })
}

#[cfg(not(feature = "rapier-peer"))]
pub(crate) fn rapier_measure(
    _: &virtual_physics::scene::SceneFile,
    _: bool,
    _: u64,
    _: RapierSettings,
) -> Result<RapierRun> {
    Err(missing())
}

/// The error of a build without the feature (exit status 2).
pub(crate) fn missing() -> anyhow::Error {
    crate::exit::PeerMissing(
        "vphys was built without the rapier peer; rebuild with `cargo run -p \
         virtual-physics-cli --release --features rapier-peer -- peers rapier`"
            .to_string(),
    )
    .into()
}

/// Runs the comparison and prints two tables, or `{"rows": [...], "matched": [...]}`.
pub fn run(scenes: &[String], steps: Option<u64>, json: bool) -> Result<()> {
    if cfg!(not(feature = "rapier-peer")) {
        return Err(missing());
    }
    let mut rows = Vec::new();
    let mut matched = Vec::new();
    for name in scenes {
        for sleeping in [false, true] {
            let s = load(name, Some(sleeping))?;
            let n = steps.or(s.steps).unwrap_or(600);
            let mut w = s.build()?;
            let dynamic = DynamicBodies::of(&w);
            let snap = |w: &World| dynamic.positions(w);
            let start = snap(&w);
            let (t, _, taken) = time_steps_counting_points(&mut w, n, !json)?;
            let ours = stats(&t).0;
            let ours_drift = max_drift(&start, &snap(&w));
            let (rapier, rapier_drift) = rapier_run(&s, sleeping, n, RapierSettings::Defaults)?;
            rows.push(Row {
                scene: name.clone(),
                sleeping,
                ours_ms: ours,
                rapier_ms: rapier,
                ratio: ours / rapier,
                ours_max_drift_m: ours_drift,
                rapier_max_drift_m: rapier_drift,
            });
            if !sleeping {
                // As many iterations as the substeps our steps took (a resting world may
                // take fewer than its settings name).
                let substeps = (taken.round() as usize).max(1);
                let hertz = w.settings().contact_hertz;
                let (rapier, rapier_drift) =
                    rapier_run(&s, false, n, RapierSettings::Matched { substeps, hertz })?;
                matched.push(MatchedRow {
                    scene: name.clone(),
                    rapier_iterations: substeps,
                    rapier_contact_hertz: hertz,
                    ours_ms: ours,
                    rapier_ms: rapier,
                    ratio: ours / rapier,
                    ours_max_drift_m: ours_drift,
                    rapier_max_drift_m: rapier_drift,
                });
            }
        }
    }
    if json {
        outln!(
            "{}",
            serde_json::json!({ "rows": rows, "matched": matched })
        );
    } else {
        outln!("median ms per step, one thread; ours f64, rapier3d 0.36 f32 at its defaults; drift = largest move of a box (m)");
        outln!(
            "{:<14} {:>8} {:>10} {:>10} {:>8} {:>14} {:>16}",
            "scene",
            "sleeping",
            "ours ms",
            "rapier ms",
            "ratio",
            "ours drift m",
            "rapier drift m"
        );
        for r in &rows {
            outln!(
                "{:<14} {:>8} {:>10.3} {:>10.3} {:>8.2} {:>14.4} {:>16.4}",
                r.scene,
                r.sleeping,
                r.ours_ms,
                r.rapier_ms,
                r.ratio,
                r.ours_max_drift_m,
                r.rapier_max_drift_m
            );
        }
        outln!();
        outln!("sleeping off, rapier with the scene's solver settings (iterations = the substeps our steps took on average, our contact Hz)");
        outln!(
            "{:<14} {:>10} {:>8} {:>10} {:>10} {:>8} {:>14} {:>16}",
            "scene",
            "iterations",
            "Hz",
            "ours ms",
            "rapier ms",
            "ratio",
            "ours drift m",
            "rapier drift m"
        );
        for r in &matched {
            outln!(
                "{:<14} {:>10} {:>8.0} {:>10.3} {:>10.3} {:>8.2} {:>14.4} {:>16.4}",
                r.scene,
                r.rapier_iterations,
                r.rapier_contact_hertz,
                r.ours_ms,
                r.rapier_ms,
                r.ratio,
                r.ours_max_drift_m,
                r.rapier_max_drift_m
            );
        }
    }
    Ok(())
}
