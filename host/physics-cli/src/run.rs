//! `vphys run SCENE` (JSON lines per step) and `vphys bench SCENE` (ms per step as JSON).

use std::time::Instant;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use virtual_physics::geometry::V3;
use virtual_physics::pipeline::{Effect, World};
use virtual_physics::scene::{builtin, SceneFile};

/// A scene file path, or a built-in name.
pub fn load(scene: &str, sleeping: Option<bool>) -> Result<SceneFile> {
    let mut s = if std::path::Path::new(scene).exists() {
        SceneFile::from_path(scene)?
    } else {
        builtin::by_name(scene)?
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

/// Largest horizontal (x, y) and vertical displacement of the dynamic bodies from `start` (m).
pub fn drift(world: &World, start: &[V3]) -> (f64, f64) {
    let mut h: f64 = 0.0;
    let mut v: f64 = 0.0;
    for (i, p0) in start.iter().enumerate() {
        if world.bodies.inv_mass[i] > 0.0 {
            let d = world.bodies.pos[i] - p0;
            h = h.max((d.x * d.x + d.y * d.y).sqrt());
            v = v.max(d.z.abs());
        }
    }
    (h, v)
}

/// `vphys run`.
pub fn run(scene: &str, steps: Option<u64>, sleeping: Option<bool>, every: u64) -> Result<()> {
    let s = load(scene, sleeping)?;
    let mut w = s.build()?;
    let n = steps.or(s.steps).unwrap_or(600);
    let start = w.bodies.pos.clone();
    let pb = bar(n);
    for k in 1..=n {
        w.step()?;
        pb.inc(1);
        if k % every.max(1) == 0 || k == n {
            let p = w.bodies.linear_momentum();
            let l = w.bodies.angular_momentum();
            let (dh, dv) = drift(&w, &start);
            let stages: Vec<&str> = w.counters.stages().map(|s| s.name()).collect();
            let c = &w.counters;
            let line = serde_json::json!({
                "step": k, "t": w.time, "energy": w.energy(),
                "momentum": [p.x, p.y, p.z], "angular_momentum": [l.x, l.y, l.z],
                "max_penetration": w.max_penetration(),
                "max_displacement": dh.max(dv), "max_horizontal_displacement": dh,
                "stages": stages, "pairs_tested": c.pairs_tested, "contacts": c.contacts,
                "solver_iterations": c.solver_iterations, "awake": c.awake_bodies,
                "contact_colours": c.contact_colours, "contact_groups": c.contact_groups,
            });
            pb.suspend(|| println!("{line}"));
        }
    }
    pb.finish_and_clear();
    Ok(())
}

/// Times `n` steps of a world; returns ms per step.
pub fn time_steps(w: &mut World, n: u64, show: bool) -> Result<Vec<f64>> {
    let pb = if show { bar(n) } else { ProgressBar::hidden() };
    let mut t = Vec::with_capacity(n as usize);
    for _ in 0..n {
        let t0 = Instant::now();
        w.step()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
        pb.inc(1);
    }
    pb.finish_and_clear();
    Ok(t)
}

/// (median, mean, worst) of samples.
pub fn stats(t: &[f64]) -> (f64, f64, f64) {
    let mut s = t.to_vec();
    s.sort_by(f64::total_cmp);
    let med = s.get(s.len() / 2).copied().unwrap_or(0.0);
    let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
    (med, mean, s.last().copied().unwrap_or(0.0))
}

/// `vphys bench`.
/// Solver settings of `vphys bench` that replace the scene's (the substep sweep in the
/// README is made with them).
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
        w.settings.substeps = n;
    }
    if let Some(hz) = overrides.contact_hertz {
        anyhow::ensure!(
            hz.is_finite() && hz > 0.0,
            "--contact-hertz must be a positive number, got {hz}"
        );
        w.settings.contact_hertz = hz;
    }
    if overrides.rigid {
        w.settings.soft_contacts = false;
    }
    if overrides.scalar_contacts {
        w.settings.batch_contacts = false;
    }
    if let Some(cap) = overrides.hertz_cap {
        anyhow::ensure!(
            cap.is_finite() && cap > 0.0,
            "--hertz-cap must be a positive number, got {cap}"
        );
        w.settings.contact_hertz_cap = cap;
    }
    let n = steps.or(s.steps).unwrap_or(600);
    let start = w.bodies.pos.clone();
    let t = time_steps(&mut w, n, true)?;
    let (med, mean, worst) = stats(&t);
    let (dh, dv) = drift(&w, &start);
    let out = serde_json::json!({
        "scene": s.name, "steps": n, "bodies": w.bodies.len(),
        "sleeping": s.effects.contains(&Effect::Sleeping),
        "median_ms": med, "mean_ms": mean, "worst_ms": worst,
        "max_horizontal_drift_m": dh, "max_vertical_drift_m": dv,
        "max_penetration_m": w.max_penetration(),
        "substeps": w.settings.substeps, "contact_hertz": w.settings.contact_hertz,
        "soft_contacts": w.settings.soft_contacts,
        "batch_contacts": w.settings.batch_contacts,
        "contact_hertz_cap": w.settings.contact_hertz_cap,
    });
    println!("{out}");
    Ok(())
}
