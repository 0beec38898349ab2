//! `vphys accuracy`: every reference problem × every integrator × a sweep of steps; writes the
//! table (Markdown and JSON) and the error-vs-cost chart (PNG and SVG).

mod chart;
mod check;
mod table;

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use virtual_physics::measure::accuracy::{
    articulated, contact, free_body, free_body::StepCost, Problem, Row, QUICK_SWEEP, SWEEP,
};
use virtual_physics::pipeline::IntegratorKind;

/// Solver substeps swept on the towers (full and quick).
const TOWER_SUBSTEPS: [usize; 5] = [2, 4, 8, 12, 16];
const TOWER_SUBSTEPS_QUICK: [usize; 3] = [4, 8, 12];

/// Everything the report holds.
#[derive(serde::Serialize)]
pub struct Report {
    /// One row per run.
    pub rows: Vec<Row>,
    /// Cost of one free-body step per integrator.
    pub step_cost: Vec<StepCost>,
    /// Whether this was the quick sweep.
    pub quick: bool,
    /// The towers scene.
    pub towers_scene: String,
}

fn default_out(quick: bool) -> PathBuf {
    if quick {
        std::env::temp_dir().join("vphys-accuracy-quick")
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../physics/accuracy")
    }
}

/// `vphys accuracy`: measures, writes the report (to `out`, or the default folder; with
/// `check` only when `out` is given) and, with `check`, compares it with the committed report
/// in that folder, failing when a row differs.
pub fn run(
    quick: bool,
    json: bool,
    out: Option<PathBuf>,
    check: Option<PathBuf>,
    peers: bool,
) -> Result<()> {
    let out = match (&check, out) {
        (_, Some(o)) => Some(o),
        (None, None) => Some(default_out(quick)),
        (Some(_), None) => None,
    };
    let report = measure(quick)?;
    if let Some(out) = &out {
        write(&report, out)?;
    }
    if json {
        outln!("{}", serde_json::to_string(&report)?);
    } else {
        outln!("{}", table::summary(&report));
        if let Some(out) = &out {
            outln!("wrote {}/accuracy.{{md,json,png,svg}}", out.display());
        }
    }
    if peers {
        peer_panels(json, out.as_deref())?;
    }
    if let Some(dir) = check {
        let fresh = serde_json::to_value(&report)?;
        let outcome = check::check_dir(&fresh, &dir)?;
        out!("{}", outcome.text);
        if outcome.differing > 0 {
            anyhow::bail!(
                "{} of {} rows differ from the committed report in {}: regenerate it with \
                 scripts/figures if the change is intended",
                outcome.differing,
                outcome.compared,
                dir.display()
            );
        }
    }
    Ok(())
}

/// The steps each setting of the front panel runs from the scene's start.
const FRONT_STEPS: u64 = 300;

/// The report's peer panels, drawn into `out` when given: the stacking front (ours, and
/// rapier3d when built in) and the tumbling box beside whichever peers are present.
fn peer_panels(json: bool, out: Option<&Path>) -> Result<()> {
    let scenes: Vec<String> = crate::front::SCENES.iter().map(|s| s.to_string()).collect();
    let points = crate::front::measure(&scenes, Some(FRONT_STEPS), cfg!(feature = "rapier-peer"))?;
    let front = out.map(|o| o.join("front.svg"));
    crate::front::report(&scenes, &points, json, front.as_deref())?;
    let tumbling = out.map(|o| o.join("tumbling-peers.svg"));
    crate::tumbling_peers::run(
        "python3",
        Path::new(crate::tumbling_peers::MUJOCO_SCRIPT),
        json,
        tumbling.as_deref(),
    )?;
    if !json {
        if let Some(out) = out {
            outln!(
                "wrote {}/front.{{png,svg}} and tumbling-peers.{{png,svg}}",
                out.display()
            );
        }
    }
    Ok(())
}

/// Writes the table, the JSON and the chart into `out`.
fn write(report: &Report, out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let text = serde_json::to_string_pretty(report)?;
    write_atomic(&out.join("accuracy.json"), text.as_bytes())?;
    write_atomic(&out.join("accuracy.md"), table::markdown(report).as_bytes())?;
    chart::draw(report, &out.join("accuracy.png"), &out.join("accuracy.svg"))
}

/// `vphys accuracy --step-cost`: the free-body step of each integrator, timed alone.
pub fn step_cost(json: bool) -> Result<()> {
    let costs = free_body::step_cost(256, 400, 15);
    if json {
        outln!("{}", serde_json::json!({ "step_cost": costs }));
    } else {
        outln!("{}", table::step_costs(&costs));
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename, so a
/// report is either the old one or the new one whole.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut file = tempfile::Builder::new()
        .prefix(".")
        .suffix(".tmp")
        .tempfile_in(dir)
        .with_context(|| format!("creating a temporary file in {}", dir.display()))?;
    file.write_all(bytes)
        .with_context(|| format!("writing {}", file.path().display()))?;
    file.persist(path)
        .with_context(|| format!("renaming to {}", path.display()))?;
    Ok(())
}

fn measure(quick: bool) -> Result<Report> {
    let sweep: &[f64] = if quick { &QUICK_SWEEP } else { &SWEEP };
    let substeps: &[usize] = if quick {
        &TOWER_SUBSTEPS_QUICK
    } else {
        &TOWER_SUBSTEPS
    };
    let tower_steps = if quick { 300 } else { 600 };
    let kinds = IntegratorKind::ALL;
    let sweep_problems = [
        Problem::TumblingBox,
        Problem::HeavyTop,
        Problem::DoublePendulum,
        Problem::Chain10,
        Problem::BallOnCloth,
    ];
    let total = (sweep_problems.len() * sweep.len() + substeps.len()) * kinds.len() + 4;
    let pb = ProgressBar::new(total as u64);
    pb.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs {elapsed_precise} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut rows = Vec::new();

    pb.set_message("tumbling box: reference (RKMK4, 1/64000 s)");
    let tumbling_ref = free_body::reference()?;
    pb.inc(1);
    for p in sweep_problems {
        let reference = match p {
            Problem::DoublePendulum | Problem::Chain10 => {
                pb.set_message(format!("{}: reference (RKMK4, 1/64000 s)", p.name()));
                let r = articulated::reference(p)?;
                pb.inc(1);
                r
            }
            _ => None,
        };
        for &dt in sweep {
            for kind in kinds {
                pb.set_message(format!("{} {} dt=1/{:.0}", p.name(), kind, 1.0 / dt));
                let row = match p {
                    Problem::TumblingBox => free_body::row(kind, dt, &tumbling_ref)?,
                    Problem::HeavyTop | Problem::DoublePendulum | Problem::Chain10 => {
                        articulated::row(p, kind, dt, reference.as_ref())?
                    }
                    _ => contact::ball_row(kind, dt)?,
                };
                rows.push(row);
                pb.inc(1);
            }
        }
    }
    for &n in substeps {
        for kind in kinds {
            pb.set_message(format!("towers {kind} substeps={n}"));
            rows.push(contact::towers_row(kind, n, tower_steps, quick)?);
            pb.inc(1);
        }
    }
    pb.set_message("free-body step cost");
    let step_cost = free_body::step_cost(256, if quick { 100 } else { 400 }, 9);
    pb.inc(1);
    pb.finish_and_clear();
    Ok(Report {
        rows,
        step_cost,
        quick,
        towers_scene: contact::towers_scene(quick).name,
    })
}
