//! `vphys run SCENE` (JSON lines per step) and `vphys bench SCENE` (ms per step as JSON).

use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Result};
use indicatif::{ProgressBar, ProgressStyle};
use virtual_physics::pipeline::{Effect, World};
use virtual_physics::scene::{builtin, SceneFile};

use crate::bodies;

/// The most steps `run` and `bench` take (`bench` keeps one sample per step).
pub const MAX_STEPS: u64 = 10_000_000;

/// The hard case of this name (`vphys hard --variants` lists them).
fn hard_case(name: &str) -> Option<virtual_physics::measure::hard::HardCase> {
    use virtual_physics::measure::hard;
    hard::cases()
        .into_iter()
        .chain(hard::variants())
        .find(|c| c.name == name)
}

/// A scene file path, a built-in name, or a hard case's name. A file of that name wins over a built-in; an
/// argument that names no built-in scene and looks like a path (has a `/` or ends in `.json`)
/// is reported as a missing file.
pub fn load(scene: &str, sleeping: Option<bool>) -> Result<SceneFile> {
    let path = Path::new(scene);
    let mut s = if path.exists() {
        SceneFile::from_path(scene)?
    } else if builtin::NAMES.contains(&scene) {
        builtin::by_name(scene)?
    } else if let Some(case) = hard_case(scene) {
        case.scene
    } else if scene.contains('/')
        || scene.contains(std::path::MAIN_SEPARATOR)
        || path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        bail!("scene file '{scene}' does not exist");
    } else {
        bail!(
            "'{scene}' is neither a scene file nor a built-in scene (built-in: {}; and the hard cases of `vphys hard --variants`)",
            builtin::NAMES.join(", ")
        );
    };
    if let Some(on) = sleeping {
        s.effects.retain(|e| *e != Effect::Sleeping);
        if on {
            s.effects.push(Effect::Sleeping);
        }
    }
    Ok(s)
}

fn bar(n: u64) -> ProgressBar {
    let pb = ProgressBar::new(n);
    pb.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if n < 200 {
        pb.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    pb
}

/// What `vphys run` prints at each printed step.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Output {
    /// One line of world totals and counters.
    Steps,
    /// One line per body (the named bodies, or all when the list is empty).
    Bodies(Vec<String>),
}

/// `vphys run`.
pub fn run(
    scene: &str,
    steps: Option<u64>,
    sleeping: Option<bool>,
    every: u64,
    output: &Output,
) -> Result<()> {
    let s = load(scene, sleeping)?;
    let mut w = s.build()?;
    let n = steps.or(s.steps).unwrap_or(600).min(MAX_STEPS);
    let selected = match output {
        Output::Bodies(names) => Some(bodies::select(&w, names)?),
        Output::Steps => None,
    };
    let start = bodies::positions(&w);
    let pb = bar(n);
    for k in 1..=n {
        w.step()?;
        pb.inc(1);
        if k % every.max(1) == 0 || k == n {
            let printed: Result<()> = pb.suspend(|| {
                match &selected {
                    Some(ids) => {
                        for &i in ids {
                            outln!(
                                "{}",
                                serde_json::to_string(&bodies::line(&w, k, i, &start))?
                            );
                        }
                    }
                    None => outln!("{}", step_line(&w, k, &start)),
                }
                Ok(())
            });
            printed?;
        }
    }
    pb.finish_and_clear();
    Ok(())
}

/// The world totals and counters of one step, as one JSON object.
fn step_line(w: &World, k: u64, start: &[virtual_physics::algebra::Vec3]) -> serde_json::Value {
    let p = w.linear_momentum();
    let l = w.angular_momentum();
    let d = bodies::displacement(w, start);
    let stages: Vec<&str> = w.counters().stages().map(|s| s.name()).collect();
    let c = w.counters();
    serde_json::json!({
        "step": k, "t": w.time(), "energy": w.energy(),
        "momentum": [p.x, p.y, p.z], "angular_momentum": [l.x, l.y, l.z],
        "max_penetration": w.max_penetration(),
        "max_displacement": d.max_3d, "max_horizontal_displacement": d.max_horizontal,
        "max_vertical_displacement": d.max_vertical,
        "stages": stages, "pairs_tested": c.pairs_tested,
        "manifolds_refreshed": c.manifolds_refreshed, "lean_contacts": c.lean_contacts, "contacts": c.contacts,
        "solver_iterations": c.solver_iterations, "awake": c.awake_bodies,
        "contact_colours": c.contact_colours, "contact_groups": c.contact_groups,
        "fine_substeps": c.fine_substeps, "fine_bodies": c.fine_bodies,
    })
}

/// Times `n` steps of a world; returns ms per step.
pub fn time_steps(w: &mut World, n: u64, show: bool) -> Result<Vec<f64>> {
    let pb = if show { bar(n) } else { ProgressBar::hidden() };
    let mut t = Vec::with_capacity(n.min(MAX_STEPS) as usize);
    for _ in 0..n {
        let t0 = Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        pb.inc(1);
    }
    pb.finish_and_clear();
    Ok(t)
}

/// Times `n` steps of a world as [`time_steps`] does; also returns the mean number of contact
/// points per step and of substeps the steps took (the step counters' `contacts` and
/// `substeps`, read after each step, outside the timing; a resting world may take fewer
/// substeps than its settings name).
pub fn time_steps_counting_points(
    w: &mut World,
    n: u64,
    show: bool,
) -> Result<(Vec<f64>, f64, f64)> {
    let pb = if show { bar(n) } else { ProgressBar::hidden() };
    let mut t = Vec::with_capacity(n.min(MAX_STEPS) as usize);
    let (mut points, mut substeps) = (0.0, 0.0);
    for _ in 0..n {
        let t0 = Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        points += w.counters().contacts as f64;
        substeps += w.counters().substeps as f64;
        pb.inc(1);
    }
    pb.finish_and_clear();
    let steps = n.max(1) as f64;
    Ok((t, points / steps, substeps / steps))
}

/// (median, mean, worst) of samples.
pub fn stats(t: &[f64]) -> (f64, f64, f64) {
    let mut s = t.to_vec();
    s.sort_by(f64::total_cmp);
    let med = s.get(s.len() / 2).copied().unwrap_or(0.0);
    let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
    (med, mean, s.last().copied().unwrap_or(0.0))
}

/// Solver settings of `vphys bench` that replace the scene's (the substep sweep in
/// `docs/physics/scenes-contacts-stacking.md` is made with them).
#[derive(Debug, Clone, Copy, Default)]
pub struct SolverOverrides {
    /// Substeps per step.
    pub substeps: Option<usize>,
    /// Contact stiffness (Hz).
    pub contact_hertz: Option<f64>,
    /// Rigid contacts (position bias) instead of soft ones.
    pub rigid: bool,
    /// Contacts solved one by one (no colouring, no four-lane groups).
    pub scalar_contacts: bool,
    /// Cap on contact stiffness as a fraction of the substep rate.
    pub hertz_cap: Option<f64>,
    /// Relax only after the last substep.
    pub relax_last_only: bool,
    /// The scene's substeps in every step, also at rest.
    pub fixed_substeps: bool,
    /// The contacts' own warm start in every substep (no per-body replay).
    pub contact_warm_start: bool,
    /// Contacts settle at their loads' overlap (no sink hold).
    pub no_sink_hold: bool,
    /// The broad phase's grid built every step.
    pub rebuild_broad_phase: bool,
    /// Every contact constraint kept whole at rest.
    pub keep_contact_constraints: bool,
}

/// `vphys bench`: ms per step and the drift of the boxes, as one JSON object.
pub fn bench(
    scene: &str,
    steps: Option<u64>,
    sleeping: Option<bool>,
    overrides: &SolverOverrides,
) -> Result<()> {
    let s = load(scene, sleeping)?;
    let mut w = s.build()?;
    if let Some(n) = overrides.substeps {
        w.settings_mut().substeps = n;
    }
    if let Some(hz) = overrides.contact_hertz {
        anyhow::ensure!(
            hz.is_finite() && hz > 0.0,
            "--contact-hertz must be a positive number, got {hz}"
        );
        w.settings_mut().contact_hertz = hz;
    }
    if overrides.rigid {
        w.variants_mut().soft_contacts = false;
    }
    if overrides.scalar_contacts {
        w.variants_mut().batch_contacts = false;
    }
    if overrides.relax_last_only {
        w.variants_mut().relax_each_substep = false;
    }
    if overrides.fixed_substeps {
        w.variants_mut().fewer_substeps_at_rest = false;
    }
    if overrides.contact_warm_start {
        w.variants_mut().replay_warm_start = false;
    }
    if overrides.no_sink_hold {
        w.variants_mut().hold_sink = false;
    }
    if overrides.rebuild_broad_phase {
        w.variants_mut().keep_broad_phase_pairs = false;
    }
    if overrides.keep_contact_constraints {
        w.variants_mut().lean_resting_contacts = false;
    }
    if let Some(cap) = overrides.hertz_cap {
        anyhow::ensure!(
            cap.is_finite() && cap > 0.0,
            "--hertz-cap must be a positive number, got {cap}"
        );
        w.variants_mut().contact_hertz_cap = cap;
    }
    let n = steps.or(s.steps).unwrap_or(600).min(MAX_STEPS);
    let start = bodies::positions(&w);
    let (t, points, taken) = time_steps_counting_points(&mut w, n, true)?;
    let (med, mean, worst) = stats(&t);
    let d = bodies::displacement(&w, &start);
    let substeps = w.settings().substeps;
    // The whole step's median time shared over every contact point of every substep taken.
    let ns_per_point_substep = if points > 0.0 && taken > 0.0 {
        serde_json::json!(med * 1e6 / (points * taken))
    } else {
        serde_json::Value::Null
    };
    let out = serde_json::json!({
        "scene": s.name, "steps": n, "bodies": w.body_count(),
        "sleeping": s.effects.contains(&Effect::Sleeping),
        "median_ms": med, "mean_ms": mean, "worst_ms": worst,
        "max_drift_m": d.max_3d,
        "max_horizontal_drift_m": d.max_horizontal, "max_vertical_drift_m": d.max_vertical,
        "max_penetration_m": w.max_penetration(),
        "mean_contact_points": points, "ns_per_contact_point_substep": ns_per_point_substep,
        "substeps": substeps, "mean_substeps_taken": taken,
        "fewer_substeps_at_rest": w.variants().fewer_substeps_at_rest,
        "replay_warm_start": w.variants().replay_warm_start,
        "hold_sink": w.variants().hold_sink,
        "keep_broad_phase_pairs": w.variants().keep_broad_phase_pairs,
        "lean_resting_contacts": w.variants().lean_resting_contacts,
        "contact_hertz": w.settings().contact_hertz,
        "soft_contacts": w.variants().soft_contacts,
        "batch_contacts": w.variants().batch_contacts,
        "contact_hertz_cap": w.variants().contact_hertz_cap,
        "relax_each_substep": w.variants().relax_each_substep,
    });
    outln!("{out}");
    Ok(())
}
