//! The report as Markdown (per-problem tables) and a short console summary.

use std::fmt::Write;

use virtual_physics::measure::accuracy::{free_body::StepCost, Problem, Row};
use virtual_physics::pipeline::IntegratorKind;

use super::Report;

fn step_label(dt: f64) -> String {
    format!("1/{:.0}", 1.0 / dt)
}

fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        "diverged".into()
    }
}

fn rows_of(r: &Report, p: Problem) -> impl Iterator<Item = &Row> {
    r.rows.iter().filter(move |row| row.problem == p.name())
}

/// Distinct steps of a problem, largest first.
fn steps(r: &Report, p: Problem) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::new();
    for row in rows_of(r, p) {
        if !v.contains(&row.dt) {
            v.push(row.dt);
        }
    }
    v
}

fn find(r: &Report, p: Problem, k: IntegratorKind, dt: f64) -> Option<&Row> {
    rows_of(r, p).find(|row| row.integrator == k.name() && row.dt == dt)
}

/// The whole report as Markdown.
pub fn markdown(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Accuracy against cost ({} sweep)\n\nRegenerate: `scripts/figures`, or `cargo run -p virtual-physics-cli --release -- accuracy{}` (the machine of the committed run: `machine.txt`).\nEach cell: error / CPU seconds per simulated second (stepping only, this machine).\n",
        if r.quick { "quick" } else { "full" },
        if r.quick { " --quick" } else { "" }
    );
    let _ = writeln!(
        s,
        "## Free-body step cost (256 tumbling boxes, 1 ms, gyroscopic on)\n"
    );
    let _ = writeln!(
        s,
        "| integrator | ns per body step | × semi-implicit Euler |\n|---|---|---|"
    );
    for c in &r.step_cost {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.2} |",
            c.integrator, c.ns_per_body_step, c.ratio_to_symplectic_euler
        );
    }
    for p in Problem::ALL {
        let _ = write!(s, "\n## {}\n\nerror = {}", p.name(), p.error_meaning());
        if p == Problem::Towers {
            let _ = write!(
                s,
                "; scene `{}`, 1/60 s steps, substeps swept (JSON `dt` = the substep)",
                r.towers_scene
            );
        }
        let _ = writeln!(s);
        let kinds = IntegratorKind::ALL;
        let first = if p == Problem::Towers {
            "substeps"
        } else {
            "dt (s)"
        };
        let _ = writeln!(s);
        header(&mut s, first, &kinds);
        for dt in steps(r, p) {
            let label = match find(r, p, kinds[0], dt).and_then(|row| row.substeps) {
                Some(n) => n.to_string(),
                None => step_label(dt),
            };
            let _ = write!(s, "| {label} |");
            for k in kinds {
                match find(r, p, k, dt) {
                    Some(row) => {
                        let _ = write!(s, " {} / {:.2e} |", sci(row.error), row.cpu_s_per_sim_s);
                    }
                    None => {
                        let _ = write!(s, " – |");
                    }
                }
            }
            let _ = writeln!(s);
        }
        if p == Problem::TumblingBox {
            let _ = writeln!(
                s,
                "\nEnergy drift (relative, 10 s) and flips (reference: 3):\n"
            );
            header(&mut s, "dt (s)", &kinds);
            for dt in steps(r, p) {
                let _ = write!(s, "| {} |", step_label(dt));
                for k in kinds {
                    if let Some(row) = find(r, p, k, dt) {
                        let _ = write!(
                            s,
                            " {} / {} |",
                            sci(row.energy_drift.unwrap_or(f64::NAN)),
                            row.flips.unwrap_or(0)
                        );
                    }
                }
                let _ = writeln!(s);
            }
        }
    }
    s
}

/// Console summary: the tumbling box at 1 ms and the step costs.
pub fn summary(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "tumbling box, dt = 1 ms, 10 s (reference: 3 flips)");
    let _ = writeln!(
        s,
        "{:<22}{:>14}{:>16}{:>7}{:>14}{:>16}",
        "integrator", "energy drift", "momentum drift", "flips", "error", "cpu s/sim s"
    );
    for row in rows_of(r, Problem::TumblingBox).filter(|row| (row.dt - 1e-3).abs() < 1e-12) {
        let _ = writeln!(
            s,
            "{:<22}{:>14.3e}{:>16.3e}{:>7}{:>14.3e}{:>16.3e}",
            row.integrator,
            row.energy_drift.unwrap_or(f64::NAN),
            row.momentum_drift.unwrap_or(f64::NAN),
            row.flips.unwrap_or(0),
            row.error,
            row.cpu_s_per_sim_s
        );
    }
    s.push('\n');
    s.push_str(&step_costs(&r.step_cost));
    s
}

/// The free-body step costs as a console table.
pub fn step_costs(costs: &[StepCost]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "free-body step (ns per body step, × semi-implicit Euler)"
    );
    for c in costs {
        let _ = writeln!(
            s,
            "{:<22}{:>10.1}{:>8.2}",
            c.integrator, c.ns_per_body_step, c.ratio_to_symplectic_euler
        );
    }
    s
}

/// A Markdown table header: the first column, then one column per integrator.
fn header(s: &mut String, first: &str, kinds: &[IntegratorKind]) {
    let _ = write!(s, "| {first} |");
    for k in kinds {
        let _ = write!(s, " {k} |");
    }
    let _ = write!(s, "\n|---|");
    for _ in kinds {
        let _ = write!(s, "---|");
    }
    let _ = writeln!(s);
}
