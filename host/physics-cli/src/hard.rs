//! `vphys hard`: the hard cases at the defaults, each run with its figures and bounds, as a
//! table (or JSON lines): pass, the figure, the bound, ms per step.

use anyhow::{bail, Result};
use std::time::Instant;
use virtual_physics::measure::hard::{self, HardCase, Outcome};

/// Runs the cases (the table's, and with `variants` their variants too), or only those named,
/// with steps `finer` times finer at the same substep ([`refine`]).
pub fn run(variants: bool, only: &[String], json: bool, finer: u32) -> Result<()> {
    let mut cases = hard::cases();
    if variants || !only.is_empty() {
        cases.extend(hard::variants());
    }
    if !only.is_empty() {
        if let Some(name) = only.iter().find(|n| !cases.iter().any(|c| &c.name == *n)) {
            let names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
            bail!(
                "no hard case named {name:?} (the cases: {})",
                names.join(", ")
            );
        }
        cases.retain(|c| only.contains(&c.name));
    }
    for case in &mut cases {
        refine(case, finer)?;
    }
    if !json {
        println!("| case | pass | figure | value | bound | ms/step |\n|---|---|---|---|---|---|");
    }
    let mut failed = Vec::new();
    for case in &cases {
        let (outcome, ms) = timed(case)?;
        if json {
            print_json(&outcome, ms);
        } else {
            print_rows(&outcome, ms);
        }
        if !outcome.holds() {
            failed.push(outcome.name);
        }
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} hard cases fail: {}",
            failed.len(),
            cases.len(),
            failed.join(", ")
        );
    }
    Ok(())
}

/// Divides `case`'s step and substeps by `n` and multiplies its steps by `n`: the same
/// substep and the same span of time, in steps `n` times shorter.
fn refine(case: &mut HardCase, n: u32) -> Result<()> {
    let scene = &mut case.scene;
    let substeps = scene.solver.substeps;
    if n == 0 || substeps % i64::from(n) != 0 {
        bail!(
            "--finer {n}: case {} takes {substeps} substeps a step, which {n} does not divide",
            case.name
        );
    }
    scene.dt /= f64::from(n);
    scene.solver.substeps = substeps / i64::from(n);
    scene.steps = Some(scene.steps.unwrap_or(600) * u64::from(n));
    Ok(())
}

/// The case's outcome and its wall time per step (ms), measurement included.
fn timed(case: &HardCase) -> Result<(Outcome, f64)> {
    let start = Instant::now();
    let outcome = hard::run(case)?;
    let ms = start.elapsed().as_secs_f64() * 1e3 / outcome.steps.max(1) as f64;
    Ok((outcome, ms))
}

fn print_rows(o: &Outcome, ms: f64) {
    for (k, f) in o.figures.iter().enumerate() {
        let (name, time) = if k == 0 {
            (o.name.as_str(), format!("{ms:.3}"))
        } else {
            ("", String::new())
        };
        let pass = if f.holds() { "yes" } else { "**no**" };
        println!(
            "| {name} | {pass} | {} | {:.3e} {} | {:.3e} | {time} |",
            f.what, f.value, f.unit, f.bound
        );
    }
}

fn print_json(o: &Outcome, ms: f64) {
    let figures: Vec<serde_json::Value> = o
        .figures
        .iter()
        .map(|f| {
            serde_json::json!({
                "what": f.what, "value": f.value, "bound": f.bound, "unit": f.unit,
                "holds": f.holds(),
            })
        })
        .collect();
    let line = serde_json::json!({
        "case": o.name, "holds": o.holds(), "steps": o.steps, "ms_per_step": ms,
        "figures": figures,
    });
    println!("{line}");
}
